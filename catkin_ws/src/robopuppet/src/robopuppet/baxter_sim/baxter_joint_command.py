"""Baxter's JointCommand as the stand-in takes it: the modes, and the checks before an arm moves.

Pure: no rospy, no messages, no clock.
"""
from robopuppet.baxter_sim.baxter_refusals import CommandError, brief, finite

POSITION_MODE = 1       # baxter_core_msgs/JointCommand.POSITION_MODE: smoothed, speed-ratio scaled
VELOCITY_MODE = 2       # JointCommand.VELOCITY_MODE: rad/s, integrated within the limits
TORQUE_MODE = 3         # JointCommand.TORQUE_MODE: N m on top of gravity compensation
RAW_POSITION_MODE = 4   # baxter_core_msgs/JointCommand.RAW_POSITION_MODE: at the velocity limit
MODES = (POSITION_MODE, VELOCITY_MODE, TORQUE_MODE, RAW_POSITION_MODE)


def command_targets(side, mode, names, values, limits, max_effort):
    """Return {joint name: target} of a JointCommand for one arm, each clamped to its bound.

    Positions (modes 1 and 4) are clamped to the joint's limits, velocities (mode 2) to its
    velocity limit, torques (mode 3) to its effort limit.

    Args:
        side: the arm ('left', 'right'), for the messages.
        names, values: the command's joint names (any subset of the arm's, any order) and values.
        limits: {joint name: baxter_description JointLimit} of the arm.
        max_effort: {joint name: effort limit N m} of the arm.

    Raises:
        CommandError: unknown mode, length mismatch, no joints, more joints than the arm has,
            an unknown (or the other arm's) or repeated joint name, or a non-finite value.
    """
    if mode not in MODES:
        raise CommandError('%s arm: joint command mode %s is not a Baxter mode (1 position, '
                           '2 velocity, 3 torque, 4 raw position)' % (side, brief(mode)),
                           'unknown mode')
    if len(names) != len(values):
        raise CommandError('%s arm: joint command has %d names but %d values'
                           % (side, len(names), len(values)), 'length mismatch')
    if not names:
        raise CommandError('%s arm: empty joint command ignored (no joints): it does not '
                           'restart the command timeout' % side, 'empty')
    if len(names) > len(limits):
        raise CommandError('%s arm: joint command names %d joints, the arm has %d'
                           % (side, len(names), len(limits)), 'too many joints')
    unknown = [n for n in names if n not in limits]
    if unknown:
        raise CommandError('%s arm: joint command names unknown to this arm: %s'
                           % (side, brief(unknown)), 'unknown joint')
    if len(set(names)) != len(names):
        raise CommandError('%s arm: joint command names a joint twice: %s'
                           % (side, brief(list(names))), 'repeated joint')
    targets = {}
    for name, value in zip(names, values):
        limit = limits[name]
        value = finite(value, '%s arm: joint command for %s' % (side, name), 'non-finite value')
        bound = {VELOCITY_MODE: limit.velocity, TORQUE_MODE: max_effort[name]}.get(mode)
        low, high = (limit.lower, limit.upper) if bound is None else (-bound, bound)
        targets[name] = min(high, max(low, value))
    return targets
