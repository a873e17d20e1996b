"""Camera frames of an episode onto the export's time grid, for ALOHA's
/observations/images/<camera>.

Pure (OpenCV and numpy, no ROS, no HDF5): frames come in as (camera, t, JPEG bytes) in time
order, t in s on the grid's clock; out come runs (camera, start, stop, image): grid steps
start..stop-1 show image, an RGB uint8 array (H, W, 3). Zero-order hold: each step shows the
newest frame at or before its time; steps before a camera's first frame show that first frame.
A frame is decoded only if a step shows it, and once however many steps show it, so memory
holds one decoded image and one JPEG per camera whatever the episode's length.

Images can be scaled to one size (W, H) for every camera (ACT stacks the cameras' images, so
they must match): decoded frames are resized with OpenCV's INTER_AREA (pixel averaging).

A frame that does not decode, or whose recorded size differs from the camera's first good
frame, is skipped (the steps keep the frame before it) and counted in report(); a camera none
of whose shown frames decodes raises ExportError.
"""
import collections
import re

import cv2
import numpy as np

from robopuppet.episodes.export import ExportError
from robopuppet.episodes.recording import RECORDED_IMAGE
from robopuppet.interface import camera_topic

_FRAME_TOPIC_RE = re.compile('^%s$' % re.escape(camera_topic('@', RECORDED_IMAGE)).replace(
    '@', '([^/]+)'))

Run = collections.namedtuple('Run', 'camera start stop image')
Run.__doc__ = """Grid steps start..stop-1 of camera show image (H, W, 3) uint8 RGB."""


def frame_topic(camera):
    """Return the topic of a camera's recorded frames: /cameras/<camera>/image/compressed
    (sensor_msgs/CompressedImage, JPEG)."""
    return camera_topic(camera, RECORDED_IMAGE)


def camera_of(topic):
    """Return the camera whose frames a topic carries, None for any other topic."""
    match = _FRAME_TOPIC_RE.match(topic)
    return match.group(1) if match else None


def decode(data):
    """Return a JPEG (or PNG) as an RGB uint8 image (H, W, 3), None when it does not decode."""
    try:
        bgr = cv2.imdecode(np.frombuffer(bytes(data), np.uint8), cv2.IMREAD_COLOR)
    except cv2.error:  # e.g. an empty frame: "!buf.empty() in function 'imdecode_'"
        return None
    return None if bgr is None else cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)


def scale(image, size):
    """Return an image (H, W, 3) scaled to size (W, H) by pixel averaging (None: as it is)."""
    if size is None or (image.shape[1], image.shape[0]) == tuple(size):
        return image
    return cv2.resize(image, tuple(size), interpolation=cv2.INTER_AREA)


class _Camera:
    """One camera's hold: the newest good decoded image and the newest frame not decoded yet."""

    def __init__(self):
        self.next_step = 0  # the first grid step not handed out yet
        self.image = None
        self.shape = None  # of its first good frame as recorded
        self.pending = None  # (t, bytes) of the newest frame
        self.first_t = None  # time of the first good frame (s)
        self.skipped = collections.OrderedDict()  # reason -> [count, time of the first]

    def skip(self, reason, t_s):
        entry = self.skipped.setdefault(reason, [0, t_s])
        entry[0] += 1


class ImageResampler:
    """Hold each camera's frames onto the grid (see the module docstring).

    Args:
        grid_s: the grid's times (T,), s, ascending, on the frames' clock.
        size: (W, H) in pixels that every image is scaled to; None: as recorded.
    """

    def __init__(self, grid_s, size=None):
        self._grid = np.asarray(grid_s, float)
        self._size = tuple(size) if size else None
        self._cameras = collections.OrderedDict()

    @property
    def cameras(self):
        """The cameras that sent frames, in the order of their first frame."""
        return list(self._cameras)

    def add(self, camera, t_s, data):
        """Take a camera's frame received at t_s (s); return the runs it completes."""
        state = self._cameras.setdefault(camera, _Camera())
        runs = self._flush(camera, state, int(np.searchsorted(self._grid, t_s, side='left')))
        state.pending = (t_s, data)
        return runs

    def finish(self):
        """Return the runs up to the last grid step of every camera.

        Raises:
            ExportError: a camera without any frame that decodes.
        """
        runs = []
        for camera, state in self._cameras.items():
            runs += self._flush(camera, state, len(self._grid))
            if state.image is None:
                raise ExportError('%s: none of its frames decodes (%s)'
                                  % (camera, self._skipped_text(state)))
        return runs

    def report(self):
        """Return lines for the user: the cameras, each camera's first frame if it came after
        the first step, and the frames skipped."""
        lines = ['images of %s, %d steps each' % (', '.join(self._cameras), len(self._grid))
                 if self._cameras else 'no camera images']
        for camera, state in self._cameras.items():
            if state.first_t is not None and state.first_t > self._grid[0]:
                lines.append('%s: first frame at %.3f s: the steps before show it'
                             % (camera, state.first_t - self._grid[0]))
            if state.skipped:
                lines.append('%s: skipped %s; the steps keep the frame before'
                             % (camera, self._skipped_text(state)))
        return lines

    def _flush(self, camera, state, stop):
        """Hand out steps next_step..stop-1 with the newest good frame (decoding the pending
        one); none while no good frame came yet, so the first good one covers those too."""
        if stop <= state.next_step:
            return []
        if state.pending is not None:
            t_s, data = state.pending
            state.pending = None
            image = decode(data)
            if image is None:
                state.skip('frames that do not decode', t_s)
            elif state.shape is not None and image.shape != state.shape:
                state.skip('frames of %dx%d, not %dx%d' % (
                    image.shape[1], image.shape[0], state.shape[1], state.shape[0]), t_s)
            else:
                if state.image is None:
                    state.first_t, state.shape = t_s, image.shape
                state.image = scale(image, self._size)
        if state.image is None:
            return []
        run = Run(camera, state.next_step, stop, state.image)
        state.next_step = stop
        return [run]

    def _skipped_text(self, state):
        return ', '.join('%s: %d (the first at %.3f s)' % (reason, count, t_s - self._grid[0])
                         for reason, (count, t_s) in state.skipped.items()) or 'no frames'
