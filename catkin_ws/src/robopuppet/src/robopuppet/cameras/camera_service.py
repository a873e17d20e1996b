"""Baxter's camera service as the stand-in answers it: which cameras have power, which stream, at
what size and rate, and the err code and log line of every refusal.

A real Baxter (SDK 1.1 and later) powers two of its three cameras at a time. /cameras/list names
only the cameras with power, so a third cannot be opened: it is refused, never made to close
another. Closing a camera takes its power and gives it to the camera that had none (Rethink's
baxter_interface commit 8501e87, SDK 1.2.0 baxter_tools smoketests.py): a camera closed while
another lacks power is listed again only after another camera is closed. At start the two hand
cameras have power and stream (smoketests.py's defaults), the head camera has none. A camera of
the room is not Baxter's: it is never listed, never opened or closed, and always streams while
watched. Pure: no ROS; times are arguments.
"""
import collections
import errno
import math
import reprlib

from robopuppet import interface

# Baxter's camera modes (width, height) in pixels: Rethink's SDK 1.2.0 CameraController.MODES.
BAXTER_MODES = ((1280, 800), (960, 600), (640, 400), (480, 300), (384, 240), (320, 200))
MAX_POWERED = 2      # cameras with power at once
MAX_FPS = 30.0       # frames/s: the most the stand-in accepts (Rethink's simulator's cameras)
# Which of Baxter's cameras get power first at start: the hand cameras, then the head.
POWER_ORDER = ('left_hand_camera', 'right_hand_camera', 'head_camera')
assert sorted(POWER_ORDER) == sorted(interface.BAXTER_CAMERAS)
# The err codes of OpenCamera and CloseCamera (errno values; CameraController.close takes
# EINVAL as "was not open").
OK = 0
NO_CAMERA = errno.ENODEV   # not a camera of this Baxter, or one without power
BAD_SETTINGS = errno.EINVAL  # a size Baxter has not, or a rate out of range
NOT_OPEN = errno.EINVAL    # close of a camera that does not stream

Mode = collections.namedtuple('Mode', 'width height fps')
Mode.__doc__ = """A streaming camera's image size (pixels) and frames per second."""
Answer = collections.namedtuple('Answer', 'err line')
Answer.__doc__ = """A service call's err code (OK or an errno value) and its log line."""


class CameraService:
    """Open and close the stand-in's cameras as a Baxter does (see the module's docstring).

    Args:
        names: the stand-in's cameras: Baxter's (interface.BAXTER_CAMERAS) and room cameras.
        start_mode: the Mode each camera streams at from the start (the node's parameters).
    """

    def __init__(self, names, start_mode):
        self._baxter = [n for n in POWER_ORDER if n in names]
        self._room = [n for n in names if n not in interface.BAXTER_CAMERAS]
        self._powered = self._baxter[:MAX_POWERED]
        self._modes = {n: start_mode for n in self._powered + self._room}
        self._next_s = {}

    def cameras(self):
        """Return /cameras/list's answer: Baxter's cameras that have power."""
        return list(self._powered)

    def streaming(self):
        """Return {name: Mode} of the cameras that stream (while watched)."""
        return dict(self._modes)

    def open(self, name, width, height, fps):
        """Start (or restart with new settings) a camera; return an Answer."""
        refused = self._refusal('open', name)
        if refused:
            return refused
        if (width, height) not in BAXTER_MODES:
            return Answer(BAD_SETTINGS, 'open %s: %sx%s is not a mode of Baxter\'s cameras (%s)'
                          % (name, width, height, modes_text()))
        if not (isinstance(fps, (int, float)) and math.isfinite(fps) and 0.0 < fps <= MAX_FPS):
            return Answer(BAD_SETTINGS, 'open %s: %r frames/s is out of range: more than 0 and '
                          'at most %g' % (name, fps, MAX_FPS))
        again = name in self._modes
        self._modes[name] = Mode(width, height, float(fps))
        self._next_s.pop(name, None)
        return Answer(OK, '%s %s at %dx%d, %g frames/s' % (
            name, 'opened again' if again else 'opened', width, height, fps))

    def close(self, name):
        """Stop a camera's images; hand its power to a camera without any; return an Answer."""
        if name in self._baxter and name not in self._powered:
            return Answer(NOT_OPEN, 'close %s: it is not open (it has no power)' % name)
        refused = self._refusal('close', name)
        if refused:
            return refused
        if name not in self._modes:
            return Answer(NOT_OPEN, 'close %s: it is not open' % name)
        del self._modes[name]
        self._next_s.pop(name, None)
        unpowered = [n for n in self._baxter if n not in self._powered]
        if not unpowered:
            return Answer(OK, '%s closed' % name)
        self._powered = [n for n in self._baxter if n != name]
        return Answer(OK, '%s closed; its power went to %s (now listed: %s)' % (
            name, ', '.join(unpowered), ', '.join(self._powered)))

    def due(self, name, now_s):
        """Return whether a streaming camera's next frame is due at now_s (s, any clock), and
        if so count it: frames come at the camera's fps, a late one is not made up twice."""
        mode = self._modes.get(name)
        if mode is None:
            return False
        next_s = self._next_s.get(name)
        if next_s is not None and now_s < next_s:
            return False
        period_s = 1.0 / mode.fps
        next_s = now_s + period_s if next_s is None else next_s + period_s
        # More than a period behind (nobody watched for a while): start afresh from now.
        self._next_s[name] = next_s if next_s > now_s else now_s + period_s
        return True

    def _refusal(self, verb, name):
        """Return the Answer refusing a camera that is not Baxter's or has no power, else None."""
        if name in self._room:
            return Answer(NO_CAMERA, '%s %s: not one of Baxter\'s cameras (it streams whenever '
                          'watched)' % (verb, name))
        if name not in self._baxter:
            return Answer(NO_CAMERA, '%s %s: no such camera; this Baxter has %s' % (
                verb, reprlib.repr(name), ', '.join(self._baxter) or 'none'))
        if name not in self._powered:
            return Answer(NO_CAMERA, '%s %s: it has no power: a Baxter powers two cameras at '
                          'once (%s); close one of them first' % (
                              verb, name, ', '.join(self._powered)))
        return None


def modes_text():
    """Return Baxter's modes as text, e.g. '1280x800, 960x600, ...'."""
    return ', '.join('%dx%d' % mode for mode in BAXTER_MODES)
