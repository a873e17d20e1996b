"""A simulated puppet: the microcontroller's firmware and a 7-joint arm under gravity.

Pure: time is an argument, no clock, no I/O, no rospy. PuppetFirmware behaves like the firmware
of DESIGN section 3 and the seed report: heartbeat at 1 Hz, state sets at the state rate, and a
50 Hz control loop that reads the encoders, clamps each angle to [angle_min, angle_max], limits
its rate to [velocity_min, velocity_max] and, in hold mode, runs one PID per joint on the wrapped
angle error clamped to [voltage_min, voltage_max].

The arm (ArmPhysics) is a chain of point masses from the seed's Table 2. At zero angles joint 0
turns about the vertical and carries a vertical column, and the arm points horizontally forward;
rotary joints 1, 3, 5 pitch, twist joints 0, 2, 4, 6 turn about their link. Each joint is driven
by gravity, its servo (stall torque proportional to the voltage, following it with a 10 ms lag,
back-EMF braking while the drivers are enabled), servo friction (Coulomb and viscous), and the
operator's hand: a stiff spring-damper toward the hand pose that moves at a hand-like speed and
is stronger than the servos. Until the first hand input the hand holds REST_POSE.

Encoders: joints 1, 3, 5 are absolute; joints 0, 2, 4, 6 report Uncalibrated (angles counted
from power-on) until they first pass their index mark at mechanical angle 0 (any multiple of
2 pi), then Working. A working joint reports wrap(home_angle + sign_angle * mechanical angle).
"""
import math

import numpy as np

from robopuppet import codec, settings

CONTROL_RATE_HZ = 50.0
HEARTBEAT_RATE_HZ = 1.0
PHYSICS_STEPS_PER_TICK = 10
QUAD_JOINTS = (0, 2, 4, 6)
NOMINAL_VOLTAGE_V = 7.2
GRAVITY_MPS2 = 9.81
INDEX_HALF_WIDTH_RAD = 0.005  # the index pulse is about 0.6 degrees wide

# Rest pose of the arm when nobody has touched it: on its stand, elbow bent. The quadrature
# joints are away from their index marks, so they start Uncalibrated.
REST_POSE_RAD = (0.3, 0.5, -0.25, 0.9, 0.2, 0.4, -0.15)
REST_GRIPPERS = (0.0, 0.0, 0.0, 1.0)  # gripper 3 is the end-piece button: ~1 when released

# Seed Table 2 assemblies: (mass kg, length m). Link J is the assembly that joint J moves.
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
        self.gravity_nm = np.zeros(n)
        self.inertia_kgm2 = ROTOR_INERTIA_KGM2.copy()
        self.update_loads()

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
        torque += np.where(self.hand_engaged, hand, 0.0)
        moving = np.abs(speed) > 1e-6
        stuck = ~moving & (np.abs(torque) <= COULOMB_FRICTION_NM)
        direction = np.where(moving, np.sign(speed), np.sign(torque))
        new_speed = speed + dt_s * (torque - COULOMB_FRICTION_NM * direction) / self.inertia_kgm2
        # Kinetic friction stops a joint; it does not reverse it.
        new_speed = np.where(moving & (np.sign(new_speed) != np.sign(speed)), 0.0, new_speed)
        self.speed_radps = np.where(stuck, 0.0, new_speed)
        self.angle_rad = self.angle_rad + self.speed_radps * dt_s
        return previous


class PuppetFirmware:
    """The puppet's microcontroller and arm; feed it host messages and the time.

    Use: handle(message) for each decoded host frame, advance(now_s) to run the control loop up
    to now and collect the frames due (heartbeat, state sets), and the set_* methods for the
    operator's hand, buttons and grippers.
    """

    def __init__(self, state_rate_hz=10.0, pose_rad=REST_POSE_RAD):
        if not state_rate_hz > 0.0:
            raise ValueError('state rate must be positive, got %r' % (state_rate_hz,))
        self.state_period_s = 1.0 / state_rate_hz
        self.arm = ArmPhysics(pose_rad)
        self.config = {j: dict(settings.DEFAULTS) for j in settings.JOINTS}
        self.opmode = codec.LIMP
        self.calibrated = [j not in QUAD_JOINTS for j in settings.JOINTS]
        self.power_on_rad = list(pose_rad)
        self.angle_rad = [self._encoder(j) for j in settings.JOINTS]
        self.setpoint_rad = list(self.angle_rad)
        self.voltage_v = [0.0] * settings.NUM_JOINTS
        self._integral = [0.0] * settings.NUM_JOINTS
        self._last_error = [None] * settings.NUM_JOINTS
        self.button = 0
        self.grippers = list(REST_GRIPPERS)
        self._time_s = None
        self._next_control_s = self._next_state_s = self._next_heartbeat_s = None

    # Operator -------------------------------------------------------------------------------
    def set_hand(self, positions_rad):
        """Move the hand toward {joint: mechanical angle rad}; None or NaN lets go of a joint."""
        for joint, angle in positions_rad.items():
            if angle is None or not math.isfinite(angle):
                self.arm.hand_engaged[joint] = False
            else:
                if not self.arm.hand_engaged[joint]:
                    self.arm.hand_rad[joint] = self.arm.angle_rad[joint]
                self.arm.hand_engaged[joint] = True
                self.arm.hand_goal_rad[joint] = angle

    def set_button(self, button):
        """Hold user button 1-4 down, or none (0). Raises ValueError for another value."""
        if button not in range(codec.NUM_BUTTONS + 1):
            raise ValueError('button must be 0-%d, got %r' % (codec.NUM_BUTTONS, button))
        self.button = button

    def set_grippers(self, readings):
        """Set the four gripper readings, each clamped to 0-1. Raises ValueError otherwise."""
        if len(readings) != codec.NUM_GRIPPERS or not all(math.isfinite(r) for r in readings):
            raise ValueError('need %d finite gripper readings, got %r'
                             % (codec.NUM_GRIPPERS, list(readings)))
        self.grippers = [min(1.0, max(0.0, r)) for r in readings]

    # Host frames ----------------------------------------------------------------------------
    def handle(self, message):
        """Obey one host->device message as the firmware does; ignore device->host types."""
        if isinstance(message, codec.Opmode):
            if message.mode == codec.HOLD and self.opmode != codec.HOLD:
                self.setpoint_rad = list(self.angle_rad)
                self._integral = [0.0] * settings.NUM_JOINTS
                self._last_error = [None] * settings.NUM_JOINTS
            self.opmode = message.mode
            if self.opmode == codec.LIMP:
                self.voltage_v = [0.0] * settings.NUM_JOINTS
        elif isinstance(message, codec.JointConfig):
            self.config[message.joint][settings.NAMES[message.config_id]] = message.value
        elif isinstance(message, codec.JointSetpoint):
            cfg = self.config[message.joint]
            self.setpoint_rad[message.joint] = min(cfg['angle_max'],
                                                   max(cfg['angle_min'], message.angle_rad))

    # Time -----------------------------------------------------------------------------------
    def advance(self, now_s):
        """Run the control loop up to now_s; return the messages the device sends by then."""
        if self._time_s is None:
            self._time_s = self._next_control_s = self._next_state_s = now_s
            self._next_heartbeat_s = now_s
        # A host that stalls for long does not make the arm catch up in one burst.
        self._next_control_s = max(self._next_control_s, now_s - 0.5)
        while self._next_control_s <= now_s:
            self._control_tick(1.0 / CONTROL_RATE_HZ)
            self._next_control_s += 1.0 / CONTROL_RATE_HZ
        self._time_s = now_s
        out = []
        if self._next_heartbeat_s <= now_s:
            out.append(codec.Heartbeat())
            self._next_heartbeat_s = _next_due(self._next_heartbeat_s, 1.0 / HEARTBEAT_RATE_HZ,
                                               now_s)
        if self._next_state_s <= now_s:
            out.extend(self.state_messages())
            self._next_state_s = _next_due(self._next_state_s, self.state_period_s, now_s)
        return out

    def next_due_s(self):
        """Return the time at which advance() next has work to do (None before the first call)."""
        if self._time_s is None:
            return None
        return min(self._next_control_s, self._next_state_s, self._next_heartbeat_s)

    def state_messages(self):
        """Return one state set: seven joint states, four grippers, then the buttons."""
        out = [codec.JointState(j, codec.WORKING if self.calibrated[j] else codec.UNCALIBRATED,
                                self.angle_rad[j], self.voltage_v[j]) for j in settings.JOINTS]
        out.extend(codec.Gripper(g, r) for g, r in enumerate(self.grippers))
        out.append(codec.Buttons(self.button))
        return out

    def _encoder(self, joint):
        """Return the raw encoder angle of a joint (rad, before the angle filter)."""
        cfg = self.config[joint]
        mechanical = self.arm.angle_rad[joint]
        if not self.calibrated[joint]:
            return wrap(cfg['sign_angle'] * (mechanical - self.power_on_rad[joint]))
        return wrap(cfg['home_angle'] + cfg['sign_angle'] * mechanical)

    def _control_tick(self, dt_s):
        """One 50 Hz firmware cycle: encoders, angle filter, PID; then the arm moves for dt_s."""
        hold = self.opmode == codec.HOLD
        for joint in settings.JOINTS:
            cfg = self.config[joint]
            raw = min(cfg['angle_max'], max(cfg['angle_min'], self._encoder(joint)))
            previous = self.angle_rad[joint]
            self.angle_rad[joint] = min(previous + cfg['velocity_max'] * dt_s,
                                        max(previous + cfg['velocity_min'] * dt_s, raw))
            if hold:
                self.voltage_v[joint] = self._pid(joint, dt_s)
        applied = np.array([v * self.config[j]['sign_motor'] for j, v in enumerate(self.voltage_v)])
        self.arm.update_loads()
        sub_dt = dt_s / PHYSICS_STEPS_PER_TICK
        for _ in range(PHYSICS_STEPS_PER_TICK):
            before = self.arm.step(sub_dt, applied, hold)
            for joint in QUAD_JOINTS:
                if not self.calibrated[joint] and _passes_index(before[joint],
                                                                self.arm.angle_rad[joint]):
                    self.calibrated[joint] = True

    def _pid(self, joint, dt_s):
        """Return the PID voltage of a joint, clamped to its voltage limits (anti-windup)."""
        cfg = self.config[joint]
        error = wrap(self.setpoint_rad[joint] - self.angle_rad[joint])
        last = self._last_error[joint]
        derivative = 0.0 if last is None else wrap(error - last) / dt_s
        self._last_error[joint] = error
        integral = self._integral[joint] + error * dt_s
        volts = cfg['pid_kp'] * error + cfg['pid_ki'] * integral + cfg['pid_kd'] * derivative
        clamped = min(cfg['voltage_max'], max(cfg['voltage_min'], volts))
        if clamped == volts:
            self._integral[joint] = integral
        return clamped


def _passes_index(before_rad, after_rad):
    """Return True if a joint moving from before_rad to after_rad meets its index mark."""
    period = 2.0 * math.pi
    if math.floor(before_rad / period) != math.floor(after_rad / period):
        return True
    return abs(wrap(after_rad)) <= INDEX_HALF_WIDTH_RAD


def _next_due(due_s, period_s, now_s):
    """Return the next due time after due_s; skip missed periods instead of bursting."""
    due_s += period_s
    return due_s if due_s > now_s else now_s + period_s
