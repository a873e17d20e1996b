"""The recorder's ~parameters, and what its metadata records of the running system.

RecorderNode's docstring lists the parameters.
"""
import types

import rospkg
import rospy

from robopuppet import interface
from robopuppet.config import config_file
from robopuppet.episodes import episode_files, episode_folder, metadata, recording
from robopuppet.episodes.session import Recorder

# The file operations session.Recorder uses.
FILES = types.SimpleNamespace(BagWriter=episode_files.BagWriter,
                              write_metadata=metadata.write_metadata,
                              free_bytes=episode_folder.free_bytes)


def make_recorder(directory):
    """Return (the session.Recorder of ~sides, ~cameras, ~min_free_mb and ~task into directory,
    ~sim).

    Raises:
        ValueError: ~sides or ~cameras names no side or camera.
    """
    sides = recording.parse_sides(rospy.get_param('~sides', 'LR'))
    cameras = recording.parse_cameras(rospy.get_param('~cameras', list(interface.SIM_CAMERAS)))
    sim = bool(rospy.get_param('~sim', False))
    min_free_mb = float(rospy.get_param('~min_free_mb', recording.DEFAULT_MIN_FREE_MB))
    task = rospy.get_param('~task', '')
    try:
        recording.check_task(task)
    except ValueError as error:  # kept: each start without a task of its own says why
        rospy.logerr("~task: %s: an episode started without a task is refused", error)
    return Recorder(directory, sides, cameras, min_free_mb, FILES, task), sim


def running_system(sides):
    """Return (the puppet's state-set rate /arm_X/comm_rate or None, {side: the sha256 of its
    live ini file, /config_X/file_name, or None}) for an episode's metadata."""
    rate = rospy.get_param(interface.node_param('arm', sides[0], 'comm_rate'), None)
    fingerprints = {s: episode_folder.ini_fingerprint(config_file.resolve_path(
        rospy.get_param(interface.node_param('config', s, 'file_name'), interface.ini_file_name(s)),
        rospkg.get_ros_home())) for s in sides}
    return rate, fingerprints
