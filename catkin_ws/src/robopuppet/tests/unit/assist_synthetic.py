"""Synthetic two-armed demonstrations for the assist learners' unit tests: the follower is a
known function of where the leader is along a shared path, so a learner's error is measurable
without the simulated tasks."""
import collections

import numpy as np

Demo = collections.namedtuple('Demo', 't left right left_closed right_closed')
BASE = np.array([0.3, -0.5, 0.0, 1.2, 0.0, 0.6, 0.0])
AMPLITUDE = np.array([0.4, 0.3, 0.2, -0.5, 0.3, 0.2, 0.1])
MIRROR = np.array([-1, 1, -1, 1, -1, 1, -1])


def demo(seed, rate_hz=50.0):
    """Return one varied demonstration: the right arm leads along a path at a varied pace from
    a varied start, the left arm is the mirror of it plus a phase term, its gripper closed in
    the middle of the motion."""
    rng = np.random.default_rng(seed)
    duration_s = rng.uniform(6.0, 9.0)
    t = np.arange(0.0, duration_s, 1.0 / rate_hz)
    s = np.clip(t / duration_s + 0.05 * np.sin(2 * np.pi * t / duration_s)
                * rng.uniform(-1, 1), 0, 1)
    s = 0.5 - 0.5 * np.cos(np.pi * s)
    start = rng.normal(0, 0.05, 7)
    right = (BASE + start * (1 - s[:, None]) + AMPLITUDE * np.sin(np.pi * s)[:, None]
             + np.outer(s, [0.2, 0, 0, 0, 0, 0, 0]) + rng.normal(0, 0.003, (len(t), 7)))
    left = right * MIRROR + 0.1 * np.sin(2 * np.pi * s)[:, None]
    closed = (s > 0.2) & (s < 0.8)
    return Demo(t, left, right, closed, closed.copy())


def unfamiliar(seed, rate_hz=50.0):
    """Return (demo, departure time s): a demonstration whose leader leaves the path a third of
    the way in, moving joints s0 and e1 as no demonstration does (the follower held)."""
    shown = demo(seed, rate_hz)
    k = len(shown.t) // 3
    right = shown.right.copy()
    after = shown.t[k:] - shown.t[k]
    right[k:] = right[k]
    right[k:, 0] -= 0.8 * after
    right[k:, 3] += 0.6 * after
    left = np.tile(shown.left[0], (len(shown.t), 1))
    still = np.zeros(len(shown.t), bool)
    return Demo(shown.t, left, right, still, still), shown.t[k]


def write_episode(directory, name, shown, task='', rate_hz=100.0, gap=None, grippers=True):
    """Write a Demo as an episode's bag and .yaml in directory (a pathlib.Path), Baxter's joint
    states and gripper states at rate_hz (the Demo interpolated); gap (start s, end s): no
    joint states in it; grippers False: no gripper states. Return the bag's path."""
    import genpy  # pylint: disable=import-outside-toplevel  (ROS only for the bag tests)
    import rosbag  # pylint: disable=import-outside-toplevel
    import yaml  # pylint: disable=import-outside-toplevel
    from baxter_core_msgs.msg import EndEffectorState  # pylint: disable=import-outside-toplevel
    from sensor_msgs.msg import JointState  # pylint: disable=import-outside-toplevel
    from robopuppet.baxter_description import arm_joint_names  # pylint: disable=C0415
    names = arm_joint_names('left') + arm_joint_names('right') + ['head_pan']
    bag_path = directory / (name + '.bag')
    times = np.arange(0.0, shown.t[-1] + 1e-9, 1.0 / rate_hz)
    with rosbag.Bag(str(bag_path), 'w') as bag:
        for t_s in times:
            stamp = genpy.Time.from_sec(1700000000.0 + t_s)
            if gap is None or not gap[0] < t_s < gap[1]:
                angles = [float(np.interp(t_s, shown.t, getattr(shown, side)[:, j]))
                          for side in ('left', 'right') for j in range(7)]
                bag.write('/robot/joint_states', JointState(name=names, position=angles + [0.0]),
                          stamp)
            for side in ('left', 'right') if grippers else ():
                k = min(np.searchsorted(shown.t, t_s), len(shown.t) - 1)
                closed = getattr(shown, side + '_closed')[k]
                bag.write('/robot/end_effector/%s_gripper/state' % side,
                          EndEffectorState(position=0.0 if closed else 100.0), stamp)
    (directory / (name + '.yaml')).write_text(yaml.safe_dump({'name': name, 'task': task}))
    return bag_path
