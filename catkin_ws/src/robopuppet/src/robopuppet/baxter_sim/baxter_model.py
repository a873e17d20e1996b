"""Kinematic motion model of Baxter for the stand-in: enable state, both arms, both grippers.

Pure: every method that changes with time takes `now_s` (seconds, any monotonic origin); nothing
here reads a clock or imports rospy. Joint names and limits come from baxter_description; the
gripper is robopuppet.baxter_sim.baxter_gripper, the refusals robopuppet.baxter_sim.baxter_refusals.
"""
import math

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_gripper import GRIPPER_OPEN, Gripper, approach
from robopuppet.baxter_sim.baxter_refusals import CommandError, NotEnabledError, brief, finite
from robopuppet.interface import BAXTER_SIDES

POSITION_MODE = 1       # baxter_core_msgs/JointCommand.POSITION_MODE: smoothed, speed-ratio scaled
RAW_POSITION_MODE = 4   # baxter_core_msgs/JointCommand.RAW_POSITION_MODE: at the velocity limit
# The modes Baxter has but the stand-in refuses, by name (any other number: 'unknown mode').
REFUSED_MODES = {2: 'velocity mode', 3: 'torque mode'}
DEFAULT_SPEED_RATIO = 0.3
DEFAULT_COMMAND_TIMEOUT_S = 0.2
# Mode 1 approaches its target as a first-order lag with this time constant (capped in speed).
SMOOTHING_TIME_S = 0.05


class Arm:
    """One arm: 7 joints following position commands within their limits.

    Positions in rad, speeds in rad/s, times in s.
    """

    def __init__(self, side, description, now_s):
        self.side = side
        self.limits = {lim.name: lim for lim in description.arm_limits(side)}
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

    def command(self, mode, names, values, now_s):
        """Take new targets; names may be any subset of this arm's joints, in any order.

        Targets outside a joint's limits are clamped to the limit. A command that is refused
        changes nothing: it neither restarts the command timeout nor switches the mode. So an
        empty command (no names), which a real Baxter ignores, does not keep the arm moving.

        Raises:
            CommandError: velocity, torque or unknown mode, length mismatch, no joints, more
                joints than the arm has, an unknown (or the other arm's) or repeated joint name,
                or a non-finite value.
        """
        if mode not in (POSITION_MODE, RAW_POSITION_MODE):
            raise CommandError('%s arm: joint command mode %s refused: only position (1) and raw '
                               'position (4) are supported' % (self.side, brief(mode)),
                               REFUSED_MODES.get(mode, 'unknown mode'))
        if len(names) != len(values):
            raise CommandError('%s arm: joint command has %d names but %d values'
                               % (self.side, len(names), len(values)), 'length mismatch')
        if not names:
            raise CommandError('%s arm: empty joint command ignored (no joints): it does not '
                               'restart the command timeout' % self.side, 'empty')
        if len(names) > len(self.limits):
            raise CommandError('%s arm: joint command names %d joints, the arm has %d'
                               % (self.side, len(names), len(self.limits)), 'too many joints')
        unknown = [n for n in names if n not in self.limits]
        if unknown:
            raise CommandError('%s arm: joint command names unknown to this arm: %s'
                               % (self.side, brief(unknown)), 'unknown joint')
        if len(set(names)) != len(names):
            raise CommandError('%s arm: joint command names a joint twice: %s'
                               % (self.side, brief(list(names))), 'repeated joint')
        targets = {}
        for name, value in zip(names, values):
            limit = self.limits[name]
            value = finite(value, '%s arm: joint command for %s' % (self.side, name),
                           'non-finite value')
            targets[name] = min(limit.upper, max(limit.lower, value))
        self.step(now_s)  # the arm moved toward the old targets until the command arrived
        self.targets.update(targets)
        self.mode = mode
        self.last_command_s = now_s

    def step(self, now_s):
        """Move toward the targets until now_s; hold once commands are older than the timeout."""
        dt = now_s - self.last_step_s
        if dt <= 0.0:
            return
        self.last_step_s = now_s
        active_s = 0.0
        if self.last_command_s is not None:
            deadline_s = self.last_command_s + self.command_timeout_s
            active_s = max(0.0, min(dt, deadline_s - (now_s - dt)))
            if now_s >= deadline_s:
                self.last_command_s = None  # commands stopped: hold after this step
        smoothing = 1.0
        ratio = 1.0
        if self.mode == POSITION_MODE:
            smoothing = 1.0 - math.exp(-active_s / SMOOTHING_TIME_S)
            ratio = self.speed_ratio
        for name, limit in self.limits.items():
            old = self.positions[name]
            new = approach(old, self.targets[name], ratio * limit.velocity * active_s, smoothing)
            self.positions[name] = new
            self.velocities[name] = (new - old) / dt
        if self.last_command_s is None:
            self.targets = dict(self.positions)


class BaxterModel:
    """Baxter's enable state, both arms and both grippers.

    Args:
        description: a baxter_description.Description.
        now_s: the start time.
        gripper_calibrated: whether the grippers start calibrated.
    """

    def __init__(self, description, now_s, gripper_calibrated=False):
        self.description = description
        self.enabled = False
        self.stopped = False
        self.arms = {side: Arm(side, description, now_s) for side in BAXTER_SIDES}
        self.fingers = {side: bd.gripper_finger_joints(side) for side in BAXTER_SIDES}
        travel_m = {side: description.limit(self.fingers[side][0]).upper for side in BAXTER_SIDES}
        self.finger_travel_m = travel_m
        self.grippers = {}
        for side in BAXTER_SIDES:
            speed = description.limit(self.fingers[side][0]).velocity / travel_m[side] * 100.0
            self.grippers[side] = Gripper(speed, gripper_calibrated, now_s)
        self.head_pan_rad = 0.0

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

    def stop(self):
        """Software e-stop: disable and latch stopped until reset."""
        self.set_enabled(False)
        self.stopped = True

    def reset(self):
        """Clear the stopped latch; the robot stays disabled.

        Rethink's reset also clears the joints' hardware faults, which this model has none of.
        Gripper errors are left alone: on Baxter the gripper's own 'reset' command clears them.
        """
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
        """Set the mode-1 speed as a fraction 0..1 of the velocity limits."""
        ratio = finite(ratio, 'speed ratio')
        if not 0.0 <= ratio <= 1.0:
            raise CommandError('speed ratio must be within 0..1, got %g' % ratio, 'out of range')
        self._arm(side).speed_ratio = ratio

    def set_command_timeout(self, side, timeout_s):
        """Set how long the arm follows its last command before holding (s, > 0)."""
        timeout_s = finite(timeout_s, 'joint command timeout')
        if timeout_s <= 0.0:
            raise CommandError('joint command timeout must be > 0 s, got %g' % timeout_s,
                               'out of range')
        self._arm(side).command_timeout_s = timeout_s

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

    # -- outputs --
    def positions(self):
        """Return {joint name: position} of every movable joint (rad, m for fingers)."""
        result = {bd.HEAD_PAN: self.head_pan_rad}
        for side in BAXTER_SIDES:
            result.update(self.arms[side].positions)
            driven, mimic = self.fingers[side]
            opening_m = self.grippers[side].position / GRIPPER_OPEN * self.finger_travel_m[side]
            result[driven], result[mimic] = opening_m, -opening_m
        return result

    def joint_state(self):
        """Return (names, positions, velocities, efforts), equal-length lists.

        Names are every movable URDF joint plus torso_t0, sorted; effort is always 0.
        """
        positions = self.positions()
        velocities = dict.fromkeys(positions, 0.0)
        for side in BAXTER_SIDES:
            velocities.update(self.arms[side].velocities)
            driven, mimic = self.fingers[side]
            speed = (self.grippers[side].speed_pct_s / GRIPPER_OPEN
                     * self.finger_travel_m[side])
            velocities[driven], velocities[mimic] = speed, -speed
        positions[bd.TORSO] = velocities[bd.TORSO] = 0.0
        names = sorted(positions)
        return (names, [positions[n] for n in names], [velocities[n] for n in names],
                [0.0] * len(names))

    def endpoint_pose(self, side):
        """Return ((x, y, z) m, (qx, qy, qz, qw)) of the side's gripper link in base."""
        return self.description.pose(self.positions(), bd.gripper_link(side))
