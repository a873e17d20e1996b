"""Recorded episodes as the learners' demonstrations: Baxter's measured arms and grippers.

An episode's bag is read with the exporter's reader (episodes.export_files) and its messages
made into series by episodes.export.collect. The Demo keeps what Baxter measured, not what was
commanded: both arms' 7 angles from /robot/joint_states and each gripper's closed state from
its EndEffectorState (position below CLOSED_BELOW_PERCENT), resampled at RATE_HZ. Where
Baxter's joint states stop for more than GAP_S, the grid steps in the gap are left out (t jumps
over it) instead of interpolated across; the learners' velocity filter restarts after a jump.
"""
import collections
import os

import numpy as np

from robopuppet.assist.demonstration import Demo
from robopuppet.episodes import export, export_files
from robopuppet.episodes.export_cli import resolve
from robopuppet.episodes.metadata import EpisodeError, episode_paths, metadata_or_empty
from robopuppet.interface import BAXTER_SIDES, ROBOT_JOINT_STATES, baxter_gripper_topic

RATE_HZ = 50.0
GAP_S = 0.1               # Baxter publishes its joint states at 100 Hz
CLOSED_BELOW_PERCENT = 50.0

Episode = collections.namedtuple('Episode', 'name task demo')
Episode.__doc__ = """A read episode: name, task (its metadata's task, '' for none), demo."""


class DatasetError(ValueError):
    """An episode cannot be a demonstration: unreadable, or without the topics it needs."""


def demo_of(messages, follower=None, rate_hz=RATE_HZ):
    """Return the Demo of an episode's (topic, msg, t) messages, t in s.

    Raises:
        DatasetError: no joint states of both arms, or no gripper state of the follower (a
            side; None: no gripper needed).
    """
    recording = export.collect(messages)
    complete = np.isfinite(recording.position.values).all(axis=1)
    times = recording.position.times[complete]
    values = recording.position.values[complete]
    if not len(times):
        raise DatasetError('no %s naming both arms\' joints' % ROBOT_JOINT_STATES)
    grid = export.time_grid(times[0], times[-1], rate_hz)
    before = np.clip(np.searchsorted(times, grid, side='right') - 1, 0, len(times) - 1)
    after = np.minimum(before + 1, len(times) - 1)
    grid = grid[times[after] - times[before] <= GAP_S]
    angles = export.interpolate(export.Samples(times, values), grid)
    closed = {}
    for side in BAXTER_SIDES:
        state = recording.gripper_state[side]
        if len(state.times):
            closed[side] = export.interpolate(state, grid)[:, 0] < CLOSED_BELOW_PERCENT
        elif side == follower:
            raise DatasetError('no %s: the follower\'s gripper is never measured'
                               % baxter_gripper_topic(side, 'state'))
        else:
            closed[side] = np.zeros(len(grid), bool)
    return Demo(grid - times[0], angles[:, :7], angles[:, 7:], closed['left'], closed['right'])


def read_episode(path, leader, follower):
    """Return the Demo of an episode (a name, .bag or .yaml path) for a leader and follower.

    Raises:
        DatasetError: it cannot be read or lacks the topics it needs.
    """
    if leader not in BAXTER_SIDES or follower not in BAXTER_SIDES or leader == follower:
        raise ValueError('leader and follower must be left and right, got %r, %r'
                         % (leader, follower))
    topics = [ROBOT_JOINT_STATES] + [baxter_gripper_topic(s, 'state') for s in BAXTER_SIDES]
    try:
        bag_path, _ = episode_paths(resolve(path))
        messages = export_files.read_messages(bag_path, topics)
    except (EpisodeError, OSError, ValueError) as error:
        raise DatasetError('%s: %s' % (path, error)) from error
    except Exception as error:  # noqa: BLE001  rosbag's own errors (ROSBagException ...)
        raise DatasetError('%s: not a readable bag (%s)' % (path, error)) from error
    try:
        return demo_of(messages, follower)
    except DatasetError as error:
        raise DatasetError('%s: %s' % (os.path.basename(bag_path), error)) from error


def episode_arguments(arguments):
    """Return the episode paths of arguments: each a folder (its .bag files, sorted), or an
    episode's name, .bag or .yaml."""
    paths = []
    for argument in arguments:
        if os.path.isdir(argument):
            paths += sorted(os.path.join(argument, name) for name in os.listdir(argument)
                            if name.endswith('.bag'))
        else:
            paths.append(argument)
    return paths


def read_episodes(arguments, leader, follower, task=None, say=print):
    """Return the Episodes of arguments (see episode_arguments) whose task is task (None: any),
    saying a line per episode (read, skipped for its task, or its error) as it goes. An
    episode that cannot be read is skipped; the returned list holds the others.

    Returns:
        (episodes, errors): the Episodes read and the DatasetError text of those skipped.
    """
    paths = episode_arguments(arguments)
    episodes, errors = [], []
    for number, path in enumerate(paths, 1):
        try:
            bag_path, yaml_path = episode_paths(resolve(path))
        except EpisodeError as error:
            errors.append(str(error))
            say('[%d/%d] skipped: %s' % (number, len(paths), error))
            continue
        name = os.path.basename(bag_path)[:-len('.bag')]
        text = ' '.join(str(metadata_or_empty(yaml_path).get('task') or '').split())
        if task is not None and text != task:
            say('[%d/%d] %s: task %r, not %r: left out' % (number, len(paths), name, text, task))
            continue
        try:
            demo = read_episode(bag_path, leader, follower)
        except DatasetError as error:
            errors.append(str(error))
            say('[%d/%d] skipped: %s' % (number, len(paths), error))
            continue
        episodes.append(Episode(name, text, demo))
        say('[%d/%d] %s: %.1f s, %d steps%s' % (number, len(paths), name,
                                                len(demo.t) / RATE_HZ, len(demo.t),
                                                ', task %r' % text if text else ''))
    return episodes, errors
