"""Kinematic motion model of Baxter for the stand-in: enable state, both arms, both grippers.

Pure: every method that changes with time takes `now_s` (seconds, any monotonic origin); nothing
here reads a clock or imports rospy. Joint names and limits come from baxter_description; the
gripper is baxter_gripper, the refusals baxter_refusals, the JointCommand's modes and checks
baxter_joint_command, the contact with obstacles baxter_contact (all in robopuppet.baxter_sim).

Position control, the model of Baxter's joint position controller that arm_X's keep-out zones
rely on (docs/baxter_sim.md, "How the arms move"): in modes 1 and 4 each joint moves on its own,
from where it is straight toward its current target (clamped to its limits), never past it, at
most at its speed: mode 1 speed_ratio x its URDF velocity limit (a first-order lag of
SMOOTHING_TIME_S under that cap), mode 4 the velocity limit. A new target starts a new such move
from wherever the joint is. Mode 1 has no command timeout: the arm goes on to its last target
(as a real Baxter finishes tuck_arms' move); in modes 2, 3 and 4 no command for command_timeout_s
holds the arm where it is. So a joint always lies between where it was when its target came and
that target.
"""
import math

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_gripper import GRIPPER_OPEN, Gripper, approach
from robopuppet.baxter_sim.baxter_io import AnalogIO, DigitalIO, Head
from robopuppet.baxter_sim.baxter_joint_command import (POSITION_MODE, TORQUE_MODE, VELOCITY_MODE,
                                                        command_targets)
from robopuppet.baxter_sim.baxter_refusals import CommandError, NotEnabledError, brief, finite
from robopuppet.interface import BAXTER_SIDES

DEFAULT_SPEED_RATIO = bd.POSITION_SPEED_RATIO
DEFAULT_COMMAND_TIMEOUT_S = 0.2
# Mode 1 approaches its target as a first-order lag with this time constant (capped in speed),
# ending on the target once within SETTLED_RAD (so a still arm stands still, as Baxter's settles).
SMOOTHING_TIME_S, SETTLED_RAD = 0.05, 1e-4


class Arm:
    """One arm: 7 joints following position commands within their limits.

    Positions in rad, speeds in rad/s, times in s, torques in N m. With a contact
    (baxter_contact.ArmContact) the arm stops where a link would enter an obstacle.
    """

    def __init__(self, side, description, now_s, contact=None):
        self.side = side
        self.contact = contact
        self.limits = {lim.name: lim for lim in description.arm_limits(side)}
        self.max_effort = {name: description.joints[name].effort for name in self.limits}
        self.rates = dict.fromkeys(self.limits, 0.0)     # modes 2 and 3: joint speeds, rad/s
        self.torques = dict.fromkeys(self.limits, 0.0)   # mode 3: commanded torques, N m
        self.efforts = dict(self.torques)   # reported: commanded torques, or contact torques
        self.positions = dict(bd.neutral_pose(side))
        self.velocities = {name: 0.0 for name in self.limits}
        self.targets = dict(self.positions)
        self.mode = POSITION_MODE
        self.speed_ratio = DEFAULT_SPEED_RATIO
        self.command_timeout_s = DEFAULT_COMMAND_TIMEOUT_S
        self.last_command_s = None
        self.last_step_s = now_s

    def hold(self):
        """Stop where the arm is."""
        self.targets = dict(self.positions)
        self.last_command_s = None
        self.rates = dict.fromkeys(self.rates, 0.0)
        self.torques = dict.fromkeys(self.torques, 0.0)
        self.efforts = dict(self.torques)

    def command(self, mode, names, values, now_s):
        """Take new targets (baxter_joint_command.command_targets checks and clamps them).

        In modes 2 and 3 joints not named get 0 (hold). A torque drives a gravity-compensated,
        damped joint: it moves at torque / effort limit x velocity limit (the effort limit
        reaches the velocity limit). A refused command changes nothing: it neither restarts the
        command timeout nor switches the mode. So an empty command (no names), which a real
        Baxter ignores, does not keep the arm moving.

        Raises:
            CommandError: the command is malformed (see command_targets).
        """
        targets = command_targets(self.side, mode, names, values, self.limits, self.max_effort)
        self.step(now_s)  # the arm moved toward the old targets until the command arrived
        self.rates = dict.fromkeys(self.rates, 0.0)
        self.torques = dict.fromkeys(self.torques, 0.0)
        if mode == VELOCITY_MODE:
            self.rates.update(targets)
        elif mode == TORQUE_MODE:
            self.torques.update(targets)
            self.rates.update({name: torque / self.max_effort[name] * self.limits[name].velocity
                               for name, torque in targets.items()})
        else:
            self.targets.update(targets)
        self.mode = mode
        self.last_command_s = now_s

    def step(self, now_s):
        """Move toward the targets until now_s. Mode 1 goes on to its last target; in the other
        modes the arm holds once commands are older than the timeout."""
        dt = now_s - self.last_step_s
        if dt <= 0.0:
            return
        self.last_step_s = now_s
        active_s = 0.0
        if self.last_command_s is not None and self.mode == POSITION_MODE:
            active_s = dt
        elif self.last_command_s is not None:
            deadline_s = self.last_command_s + self.command_timeout_s
            active_s = max(0.0, min(dt, deadline_s - (now_s - dt)))
            if now_s >= deadline_s:
                self.last_command_s = None  # commands stopped: hold after this step
        smoothing = 1.0
        ratio = 1.0
        if self.mode == POSITION_MODE:
            smoothing = 1.0 - math.exp(-active_s / SMOOTHING_TIME_S)
            ratio = self.speed_ratio
        integrating = self.mode in (VELOCITY_MODE, TORQUE_MODE)
        old = dict(self.positions)
        for name, limit in self.limits.items():
            if integrating:
                new = min(limit.upper, max(limit.lower, old[name] + self.rates[name] * active_s))
            else:
                new = approach(old[name], self.targets[name], ratio * limit.velocity * active_s,
                               smoothing, SETTLED_RAD if self.mode == POSITION_MODE else 0.0)
            self.positions[name] = new
        self.efforts = dict(self.torques)
        if self.contact is not None:
            self._touch(old, integrating)
        if not integrating:   # p + (target - p) can round past target: never past it
            for name in self.limits:
                low, high = sorted((old[name], self.targets[name]))
                self.positions[name] = min(high, max(low, self.positions[name]))
        for name in self.limits:
            self.velocities[name] = (self.positions[name] - old[name]) / dt
        if self.last_command_s is None:
            self.hold()
        elif integrating:
            self.targets = dict(self.positions)

    def _touch(self, old, integrating):
        """Cut this step's motion from `old` at contact. Blocked joints press: in modes 1 and 4
        with their command's distance past contact (ArmContact.press), in modes 2 and 3 with
        the torque their speed stands for (mode 3's own torque)."""
        names = list(self.limits)
        reached, blocked = self.contact.limit([old[n] for n in names],
                                              [self.positions[n] for n in names])
        press = self.contact.press([self.targets[n] - reached[j] for j, n in enumerate(names)])
        for j, name in enumerate(names):
            self.positions[name] = float(reached[j])
            if blocked[j]:
                self.efforts[name] = (self.rates[name] / self.limits[name].velocity
                                      * self.max_effort[name] if integrating else float(press[j]))


class BaxterModel:
    """Baxter's enable state, both arms and both grippers.

    Args:
        description: a baxter_description.Description.
        now_s: the start time.
        gripper_calibrated: whether the grippers start calibrated.
        contacts: {side: baxter_contact.ArmContact} of the arms that obstacles block.
    """

    def __init__(self, description, now_s, gripper_calibrated=False, contacts=None):
        self.description = description
        self.enabled = False
        self.stopped = False
        self.arms = {side: Arm(side, description, now_s, (contacts or {}).get(side))
                     for side in BAXTER_SIDES}
        self.fingers = {side: bd.gripper_finger_joints(side) for side in BAXTER_SIDES}
        travel_m = {side: description.limit(self.fingers[side][0]).upper for side in BAXTER_SIDES}
        self.finger_travel_m = travel_m
        self.grippers = {}
        for side in BAXTER_SIDES:
            speed = description.limit(self.fingers[side][0]).velocity / travel_m[side] * 100.0
            self.grippers[side] = Gripper(speed, gripper_calibrated, now_s)
        self.head = Head(description.limit(bd.HEAD_PAN), now_s)
        self.io, self.analog = DigitalIO(), AnalogIO()

    # -- enable state (/robot/set_super_enable, _reset, _stop) --
    def set_enabled(self, enable):
        """Enable or disable; arms hold where they are either way.

        Raises:
            CommandError: enabling while stopped (reset first).
        """
        if enable and self.stopped:
            raise CommandError('cannot enable: the robot is stopped; reset it first', 'stopped')
        self.enabled = bool(enable)
        for arm in self.arms.values():
            arm.hold()
        self.head.hold()

    def stop(self):
        """Software e-stop: disable and latch stopped until reset."""
        self.set_enabled(False)
        self.stopped = True

    def reset(self):
        """Clear the stopped latch; the robot stays disabled. Gripper errors stay (on Baxter the
        gripper's own 'reset' command clears them); the joints' hardware faults that Rethink's
        reset also clears are not modelled."""
        self.set_enabled(False)
        self.stopped = False

    # -- commands --
    def _arm(self, side):
        if side not in self.arms:
            raise CommandError('unknown arm side %s' % brief(side), 'unknown side')
        return self.arms[side]

    def joint_command(self, side, mode, names, values, now_s):
        """Apply a JointCommand to one arm (see Arm.command).

        Raises:
            NotEnabledError: the robot is disabled.
            CommandError: the command is malformed.
        """
        if not self.enabled:
            raise NotEnabledError('joint command for the %s arm ignored: robot disabled' % side)
        self._arm(side).command(mode, list(names), list(values), now_s)

    def set_speed_ratio(self, side, ratio):
        """Set the mode-1 speed as a fraction of the velocity limits, clipped to 0..1 as on
        Baxter (baxter_interface Limb.set_joint_position_speed).

        Raises:
            CommandError: a non-finite ratio (the ratio is left as it was).
        """
        self._arm(side).speed_ratio = min(1.0, max(0.0, finite(ratio, 'speed ratio')))

    def set_command_timeout(self, side, timeout_s):
        """Set how long the arm follows its last command before holding (s, > 0; modes 2-4)."""
        timeout_s = finite(timeout_s, 'joint command timeout')
        if timeout_s <= 0.0:
            raise CommandError('joint command timeout must be > 0 s, got %g' % timeout_s,
                               'out of range')
        self._arm(side).command_timeout_s = timeout_s

    def head_pan(self, target_rad, speed_ratio, enable_pan_request):
        """Apply a HeadPanCommand (see Head.command_pan); refused while disabled."""
        if not self.enabled:
            raise NotEnabledError('head pan command ignored: robot disabled')
        self.head.command_pan(target_rad, speed_ratio, enable_pan_request)

    def gripper_command(self, side, command, args, sender, sequence):
        """Apply an EndEffectorCommand to one gripper (see Gripper.command)."""
        if side not in self.grippers:
            raise CommandError('unknown gripper side %s' % brief(side), 'unknown side')
        self.grippers[side].command(command, args, sender, sequence)

    # -- time --
    def step(self, now_s):
        """Advance arms and grippers to now_s."""
        for arm in self.arms.values():
            if self.enabled:
                arm.step(now_s)
            else:
                arm.last_step_s = now_s
                arm.velocities = dict.fromkeys(arm.velocities, 0.0)
        for gripper in self.grippers.values():
            gripper.step(now_s, self.enabled)
        self.head.step(now_s, self.enabled)

    # -- outputs --
    def positions(self):
        """Return {joint name: position} of every movable joint (rad, m for fingers)."""
        result = {bd.HEAD_PAN: self.head.pan_rad}
        for side in BAXTER_SIDES:
            result.update(self.arms[side].positions)
            driven, mimic = self.fingers[side]
            opening_m = self.grippers[side].position / GRIPPER_OPEN * self.finger_travel_m[side]
            result[driven], result[mimic] = opening_m, -opening_m
        return result

    def joint_state(self):
        """Return (names, positions, velocities, efforts), equal-length lists.

        Names are every movable URDF joint plus torso_t0, sorted. Effort (N m) is the torque a
        torque-mode command applies on top of gravity compensation, or a blocked joint's press
        on an obstacle (Arm._touch), else 0: the efforts beyond gravity (BaxterApi.cycle adds
        the gravity torques of baxter_statics).
        """
        positions = self.positions()
        velocities = dict.fromkeys(positions, 0.0)
        efforts = dict.fromkeys(positions, 0.0)
        velocities[bd.HEAD_PAN] = self.head.velocity_rad_s
        for side in BAXTER_SIDES:
            velocities.update(self.arms[side].velocities)
            efforts.update(self.arms[side].efforts)
            driven, mimic = self.fingers[side]
            speed = (self.grippers[side].speed_pct_s / GRIPPER_OPEN
                     * self.finger_travel_m[side])
            velocities[driven], velocities[mimic] = speed, -speed
        positions[bd.TORSO] = velocities[bd.TORSO] = efforts[bd.TORSO] = 0.0
        names = sorted(positions)
        return (names, [positions[n] for n in names], [velocities[n] for n in names],
                [efforts[n] for n in names])

    def endpoint_pose(self, side):
        """Return ((x, y, z) m, (qx, qy, qz, qw)) of the side's gripper link in base."""
        return self.description.pose(self.positions(), bd.gripper_link(side))
