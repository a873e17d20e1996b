"""The simulated puppet's arm: a 7-joint chain of point masses under gravity, servos and a hand.

Pure: time is an argument, no clock, no I/O, no rospy. The arm is a chain of point masses, the 2020
puppet's assemblies (masses and lengths below). At zero angles joint 0 turns about the vertical and
carries a vertical column, and the arm points horizontally forward; rotary joints 1, 3, 5 pitch,
twist joints 0, 2, 4, 6 turn about their link. Each joint is driven by gravity, its servo (stall
torque proportional to the voltage, following it with a 10 ms lag, back-EMF braking while the
drivers are enabled), servo friction (Coulomb and viscous), and the operator's hand: a stiff
spring-damper toward the hand pose that moves at a hand-like speed and is stronger than the servos.
Until the first hand input the hand holds REST_POSE_RAD. Angles here are mechanical; the firmware's
encoders (robopuppet.puppet_sim.puppet_model) turn them into reported angles. hand_torque_nm
observes what the hand exerts (what the nurse feels in feel mode); it changes nothing in the
motion.

The hand grips a joint for HAND_GRIP_S after each input for it (the operator moving it, or
holding on: a test that keeps sending the pose); then it rests on the puppet. A resting hand
still carries the puppet's weight, but gives way to the motors as a nurse's hand does in a
playback into the puppet (she keeps a hand on it and lets the motors lead): once the motor of
a joint drives at more than HAND_YIELD_V, the hand goes along with that joint, pushing nothing,
until the drivers stop (limp: it holds the puppet where it is) or the operator gives that
joint a new target (the same target again, as the GUI sends every slider when one moves, leaves
it with the puppet). HAND_YIELD_V is above feel mode's default 2 V voltage limit (in feel the
nurse leads: her hand does not give way to the gentle pull) and well below the 7.2 V that a
motor reaches against a hand that holds on.
"""
import math

import numpy as np

from robopuppet import settings

NOMINAL_VOLTAGE_V = 7.2
GRAVITY_MPS2 = 9.81

# Rest pose of the arm when nobody has touched it: on its stand, elbow bent. The quadrature
# joints are away from their index marks, so they start Uncalibrated.
REST_POSE_RAD = (0.3, 0.5, -0.25, 0.9, 0.2, 0.4, -0.15)
REST_GRIPPERS = (0.0, 0.0, 0.0, 1.0)  # gripper 3 is the end-piece button: ~1 when released

# The 2020 puppet's assemblies: (mass kg, length m). Link J is the assembly that joint J moves.
_TWIST, _ROTARY, _SMALL_TWIST, _GRIPPER = (0.16, 0.0957), (0.14, 0.0475), (0.11, 0.083), \
    (0.026, 0.065)
LINKS = (_TWIST, _ROTARY, _TWIST, _ROTARY, _SMALL_TWIST, _ROTARY, _GRIPPER)
_Z, _Y, _X = np.array([0., 0., 1.]), np.array([0., 1., 0.]), np.array([1., 0., 0.])
JOINT_AXES = (_Z, _Y, _X, _Y, _X, _Y, _X)          # in the frame of the previous link
LINK_DIRECTIONS = (_Z, _X, _X, _X, _X, _X, _X)     # link J's direction at zero angles
# Servos: 25 kg*cm (2.45 N*m) for joints 0-5, a 9 g servo (1 kg*cm) for joint 6.
STALL_TORQUE_NM = np.array([2.45] * 6 + [0.098])
NO_LOAD_SPEED_RADPS = np.array([7.0] * 7)
ROTOR_INERTIA_KGM2 = np.array([0.004] * 6 + [0.0004])   # reflected through the gearing
COULOMB_FRICTION_NM = np.array([0.06] * 6 + [0.006])
VISCOUS_FRICTION_NMS = np.array([0.02] * 6 + [0.002])
MOTOR_LAG_S = 0.01
HAND_STIFFNESS_NM_PER_RAD = 30.0
HAND_DAMPING_NMS = 1.0
HAND_MAX_TORQUE_NM = 8.0
HAND_SPEED_RADPS = 3.0
HAND_GRIP_S = 1.0     # after an input, the hand grips this long; then it rests on the puppet
HAND_YIELD_V = 3.6    # a resting hand gives way to a motor driving harder than this (1.2 N m)


def wrap(angle_rad):
    """Return angle_rad wrapped to [-pi, pi)."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi


def _rotation(axis, angle_rad):
    """Return the 3x3 rotation matrix about a unit axis (Rodrigues)."""
    x, y, z = axis
    k = np.array([[0., -z, y], [z, 0., -x], [-y, x, 0.]])
    return np.eye(3) + math.sin(angle_rad) * k + (1.0 - math.cos(angle_rad)) * k.dot(k)


class ArmPhysics:
    """The puppet's seven joints: mechanical angles, speeds, torques and the operator's hand."""

    def __init__(self, pose_rad=REST_POSE_RAD):
        n = settings.NUM_JOINTS
        self.angle_rad = np.array(pose_rad, dtype=float)
        self.speed_radps = np.zeros(n)
        self.motor_voltage_v = np.zeros(n)   # lagged voltage at the motor terminals
        self.hand_goal_rad = np.array(pose_rad, dtype=float)
        self.hand_rad = np.array(pose_rad, dtype=float)
        self.hand_engaged = np.ones(n, dtype=bool)
        self.hand_still_s = np.full(n, HAND_GRIP_S)   # since the last input: resting at first
        self.hand_yielding = np.zeros(n, dtype=bool)  # going along with the motors
        self._hand_input_rad = list(pose_rad)         # the last target given per joint
        self.hand_torque_nm = np.zeros(n)  # the hand's torque on each joint at the last step
        self.gravity_nm = np.zeros(n)
        self.inertia_kgm2 = ROTOR_INERTIA_KGM2.copy()
        self.update_loads()

    def set_hand(self, joint, angle_rad):
        """Move the hand on a joint toward a mechanical angle (rad); None lets go of it.

        The same target again for a joint where the hand goes along with the motors changes
        nothing (the GUI sends every slider when one moves): only a new one grips it again."""
        if angle_rad is not None and self.hand_yielding[joint] and (
                angle_rad == self._hand_input_rad[joint]):
            return
        self._hand_input_rad[joint] = angle_rad
        self.hand_yielding[joint] = False
        if angle_rad is None:
            self.hand_engaged[joint] = False
            return
        if not self.hand_engaged[joint]:
            self.hand_rad[joint] = self.angle_rad[joint]
        self.hand_engaged[joint] = True
        self.hand_goal_rad[joint] = angle_rad
        self.hand_still_s[joint] = 0.0

    def update_hand(self, dt_s, drivers_enabled):
        """Let the hand rest dt_s longer; where it rests and a motor drives at more than
        HAND_YIELD_V it gives way: until limp or a new target it goes along with that joint,
        pushing nothing (call once per control tick, before its steps)."""
        self.hand_still_s += dt_s
        if drivers_enabled:
            self.hand_yielding |= (self.hand_engaged & (self.hand_still_s >= HAND_GRIP_S)
                                   & (np.abs(self.motor_voltage_v) > HAND_YIELD_V))
        else:
            self.hand_yielding[:] = False
        self.hand_rad[self.hand_yielding] = self.angle_rad[self.hand_yielding]
        self.hand_goal_rad[self.hand_yielding] = self.angle_rad[self.hand_yielding]

    def update_loads(self):
        """Recompute gravity torque and effective inertia of each joint for the current pose."""
        origin = np.zeros(3)
        frame = np.eye(3)
        origins, axes, centres, masses = [], [], [], []
        for joint, ((mass, length), axis, direction) in enumerate(
                zip(LINKS, JOINT_AXES, LINK_DIRECTIONS)):
            frame = frame.dot(_rotation(axis, self.angle_rad[joint]))
            origins.append(origin)
            axes.append(frame.dot(axis))
            tip = origin + frame.dot(direction) * length
            centres.append((origin + tip) / 2.0)
            masses.append(mass)
            origin = tip
        weight = np.array([0., 0., -GRAVITY_MPS2])
        for joint in settings.JOINTS:
            arms = np.array(centres[joint:]) - origins[joint]
            mass = np.array(masses[joint:])
            axis = axes[joint]
            torques = np.cross(arms, weight) * mass[:, None]
            self.gravity_nm[joint] = torques.sum(axis=0).dot(axis)
            radial = arms - np.outer(arms.dot(axis), axis)
            self.inertia_kgm2[joint] = (ROTOR_INERTIA_KGM2[joint]
                                        + (mass * (radial ** 2).sum(axis=1)).sum())

    def step(self, dt_s, applied_voltage_v, drivers_enabled):
        """Advance the arm by dt_s with the given motor voltages; return the previous angles."""
        previous = self.angle_rad.copy()
        self.motor_voltage_v += (applied_voltage_v - self.motor_voltage_v) * min(
            1.0, dt_s / MOTOR_LAG_S)
        speed = self.speed_radps
        torque = self.gravity_nm - VISCOUS_FRICTION_NMS * speed
        if drivers_enabled:
            torque += STALL_TORQUE_NM * (self.motor_voltage_v / NOMINAL_VOLTAGE_V
                                         - speed / NO_LOAD_SPEED_RADPS)
        step = HAND_SPEED_RADPS * dt_s
        self.hand_rad += np.clip(self.hand_goal_rad - self.hand_rad, -step, step)
        hand = np.clip(HAND_STIFFNESS_NM_PER_RAD * (self.hand_rad - self.angle_rad)
                       - HAND_DAMPING_NMS * speed, -HAND_MAX_TORQUE_NM, HAND_MAX_TORQUE_NM)
        hand[~self.hand_engaged | self.hand_yielding] = 0.0
        self.hand_torque_nm = hand
        torque += self.hand_torque_nm
        moving = np.abs(speed) > 1e-6
        stuck = ~moving & (np.abs(torque) <= COULOMB_FRICTION_NM)
        direction = np.where(moving, np.sign(speed), np.sign(torque))
        new_speed = speed + dt_s * (torque - COULOMB_FRICTION_NM * direction) / self.inertia_kgm2
        # Kinetic friction stops a joint; it does not reverse it.
        new_speed = np.where(moving & (np.sign(new_speed) != np.sign(speed)), 0.0, new_speed)
        self.speed_radps = np.where(stuck, 0.0, new_speed)
        self.angle_rad = self.angle_rad + self.speed_radps * dt_s
        return previous
