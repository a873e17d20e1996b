"""Feel mode as serial_X runs it: its start on the feel gains, and its setpoint watchdog (pure).

Feel is the device's hold with config_X's feel profile (active_settings, profile feel) and
setpoints that arm_X streams from Baxter's measured pose (docs/feel.md). The 2020 firmware runs
its PID at 50 Hz on whatever gains it holds, so the device must hold the feel gains before the
hold frame, or its first control ticks pull on the stored gains. Time is an argument; hold is
never timed out.
"""
import math

from robopuppet.protocol import codec


class FeelWatch:
    """Say when feel's hold may go out, what waits for it, and when feel must end.

    Feel starts waiting for its gains (start()); meanwhile setpoints are kept (the newest per
    joint) instead of sent, and gains_loaded() ends the wait and hands them over, to go out
    just before the hold. Feel ends when its gains are not on the device timeout_s after the
    start, or no setpoint came for timeout_s (arm_X died, the network to the robot host is
    cut): the device must not hold a stale pose.
    """

    def __init__(self, timeout_s):
        if not timeout_s > 0.0:
            raise ValueError('the feel setpoint timeout must be positive, got %r' % timeout_s)
        self._timeout_s = timeout_s
        self._last_s = None  # the newest setpoint (or the start of feel), None outside feel
        self._waiting_s = None  # the start of feel while it waits for its gains, else None
        self._kept = {}  # joint: the newest setpoint (rad) kept while feel waits

    @property
    def active(self):
        """True in feel mode (waiting for its gains or holding)."""
        return self._last_s is not None

    @property
    def waiting(self):
        """True while feel waits for its gains on the device."""
        return self._waiting_s is not None

    @property
    def due_s(self):
        """Return when the watchdog or the wait expires (inf outside feel)."""
        if self._last_s is None:
            return math.inf
        return min(self._last_s, math.inf if self._waiting_s is None
                   else self._waiting_s) + self._timeout_s

    def start(self, now_s):
        """Feel mode starts: it waits for its gains."""
        self._last_s = self._waiting_s = now_s
        self._kept = {}

    def gains_loaded(self):
        """The device holds the feel gains: the wait ends; return the kept setpoints (a
        codec.JointSetpoint per joint that got one, in joint order) to send before the hold."""
        self._waiting_s = None
        return self._take_kept()

    def stop(self):
        """Feel mode ends (limp, hold, a reconnect, or its own limp); return the setpoints kept
        while it waited, as gains_loaded does ([] if none)."""
        self._last_s = self._waiting_s = None
        return self._take_kept()

    def on_setpoint(self, now_s, joint, angle_rad):
        """A joint setpoint arrived (in any mode; only feel mode counts it); return True to
        send it now, False when it is kept (feel waits for its gains)."""
        if self._last_s is not None:
            self._last_s = max(self._last_s, now_s)
        if self._waiting_s is None:
            return True
        self._kept[joint] = angle_rad
        return False

    def expired(self, now_s):
        """Return why feel mode must end now ('' while it need not)."""
        if self._waiting_s is not None and now_s >= self._waiting_s + self._timeout_s:
            return ('feel refused: the feel gains (active_settings of profile feel) were not on '
                    'the device %.2f s after the opmode feel' % (now_s - self._waiting_s))
        if self._last_s is None or now_s < self._last_s + self._timeout_s:
            return ''
        return ("no joint setpoint for %.2f s in feel mode: arm_X stopped streaming Baxter's "
                'pose (it stopped, or the link to the robot host is down)'
                % (now_s - self._last_s))

    def _take_kept(self):
        kept, self._kept = self._kept, {}
        return [codec.JointSetpoint(j, angle) for j, angle in sorted(kept.items())]
