"""The receive side of the puppet's link: whole, plausible state sets and healthy heartbeats.

Pure (sans-I/O): bytes and the time go in, events come out; no clock, no port, no rospy.

The 2020 firmware's checksum is an 8-bit sum of the payload only and its heartbeat is A5 00 00,
so line noise decodes into frames that pass codec.Decoder. This layer adds what the host can:

- **Plausibility** of every field: the decoder already refuses a joint, status, gripper or
  button number out of range and any non-finite float; here an angle must lie in [-pi, pi]
  (float32 rounding allowed), a motor voltage within the limits the device holds (widened to
  0 V, what a limp device reports) plus VOLTAGE_MARGIN_V, and a gripper reading in [0, 1]. An
  implausible frame is dropped, counted and described in `last_problem`.
- **Structure.** The firmware sends a state set in one burst: joint states 0..6, grippers 0..3,
  then the buttons (SET_ORDER). A set is returned only when all twelve frames arrive in that
  order, each on a clean frame boundary (no byte dropped before it), within SET_SPAN_S of its
  joint 0. Anything else drops the set in progress (counted); the next joint 0 starts over.
- **Heartbeats** count only on a healthy line. A heartbeat counts when a whole set completed
  at most HEARTBEAT_SET_WINDOW_S before it, no heartbeat counted since that set, the last
  counted one is at least HEARTBEAT_SPACING_S old, and it sits on a clean frame boundary on
  at least one side: right after a frame that fit (nothing dropped between), or right before
  one (then it is returned when that frame arrives). On a dead line noise can count none; on
  a live one a noise heartbeat must touch a real frame and still cannot raise the rate above
  one per HEARTBEAT_SPACING_S.
"""
import collections
import math

from robopuppet import interface, settings
from robopuppet.protocol import codec

# An angle is wrapped to [-pi, pi] by the firmware; float32(pi) is a little above math.pi.
ANGLE_LIMIT_RAD = math.pi + 1e-6
# The device clamps its PID output to [voltage_min, voltage_max]; the margin covers a frame in
# flight while the host changes the limits.
VOLTAGE_MARGIN_V = 0.5
# The firmware writes a set (127 bytes, 11 ms at 115200 baud) in one burst; a set spread over
# longer than this is frames of different bursts (e.g. across a reconnect).
SET_SPAN_S = 1.0
# The firmware sends sets at 10 Hz and a heartbeat at 1 Hz: a real heartbeat always follows a
# whole set by at most 0.1 s, and comes 1 s after the one before.
HEARTBEAT_SET_WINDOW_S = 1.5
HEARTBEAT_SPACING_S = 0.8  # the firmware sends one every 1 s

# The frames of one state set, in the order the firmware sends them: (type, index field).
SET_ORDER = (tuple((codec.JointState, j) for j in settings.JOINTS)
             + tuple((codec.Gripper, g) for g in range(interface.NUM_GRIPPERS))
             + ((codec.Buttons, None),))
_POSITION = {key: index for index, key in enumerate(SET_ORDER)}
_INDEX_FIELD = {codec.JointState: 'joint', codec.Gripper: 'gripper', codec.Buttons: None}

# Fixed plausible ranges of float fields; a joint's voltage range comes from its settings.
PLAUSIBLE_RANGES = {
    (codec.JointState, 'angle_rad'): (-ANGLE_LIMIT_RAD, ANGLE_LIMIT_RAD),
    (codec.Gripper, 'reading'): (0.0, 1.0),
}

StateSet = collections.namedtuple('StateSet', 'start_s joints grippers button')
StateSet.__doc__ = """One whole state set: start_s (time its joint 0 arrived), joints (seven
codec.JointState, joint order), grippers (four readings 0-1), button (0 none, 1-4)."""


class Receiver:
    """Turn received bytes into StateSet events and counted heartbeats (codec.Heartbeat()).

    Args:
        voltage_limits(joint): return (voltage_min, voltage_max) in V that the device holds for
            a joint; called for every joint state frame.
        decoder: the codec.Decoder to use (default: a new one for device->host frames).
    Counters (totals): sets, dropped_sets (begun, with at least joints 0 and 1, but not
    completed cleanly), stray_frames (state frames outside any set, and a joint 0 not followed
    by joint 1), implausible_frames, heartbeats (counted), refused_heartbeats.
    last_problem describes the newest implausible or invalid frame ('' before any).
    """

    def __init__(self, voltage_limits, decoder=None):
        self._voltage_limits = voltage_limits
        self.decoder = decoder or codec.Decoder(codec.types_sent_by(codec.TO_HOST))
        self._parts = []  # frames of the set in progress
        self._start_s = None
        self._set_end_s = None  # time the newest whole set completed
        self._heartbeat_due = False  # no heartbeat counted since that set
        self._heartbeat_s = None  # time of the newest counted heartbeat
        self._pending_heartbeat = False  # clean only if the next frame follows it cleanly
        self._previous_fits = False  # the newest frame was plausible and in place
        self._invalid_seen = 0
        self.sets = self.dropped_sets = self.stray_frames = self.implausible_frames = 0
        self.heartbeats = self.refused_heartbeats = 0
        self.last_problem = ''

    def feed(self, data, now_s):
        """Add bytes received at now_s (monotonic s); return the events they complete."""
        events = []
        for message, skipped in self.decoder.feed_frames(data):
            self._on_frame(message, skipped, now_s, events)
        if self.decoder.invalid_frames != self._invalid_seen:
            self._invalid_seen = self.decoder.invalid_frames
            self.last_problem = self.decoder.last_invalid
        return events

    def problem(self, message):
        """Return why a decoded message is implausible, or None if it is plausible."""
        kind = type(message)
        for name, value in zip(kind._fields, message):
            if not isinstance(value, float):
                continue
            if kind is codec.JointState and name == 'voltage_v':
                # 0 V too: a limp device reports 0 V whatever its limits (a range such as
                # [1, 1] V is allowed), and refusing that would drop every set it sends.
                low, high = self._voltage_limits(message.joint)
                low, high = min(low, 0.0) - VOLTAGE_MARGIN_V, max(high, 0.0) + VOLTAGE_MARGIN_V
            else:
                low, high = PLAUSIBLE_RANGES.get((kind, name), (-math.inf, math.inf))
            if not low <= value <= high:  # also refuses NaN
                return '%s.%s = %r is outside [%g, %g]' % (kind.__name__, name, value, low, high)
        return None

    def _on_frame(self, message, skipped, now_s, events):
        if skipped:
            self._drop_set()  # bytes lost inside a set: it is not whole
        kind = type(message)
        problem = self.problem(message)
        position = None
        if problem:
            self.implausible_frames += 1
            self.last_problem = problem
            fits = False
        elif kind is codec.Heartbeat:
            fits = True  # a heartbeat may come between any two frames
        else:
            field = _INDEX_FIELD.get(kind)
            position = _POSITION.get((kind, getattr(message, field) if field else None))
            fits = position == 0 or (self._parts and position == len(self._parts)
                                     and now_s - self._start_s <= SET_SPAN_S)
        if self._pending_heartbeat:  # a heartbeat after dropped bytes: decided by what follows
            self._pending_heartbeat = False
            self._heartbeat(fits and not skipped, now_s, events)
        if kind is codec.Heartbeat and not problem:
            if not skipped and self._previous_fits:
                self._heartbeat(True, now_s, events)
            elif self._heartbeat_allowed(now_s):
                self._pending_heartbeat = True
            else:
                self.refused_heartbeats += 1
        elif not fits:  # implausible, out of order or too late: it cannot be part of a set
            if not self._drop_set():
                self.stray_frames += position is not None
        else:
            if position == 0:
                self._drop_set()
                self._parts, self._start_s = [], now_s
            self._parts.append(message)
            if len(self._parts) == len(SET_ORDER):
                self._complete_set(now_s, events)
        self._previous_fits = fits

    def _complete_set(self, now_s, events):
        joints = tuple(self._parts[:settings.NUM_JOINTS])
        grippers = tuple(m.reading for m in self._parts[settings.NUM_JOINTS:-1])
        events.append(StateSet(self._start_s, joints, grippers, self._parts[-1].button))
        self._parts = []
        self.sets += 1
        self._set_end_s = now_s
        self._heartbeat_due = True

    def _heartbeat_allowed(self, now_s):
        return (self._heartbeat_due and now_s - self._set_end_s <= HEARTBEAT_SET_WINDOW_S
                and (self._heartbeat_s is None
                     or now_s - self._heartbeat_s >= HEARTBEAT_SPACING_S))

    def _heartbeat(self, clean, now_s, events):
        """Count a heartbeat (append it to events) if it is clean and allowed now."""
        if clean and self._heartbeat_allowed(now_s):
            self._heartbeat_due = False
            self._heartbeat_s = now_s
            self.heartbeats += 1
            events.append(codec.Heartbeat())
        else:
            self.refused_heartbeats += 1

    def _drop_set(self):
        """Drop the set in progress, if any; return True if there was one.

        It counts as a dropped set once it has two frames; a lone joint 0 counts as a stray
        frame (noise such as A5 20 and ten zeros makes a plausible joint 0 on its own).
        """
        if not self._parts:
            return False
        if len(self._parts) > 1:
            self.dropped_sets += 1
        else:
            self.stray_frames += 1
        self._parts = []
        return True
