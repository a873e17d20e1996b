"""What serial_X sends the puppet, in which order and in which writes (pure: no rospy, no clock).

The rules come from the real 2020 firmware (its code, doates625/RoboPuppet; docs/serial.md):
- It stores home_angle x the sign_angle in force when the home frame arrives, so sign_angle
  (and sign_motor) go before home_angle, and home_angle again after any change of sign_angle:
  loading the same settings twice then changes nothing.
- It reads a frame whole as soon as its start byte is in: a frame split across two 64-byte USB
  packets is garbage. So the host writes whole frames in writes of at most one packet, and
  writes that add up to more than a packet at least LOAD_PAUSE_S apart (WritePacer), so that
  no packet can hold the end of one frame and the start of another.
- On hold it keeps the setpoints it has, and limp (and power-on) set them to 0 rad. So a hold
  goes out only after seven setpoints; the missing ones are the current reported angles.
- Its state rate is a compile-time constant (10 Hz in 2020); ~comm_rate does not change it, so
  the node only checks that the two agree.
"""
import collections
import math

from robopuppet import settings
from robopuppet.protocol import codec

USB_PACKET_BYTES = 64  # full-speed USB bulk packet of the Teensy's serial port
LOAD_PAUSE_S = 0.005  # between two settings writes: one packet at a time reaches the device
RATE_TOLERANCE = 0.2  # measured state-set rate vs ~comm_rate, as a fraction of ~comm_rate

# Signs first: home_angle is stored with the sign in force when it arrives.
LOAD_ORDER = settings.SIGNS + tuple(n for n in settings.NAMES if n not in settings.SIGNS)


def settings_to_send(stored, held=None):
    """Return [(name, value)] that make a device holding `held` hold `stored`, in LOAD_ORDER.

    Args:
        stored: {name: value} of one joint, as the config node stored it.
        held: {name: value} the device holds, or None for a full load (every value).
    Every value that differs is sent; after a change of sign_angle home_angle is sent again
    (with its stored value), since the device stored it with the old sign.
    """
    if held is None:
        names = set(settings.NAMES)
    else:
        names = {n for n in settings.NAMES if stored[n] != held[n]}
        if 'sign_angle' in names:
            names.add('home_angle')
    return [(n, stored[n]) for n in LOAD_ORDER if n in names]


def pack(frames, limit=USB_PACKET_BYTES):
    """Return the writes that carry encoded frames in order: whole frames, each write <= limit.

    Raises:
        ValueError: a frame is longer than limit.
    """
    writes, current = [], b''
    for frame in frames:
        if len(frame) > limit:
            raise ValueError('a %d-byte frame does not fit in a %d-byte write'
                             % (len(frame), limit))
        if len(current) + len(frame) > limit:
            writes.append(current)
            current = b''
        current += frame
    if current:
        writes.append(current)
    return writes


class WritePacer:
    """Say how long a write must wait so that writes adding up to more than a packet are at
    least gap_s apart (time is an argument; the caller sleeps and serialises the writes).

    Writes (each of whole frames, at most one packet) that follow each other within gap_s form
    a group of at most packet_bytes; the write that would make the group larger waits until
    gap_s after the group's last write and starts the next group. A stack or a simulator that
    merges back-to-back writes (a pty keeps no write boundaries; puppet_sim's USB packet model
    cuts what arrived within 1.5 ms every 64 bytes) then never cuts a frame: e.g. a hold's 60
    bytes of setpoints and opmode, and then arm_X's setpoints from other topics at once.
    """

    def __init__(self, packet_bytes=USB_PACKET_BYTES, gap_s=LOAD_PAUSE_S):
        self._packet_bytes, self._gap_s = packet_bytes, gap_s
        self._group_bytes = 0
        self._last_s = -math.inf  # the group's last write

    def delay_s(self, now_s, size):
        """Return the seconds a write of `size` bytes must wait at now_s (0: none)."""
        if now_s - self._last_s >= self._gap_s or self._group_bytes + size <= self._packet_bytes:
            return 0.0
        return self._last_s + self._gap_s - now_s

    def wrote(self, now_s, size):
        """A write of `size` bytes went out at now_s."""
        if now_s - self._last_s >= self._gap_s or \
                self._group_bytes + size > self._packet_bytes:
            self._group_bytes = 0
        self._group_bytes += size
        self._last_s = now_s


HoldPlan = collections.namedtuple('HoldPlan', 'messages refusal')


class HoldGate:
    """Keep track of the setpoints the device holds, so that a hold never drives it to 0 rad.

    `epoch` is a number that the caller raises whenever the device may have lost its setpoints
    (a (re)connect, a limp sent by the settings load); the gate forgets setpoints and angles of
    older epochs. Each method takes the epoch read *before* the write it is about, so that a
    setpoint written across an epoch change is forgotten (then the hold re-sends an angle: safe)
    rather than believed (then the device could hold 0 rad).
    Not thread-safe: the caller serialises plan_hold/record with its writes.
    """

    def __init__(self):
        self._epoch = 0
        self._sent = set()  # joints with a setpoint since the last limp/connect
        self._angles = None  # the newest reported angles of this epoch

    def _current(self, epoch):
        """Move to `epoch` if it is newer; return False if it is older (stale news)."""
        if epoch > self._epoch:
            self._epoch, self._sent, self._angles = epoch, set(), None
        return epoch == self._epoch

    def on_angles(self, angles_rad, epoch):
        """The device reported a whole set of joint angles (settings loaded)."""
        if self._current(epoch):
            self._angles = tuple(angles_rad)

    def plan_hold(self, epoch, setpoints=()):
        """Return HoldPlan(messages, None) to send for a hold, or (None, why it is refused).

        The messages are `setpoints` (codec.JointSetpoint), a setpoint at the current angle for
        each other joint without a setpoint since the last limp/connect, then the hold opmode.
        """
        self._current(epoch)
        given = {m.joint for m in setpoints}
        missing = [j for j in settings.JOINTS if j not in self._sent and j not in given]
        if missing and self._angles is None:
            return HoldPlan(None, 'no setpoint since the last limp or connect for joints %s and '
                            'no current angles (settings not loaded or no joint state yet); '
                            'the firmware would drive them to 0 rad' % missing)
        messages = [codec.JointSetpoint(j, self._angles[j]) for j in missing]
        return HoldPlan(list(setpoints) + messages + [codec.Opmode(codec.HOLD)], None)

    def record(self, messages, epoch):
        """These messages were written: note setpoints; a limp zeroes the device's setpoints."""
        if not self._current(epoch):
            return
        for message in messages:
            if isinstance(message, codec.JointSetpoint):
                self._sent.add(message.joint)
            elif isinstance(message, codec.Opmode) and message.mode != codec.HOLD:
                self._sent.clear()


class RateMeter:
    """Measure how many events per second arrived over the last window_s (time is an argument)."""

    def __init__(self, window_s=5.0):
        self._window_s = window_s
        self._times = collections.deque()
        self._since_s = None  # when counting started (or restarted)

    def restart(self, now_s):
        """Forget what was counted (e.g. the stream stopped on purpose)."""
        self._times.clear()
        self._since_s = now_s

    def add(self, now_s):
        """An event happened at now_s."""
        if self._since_s is None:
            self._since_s = now_s
        self._times.append(now_s)
        self._trim(now_s)

    def rate_hz(self, now_s):
        """Return events per second over the last window, or None before a whole window."""
        if self._since_s is None or now_s - self._since_s < self._window_s:
            return None
        self._trim(now_s)
        return len(self._times) / self._window_s

    def _trim(self, now_s):
        while self._times and self._times[0] <= now_s - self._window_s:
            self._times.popleft()


def rate_problem(measured_hz, expected_hz, tolerance=RATE_TOLERANCE):
    """Return why a measured state-set rate disagrees with ~comm_rate, or None if it agrees.

    None also when either is unknown (None or expected not positive).
    """
    if measured_hz is None or not expected_hz or expected_hz <= 0.0:
        return None
    if abs(measured_hz - expected_hz) <= tolerance * expected_hz:
        return None
    return ('state sets arrive at %.1f Hz, but comm_rate is %.1f Hz (more than %.0f %% off): '
            'a real puppet\'s firmware rate is a compile-time constant (10 Hz in 2020), so set '
            'comm_rate to match it; a simulated puppet sends at comm_rate, so there the machine '
            'is too loaded to keep up (free some CPU)' % (measured_hz, expected_hz,
                                                         tolerance * 100))
