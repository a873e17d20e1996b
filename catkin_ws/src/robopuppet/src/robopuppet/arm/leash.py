"""The leash: no command further ahead of Baxter's measured pose than Baxter goes in a moment.

Pure: angles in rad, times in s. Baxter in position mode (mode 1) has no command timeout: when
the commands stop (arm_X killed, the robot host's master dead) it goes on to its last target at
its speed ratio x each joint's URDF velocity limit. A target kept within leash_s of that speed
from where Baxter is bounds the coast to about leash_s of travel (docs/zones.md, "When the
commands stop: the leash").
"""
from robopuppet.baxter_description import POSITION_SPEED_RATIO as MODE1_SPEED_RATIO


def leash_rad(limits, leash_s):
    """Return how far (rad) each joint's target may lead Baxter: leash_s x its mode-1 speed.

    Args:
        limits: 7 limits with velocity (rad/s), see baxter_description.arm_limits.
        leash_s: the leash in seconds of mode-1 travel.
    """
    return [leash_s * MODE1_SPEED_RATIO * lim.velocity for lim in limits]


def leashed(target, pose, limits, leash_s):
    """Return target (7 rad) with each joint kept within leash_rad of Baxter's pose (7 rad).

    The target as it is when leash_s is 0 (no leash) or the pose is None (unknown).
    """
    if not leash_s or pose is None:
        return list(target)
    return [min(max(goal, at - reach), at + reach)
            for goal, at, reach in zip(target, pose, leash_rad(limits, leash_s))]
