"""The camera node's pure part: its parameters, where frames come from, retries and CameraInfo.

No ROS and no clock: time is passed in (monotonic seconds).
"""
import collections
import math
import os
import re

import cv2

from robopuppet import interface, params
from robopuppet.cameras import image_params

# ~parameter -> default (docs/cameras.md and launch/camera.launch list the same)
DEFAULTS = {
    'name': interface.ROOM_CAMERA,  # topics /cameras/<name>/...
    'device': '/dev/video0',        # V4L2 device, its index, or a video file
    'width': 640,                   # pixels of the published image
    'height': 480,
    'rate': 15.0,                   # Hz: images published per second
    'quality': 80,                  # JPEG quality 1..100
    'hfov_deg': 60.0,               # horizontal field of view for CameraInfo
    'frame_id': '',                 # header.frame_id; '' means <name>_optical_frame
}
MAX_RATE_HZ = 120.0
NAME_PATTERN = re.compile(r'^[A-Za-z][A-Za-z0-9_]*$')  # one ROS name segment

Settings = collections.namedtuple('Settings', 'name device width height rate_hz quality '
                                              'hfov_deg frame_id')
Settings.__doc__ = """The camera node's checked parameters (see DEFAULTS; device is an int index
or a path)."""


def parse_device(value):
    """Return a device as an int V4L2 index or a path string.

    Accepts an int (or digits, '0') as an index, '/dev/videoN' or any other path (a video file).

    Raises:
        ValueError: empty, negative, or not a string or int.
    """
    if isinstance(value, bool):
        raise ValueError('~device must be a V4L2 device, its index or a video file, got %r'
                         % (value,))
    if isinstance(value, int) or (isinstance(value, str) and value.strip().isdigit()):
        return int(value)
    if not isinstance(value, str) or not value.strip():
        raise ValueError('~device must be a V4L2 device, its index or a video file, got %r'
                         % (value,))
    return value.strip()


def read_settings(get):
    """Return the checked Settings, reading each parameter with get(name, default).

    Raises:
        ValueError: a parameter is out of range or of the wrong kind; the message names it.
    """
    raw = {name: get(name, default) for name, default in DEFAULTS.items()}
    name = raw['name']
    if not isinstance(name, str) or not NAME_PATTERN.match(name):
        raise ValueError('~name must be a camera name like room_camera, got %r' % (name,))
    rate_hz = params.positive('~rate', raw['rate'])
    if rate_hz > MAX_RATE_HZ:
        raise ValueError('~rate must be at most %g Hz, got %r' % (MAX_RATE_HZ, raw['rate']))
    hfov_deg = params.positive('~hfov_deg', raw['hfov_deg'])
    if hfov_deg >= 180.0:
        raise ValueError('~hfov_deg must be below 180 degrees, got %r' % (raw['hfov_deg'],))
    frame_id = raw['frame_id'] or '%s_optical_frame' % name
    if not isinstance(frame_id, str):
        raise ValueError('~frame_id must be a string, got %r' % (frame_id,))
    return Settings(name, parse_device(raw['device']), image_params.pixels('width', raw['width']),
                    image_params.pixels('height', raw['height']), rate_hz, image_params.quality(raw['quality']),
                    hfov_deg, frame_id)


def describe(device):
    """Return a device for log lines: '/dev/video0', 'V4L2 device 0' or the file's path."""
    return 'V4L2 device %d (/dev/video%d)' % (device, device) if isinstance(device, int) \
        else device


def is_file(device):
    """Return True when the device is a video file (played in a loop), not a V4L2 device."""
    return isinstance(device, str) and not device.startswith('/dev/')


def source(device):
    """Return (what to open, OpenCV backend) for cv2.VideoCapture(what, backend).

    V4L2 devices (an index or a /dev path) go through OpenCV's V4L2 backend, video files
    through FFmpeg: naming the backend keeps OpenCV from trying (and logging) every other one.
    """
    if isinstance(device, int) or device.startswith('/dev/'):
        return device, cv2.CAP_V4L2
    return device, cv2.CAP_FFMPEG


def missing(device, exists=os.path.exists):
    """Return why the device cannot be there ('no such device') or '' if it may be."""
    path = '/dev/video%d' % device if isinstance(device, int) else device
    return '' if exists(path) else ('no such file' if is_file(device) else 'no such device')


class Retry:
    """When to try opening a missing device again, and what to log (throttled).

    The pause after a failure doubles from first_s up to max_s; success resets it. A failure is
    logged the first time, when its reason changes and then every log_every_s.

    Attributes:
        failures: failed attempts since the device last worked (0 while it works).
        reason: why the newest attempt failed ('' while it works).
        delay_s: the pause before the next attempt.
    """

    def __init__(self, first_s=0.5, max_s=5.0, log_every_s=30.0):
        if not 0.0 < first_s <= max_s:
            raise ValueError('need 0 < first_s <= max_s, got %r, %r' % (first_s, max_s))
        self.first_s, self.max_s, self.log_every_s = first_s, max_s, log_every_s
        self.failures, self.reason, self.delay_s = 0, '', 0.0
        self._next_s = -math.inf
        self._logged_s = None

    def due(self, now_s):
        """Return True when the next attempt to open the device is due."""
        return now_s >= self._next_s

    def failed(self, now_s, reason):
        """Count a failed attempt (or a lost device); return a log line, or None to stay quiet."""
        changed = reason != self.reason
        self.failures += 1
        self.delay_s = min(self.first_s * 2 ** (self.failures - 1), self.max_s)
        self._next_s = now_s + self.delay_s
        self.reason = reason
        if changed or self._logged_s is None or now_s - self._logged_s >= self.log_every_s:
            self._logged_s = now_s
            return '%s; retrying (attempt %d, next in %.1f s)' % (reason, self.failures,
                                                                  self.delay_s)
        return None

    def succeeded(self):
        """Reset after the device delivered; return how many attempts had failed before."""
        failures = self.failures
        self.failures, self.reason, self.delay_s = 0, '', 0.0
        self._next_s, self._logged_s = -math.inf, None
        return failures


CameraModel = collections.namedtuple('CameraModel', 'width height K D R P')
CameraModel.__doc__ = """sensor_msgs/CameraInfo's fields of an ideal pinhole camera (row-major
lists; D: plumb_bob's five coefficients, all 0: no distortion)."""


def camera_model(width, height, hfov_deg):
    """Return the CameraModel of a distortion-free camera of this size and horizontal view.

    Square pixels (fy = fx), the principal point at the image centre.
    """
    if not 0.0 < hfov_deg < 180.0:
        raise ValueError('hfov_deg must be in (0, 180), got %r' % (hfov_deg,))
    fx = (width / 2.0) / math.tan(math.radians(hfov_deg) / 2.0)
    cx, cy = width / 2.0, height / 2.0
    return CameraModel(width, height, [fx, 0.0, cx, 0.0, fx, cy, 0.0, 0.0, 1.0],
                       [0.0] * 5, [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
                       [fx, 0.0, cx, 0.0, 0.0, fx, cy, 0.0, 0.0, 0.0, 1.0, 0.0])
