"""Teleop's inputs from the fields of arm_X's messages (pure).

Joints are matched by name, never by index: the puppet's joint_states name joint_0..joint_6,
Baxter's /robot/joint_states name every joint of the robot in an order of its own.
"""
import math
import reprlib

from robopuppet import settings


def joint_angles(names, positions):
    """Return the puppet's 7 angles (rad) from a JointState's names and positions, or raise.

    Non-finite angles pass through: teleop ignores them joint by joint.
    Raises:
        ValueError: a name of joint_0..joint_6 is missing, or names and positions differ in
            number (the message says which).
    """
    if len(names) != len(positions):
        raise ValueError('%d names but %d positions' % (len(names), len(positions)))
    position = dict(zip(names, positions))
    missing = [n for n in settings.JOINT_NAMES if n not in position]
    if missing:
        raise ValueError('no %s (names %s)' % (', '.join(missing), reprlib.repr(list(names))))
    return [float(position[n]) for n in settings.JOINT_NAMES]


def non_finite_joints(angles):
    """Return the names of the joints whose angle is not finite."""
    return [settings.JOINT_NAMES[j] for j, a in enumerate(angles) if not math.isfinite(a)]


def arm_poses(names, positions, velocities, joint_names):
    """Return ({side: 7 angles rad}, {side: 7 velocities rad/s}) of Baxter's arms.

    Args:
        names, positions, velocities: the fields of Baxter's JointState (velocities may be
            empty; any other length than names' is ignored).
        joint_names: {side: the arm's 7 joint names, in puppet joint order}.
    An arm with a joint missing from names is left out of the poses; a missing velocity is 0.
    """
    position = dict(zip(names, positions))
    velocity = dict(zip(names, velocities)) if len(velocities) == len(names) else {}
    poses = {side: [position[n] for n in arm] for side, arm in joint_names.items()
             if all(n in position for n in arm)}
    speeds = {side: [velocity.get(n, 0.0) for n in arm] for side, arm in joint_names.items()}
    return poses, speeds
