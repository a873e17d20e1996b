"""What the camera pane shows, decided without Qt or ROS: the frame kept, frames/s, age, colour.

The camera client's ROS callback (any thread) decodes each JPEG and puts it in a FrameSlot;
the GUI thread takes the newest once per frame and asks judge() how healthy the stream is.
Times are ROS seconds passed in (a frame's age is now minus its header stamp); no clock here.
"""
import collections
import threading

import cv2
import numpy as np

from robopuppet import interface

# ---- the thresholds of the pane's colour (one place) -----------------------------------------
AGE_WARN_S = 0.3     # the frame shown was captured longer ago than this: amber
AGE_ERROR_S = 1.0    # ... red: what the nurse sees is no longer what happens
STALL_WARN_S = 0.5   # no new frame for this long: amber (the stream stutters or stops)
STALL_ERROR_S = 2.0  # ... red: the stream has stopped
FUTURE_WARN_S = 0.3  # a stamp this far ahead of now: the two hosts' clocks differ (amber)
RATE_WINDOW_S = 2.0  # frames/s counts the frames received in this window

OK, WARN, ERROR = 0, 1, 2  # diagnostic_msgs levels, as the other status boxes use them

Frame = collections.namedtuple('Frame', 'image stamp_s received_s seq')
Frame.__doc__ = """A decoded camera frame: image (numpy BGR, height x width x 3, uint8), stamp_s
(its header stamp: capture time), received_s (when it arrived) and seq (1, 2, ... per slot)."""

Verdict = collections.namedtuple('Verdict', 'level text')
Verdict.__doc__ = """The stream's health: level (OK, WARN or ERROR: green, amber, red) and a
short text for the operator."""


def decode(data):
    """Return a JPEG's (or PNG's) pixels as a BGR numpy image.

    Raises:
        ValueError: the bytes are not an image OpenCV can decode.
    """
    try:
        image = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR) if data else None
    except cv2.error:  # OpenCV raises for some bad buffers and returns None for others
        image = None
    if image is None:
        raise ValueError('not a decodable image (%d bytes)' % len(data))
    return image


class FrameSlot:
    """The newest decoded frame of one camera and the receive times for frames/s. Thread-safe.

    Only the newest frame is kept: a GUI that draws slower than frames arrive skips frames
    instead of queueing them (memory stays bounded, and the image shown stays fresh).
    """

    def __init__(self, window_s=RATE_WINDOW_S, capacity=256):
        self._lock = threading.Lock()
        self._window_s = window_s
        self._frame = None
        self._seq = 0
        self._received = collections.deque(maxlen=capacity)
        self.bad = 0  # frames that could not be decoded
        self.last_problem = ''

    def put(self, image, stamp_s, received_s):
        """Keep a decoded frame as the newest."""
        with self._lock:
            self._seq += 1
            self._frame = Frame(image, stamp_s, received_s, self._seq)
            self._received.append(received_s)

    def put_bad(self, problem):
        """Count a frame that could not be decoded."""
        with self._lock:
            self.bad += 1
            self.last_problem = problem

    def newest(self):
        """Return the newest Frame, or None before the first."""
        with self._lock:
            return self._frame

    def rate_hz(self, now_s, since_s):
        """Return the frames per second received over the last RATE_WINDOW_S before now_s
        (over less when the subscription is younger: since_s is when it started)."""
        span_s = min(self._window_s, now_s - since_s)
        if span_s <= 0.0:
            return 0.0
        with self._lock:
            count = sum(1 for t in self._received if now_s - self._window_s < t <= now_s)
        return count / span_s


def _level(value_s, warn_s, error_s):
    return ERROR if value_s > error_s else WARN if value_s > warn_s else OK


def duration(seconds):
    """Return a duration for the operator: '45 ms', '1.4 s', '12 s'."""
    if seconds < 1.0:
        return '%.0f ms' % (seconds * 1000.0)
    return '%.1f s' % seconds if seconds < 10.0 else '%.0f s' % seconds


def judge(now_s, frame, subscribed_s):
    """Return the Verdict on a stream: the newest Frame (or None) at now_s, subscribed since
    subscribed_s (None: not subscribed, e.g. no camera chosen)."""
    if subscribed_s is None:
        return Verdict(WARN, 'no camera chosen')
    if frame is None:
        waited_s = max(now_s - subscribed_s, 0.0)
        if waited_s <= STALL_ERROR_S:
            return Verdict(WARN, 'waiting for frames')
        return Verdict(ERROR, 'no frames for %s' % duration(waited_s))
    age_s, stall_s = now_s - frame.stamp_s, max(now_s - frame.received_s, 0.0)
    if age_s < -FUTURE_WARN_S:
        return Verdict(WARN, 'stamped %s ahead: are the hosts\' clocks synchronised?'
                       % duration(-age_s))
    age_level = _level(age_s, AGE_WARN_S, AGE_ERROR_S)
    stall_level = _level(stall_s, STALL_WARN_S, STALL_ERROR_S)
    if stall_level:  # frames do not come: stopped, however old the last one was
        return Verdict(max(stall_level, age_level),
                       'stopped: no new frame for %s' % duration(stall_s))
    if age_level:
        return Verdict(age_level, 'late: the frame shown is %s old' % duration(age_s))
    return Verdict(OK, 'live')


def own_camera(baxter_arm):
    """Return the hand camera of Baxter's arm 'left' or 'right': the camera an operator
    driving that arm looks through first."""
    return interface.hand_camera(baxter_arm)


def camera_list(published_topics, known=()):
    """Return [(camera name, published)] for the chooser: the cameras whose image/compressed
    topic the master knows (published, sorted), then the known names not published yet.

    Args:
        published_topics: [(topic, type)] as rospy.get_published_topics() returns them.
        known: camera names always offered (Baxter's and the room camera).
    """
    live = sorted({interface.camera_of_topic(topic, interface.CAMERA_COMPRESSED)
                   for topic, kind in published_topics
                   if kind == 'sensor_msgs/CompressedImage'} - {None})
    return [(name, True) for name in live] + [(name, False) for name in known
                                              if name not in live]
