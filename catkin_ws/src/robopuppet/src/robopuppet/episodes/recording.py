"""What the recorder records and when: topics per side, button 4, names, metadata, disk rule.

Pure: no rospy, no clock; the node passes times in. The format these follow is fixed in
docs/demonstrations.md ("The episode format"), shared with the exporter.
"""
import collections
import math
import os
import re
import time

from robopuppet import interface

FORMAT_VERSION = 1
DEFAULT_MIN_FREE_MB = 200.0       # below this free space an episode neither starts nor goes on
NAME_PREFIX = 'episode_'
TASK_MAX_CHARS = 500              # an episode's task: one printable line of at most this many
BAG, ACTIVE, META = '.bag', '.bag.active', '.yaml'
LOCK_FILE = '.recorder.lock'      # in the episodes folder: one recorder per folder (flock)
RECORDED_IMAGE = interface.CAMERA_COMPRESSED  # what an episode holds of each camera (JPEG)
CAMERA_NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*\Z')  # a ROS name segment, e.g. room_camera
# A side's own topics (relative to interface.puppet_ns(side)).
SIDE_TOPICS = (interface.JOINT_STATES,) + tuple(
    'gripper_%d' % g for g in range(interface.NUM_GRIPPERS)) + (
    interface.USER_BUTTON, interface.OPMODE, interface.TELEOP_STATE, interface.STORED_SETTINGS)
BAXTER_TOPICS = tuple(
    [interface.limb_topic(s, 'joint_command') for s in interface.BAXTER_SIDES]
    + [interface.baxter_gripper_topic(s, n) for n in ('command', 'state')
       for s in interface.BAXTER_SIDES]
    + [interface.ROBOT_JOINT_STATES, interface.DIAGNOSTICS])

Status = collections.namedtuple('Status', 'recording episode duration_s size_bytes messages '
                                          'problem')
Status.__doc__ = """What the recorder is doing (robopuppet_msgs/RecordingState's fields):
recording (bool), episode (the bag file; the last one after a stop; '' before the first),
duration_s (s recorded), size_bytes, messages (written so far), problem ('' or why not)."""
IDLE = Status(False, '', 0.0, 0, 0, '')


def episodes_dir(ros_home):
    """Return the default episodes directory under a ROS home: <ros_home>/robopuppet/episodes."""
    return os.path.join(ros_home, 'robopuppet', 'episodes')

def parse_sides(text):
    """Return the puppet sides named in text ('R', 'LR', 'L R'), in interface order.

    Raises:
        ValueError: no side, or a character that is not a side.
    """
    letters = set(text.replace(' ', '').replace(',', '').upper())
    if not letters or not letters <= set(interface.PUPPET_SIDES):
        raise ValueError("sides must name puppet sides L and/or R, got %r" % (text,))
    return tuple(s for s in interface.PUPPET_SIDES if s in letters)


def parse_cameras(value):
    """Return the camera names of ~cameras: a list of names, or one string of names separated by
    commas or spaces ('' and [] name none); a repeated name counts once.

    Raises:
        ValueError: not a list of strings, or a string that is not a camera name.
    """
    if isinstance(value, str):
        value = value.replace(',', ' ').split()
    if not isinstance(value, (list, tuple)):
        raise ValueError('cameras must be a list of camera names, got %r' % (value,))
    for name in value:
        if not isinstance(name, str) or not CAMERA_NAME.match(name):
            raise ValueError('cameras must be camera names like %s, got %r' % (
                interface.ROOM_CAMERA, name))
    return tuple(collections.OrderedDict.fromkeys(value))


def button_topics(sides):
    """Return the user_btn topics of these puppet sides (button 4 starts and stops episodes)."""
    return tuple('%s/%s' % (interface.puppet_ns(side), interface.USER_BUTTON) for side in sides)


def recorded_topics(sides, cameras=()):
    """Return every topic an episode of these puppet sides and cameras holds: the sides', then
    Baxter's, then each camera's interface.camera_topic(camera, RECORDED_IMAGE)."""
    return (tuple('%s/%s' % (interface.puppet_ns(side), name)
                  for side in sides for name in SIDE_TOPICS) + BAXTER_TOPICS
            + tuple(interface.camera_topic(camera, RECORDED_IMAGE) for camera in cameras))


def episode_topics(sides, cameras=()):
    """Return the recorded topics subscribed only while an episode runs: all but the buttons."""
    buttons = set(button_topics(sides))
    return tuple(t for t in recorded_topics(sides, cameras) if t not in buttons)


class ButtonEdge:
    """Turn a button's readings into presses: a press acts once, a held button never repeats.

    The first reading counts as a change from 'not pressed' (user_btn is published at once on a
    change, so a first reading of the button is a press).
    """

    def __init__(self, button=interface.BUTTON_RECORD):
        self._button = button
        self._held = False

    def update(self, reading):
        """Return True when this reading (0 none, 1-4) is a new press of the button."""
        held = reading == self._button
        pressed = held and not self._held
        self._held = held
        return pressed


def episode_name(local_time, taken):
    """Return a free episode name, e.g. 'episode_20240131-142501' (or '..._2', '..._3').

    Args:
        local_time: a time.struct_time (local time of the start).
        taken(name): True when files of that name exist already.
    """
    base = NAME_PREFIX + time.strftime('%Y%m%d-%H%M%S', local_time)
    name, suffix = base, 1
    while taken(name):
        suffix += 1
        name = '%s_%d' % (base, suffix)
    return name


def files_taken(directory, name):
    """Return True when directory holds a bag, active bag or metadata file of that name."""
    return any(os.path.exists(os.path.join(directory, name + ext)) for ext in (BAG, ACTIVE, META))


def disk_problem(free_bytes, min_free_mb):
    """Return why recording must not go on with free_bytes left (min_free_mb in MB), or ''."""
    if free_bytes < min_free_mb * 1e6:
        return 'disk nearly full: %.0f MB free, recording needs at least %.0f MB' % (
            free_bytes / 1e6, min_free_mb)
    return ''


def check_task(text):
    """Return an episode's task (what the demonstration shows, for a language-conditioned
    policy) with the white space at its ends removed; '' means none.

    Raises:
        ValueError: not one line of at most TASK_MAX_CHARS printable characters.
    """
    if not isinstance(text, str):
        raise ValueError('task must be text, got %r' % (text,))
    task = text.strip()
    if any(c in task for c in '\r\n\x0b\x0c\x1c\x1d\x1e\x85\u2028\u2029'):
        raise ValueError('task must be one line: it holds a line break')
    if len(task) > TASK_MAX_CHARS:
        raise ValueError('task must be at most %d characters, got %d' % (
            TASK_MAX_CHARS, len(task)))
    bad = next((c for c in task if not c.isprintable()), None)
    if bad is not None:
        raise ValueError('task must be printable text: it holds %s at character %d' % (
            ascii(bad), task.index(bad) + 1))
    return task


def metadata(name, start_wall_s, start_stamp_s, duration_s, sides, cameras, comm_rate_hz,
             ini_fingerprints, notes, ended_cleanly, sim, topics, task=''):
    """Return an episode's metadata as the dict written to <name>.yaml.

    Args:
        start_wall_s: the start in Unix time (s), written as ISO 8601 UTC.
        start_stamp_s: the start in ROS time (s).
        duration_s: s recorded (0 at start).
        sides: the puppet sides recorded.
        cameras: the cameras recorded (their RECORDED_IMAGE topics are in the bag).
        comm_rate_hz: the puppet's state-set rate, or None when unknown.
        ini_fingerprints: {side: sha256 hex of the live ini file, or None}.
        sim: recorded against the simulated system.
        topics: {topic: message count} ({} at start).
        task: what the episode demonstrates (check_task), '' for none.
    """
    return {
        'format_version': FORMAT_VERSION,
        'name': name,
        'start_time': time.strftime('%Y-%m-%dT%H:%M:%S', time.gmtime(start_wall_s))
                      + '.%03dZ' % int(round((start_wall_s % 1.0) * 1000) % 1000),
        'start_stamp': float(start_stamp_s),
        'duration_s': float(duration_s),
        'sides': list(sides),
        'cameras': list(cameras),
        'comm_rate_hz': None if comm_rate_hz is None else float(comm_rate_hz),
        'ini_fingerprints': {side: ini_fingerprints.get(side) for side in sides},
        'notes': notes,
        'task': task,
        'ended_cleanly': bool(ended_cleanly),
        'sim': bool(sim),
        'topics': {topic: int(count) for topic, count in sorted(topics.items())},
    }


class Episode:
    """Count what one episode has written: messages per topic and bytes.

    Args:
        name: the episode's name (its files are name + BAG / ACTIVE / META).
        start_stamp_s: ROS time of the start (s).
        notes: the operator's notes.
    """

    def __init__(self, name, start_stamp_s, notes=''):
        self.name = name
        self.start_stamp_s = start_stamp_s
        self.notes = notes
        self.topics = collections.Counter()
        self.messages = 0
        self.last_stamp_s = start_stamp_s

    def count(self, topic, stamp_s):
        """Count one message written on topic at ROS time stamp_s (s)."""
        self.topics[topic] += 1
        self.messages += 1
        self.last_stamp_s = max(self.last_stamp_s, stamp_s)

    def status(self, bag_file, now_stamp_s, size_bytes, recording=True, problem=''):
        """Return the Status of this episode at ROS time now_stamp_s (s), its bag at size_bytes."""
        return Status(recording, bag_file, max(0.0, now_stamp_s - self.start_stamp_s),
                      int(size_bytes), self.messages, problem)


def status_text(status):
    """Return the one-line summary the GUI shows, e.g. 'REC 00:12, 3.4 MB'.

    status comes off the wire: a duration that is not a finite number >= 0 shows as '--:--'.
    """
    if status is None:
        return 'no recorder'
    if math.isfinite(status.duration_s) and status.duration_s >= 0:
        duration = '%02d:%02d' % divmod(int(status.duration_s), 60)
    else:
        duration = '--:--'
    size = '%s, %.1f MB' % (duration, status.size_bytes / 1e6)
    if status.recording:
        return 'REC ' + size
    if status.problem:
        return status.problem
    if status.episode:
        return 'stopped: %s (%s)' % (os.path.basename(status.episode), size)
    return 'not recording'
