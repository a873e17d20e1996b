"""What the Baxter stand-in refuses, and how often it says so.

Pure: no rospy, no clock. The models raise CommandError with a short, fixed `reason`; the node
logs each (topic, reason) at most once per interval through RefusalThrottle. The reason is never
the bad value itself, so a hostile stream of ever-different garbage cannot flood the log, nor
grow the throttle's table without bound.
"""
import math
import numbers
import reprlib

# How much of a refused value a log line shows (a 10 MB gripper args string is not logged whole).
_BRIEF = reprlib.Repr()
_BRIEF.maxstring = _BRIEF.maxother = _BRIEF.maxlong = 80
_BRIEF.maxlist = _BRIEF.maxtuple = _BRIEF.maxdict = 8
_BRIEF.maxlevel = 3


class CommandError(ValueError):
    """A command is malformed or not allowed now; it was dropped.

    Args:
        text: what was wrong, for the log.
        reason: the kind of refusal, from a small fixed set ('unknown joint', 'malformed args').
    """

    def __init__(self, text, reason):
        super().__init__(text)
        self.reason = reason


class NotEnabledError(CommandError):
    """A motion command arrived while the robot is disabled; it was dropped."""

    def __init__(self, text):
        super().__init__(text, 'disabled')


def brief(value):
    """Return a short repr of value: long text, long lists and deep nesting are cut."""
    return _BRIEF.repr(value)


def finite(value, what, reason='bad value'):
    """Return value as a finite float; only real numbers (not bool, not text) are accepted.

    Raises:
        CommandError: with `reason`, naming `what`.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise CommandError('%s must be a number, got %s' % (what, brief(value)), reason)
    try:
        number = float(value)
    except OverflowError as error:   # a JSON integer with hundreds of digits
        raise CommandError('%s is out of range: %s' % (what, brief(value)), reason) from error
    if not math.isfinite(number):
        raise CommandError('%s must be finite, got %r' % (what, number), reason)
    return number


class RefusalThrottle:
    """Decide whether to log a refusal: at most once per interval for each key.

    Args:
        interval_s: seconds between two log lines of the same key.
    """

    def __init__(self, interval_s):
        self.interval_s = interval_s
        self._last_s = {}
        self._skipped = {}

    def report(self, key, now_s):
        """Return None when key was logged less than interval_s ago (the repeat is counted),
        else the number of repeats not logged since its last line (and restart its interval).
        """
        last_s = self._last_s.get(key)
        if last_s is not None and 0.0 <= now_s - last_s < self.interval_s:
            self._skipped[key] = self._skipped.get(key, 0) + 1
            return None
        self._last_s[key] = now_s
        return self._skipped.pop(key, 0)

    def due(self, key, now_s):
        """Return True (and restart the key's interval) when key was not logged recently."""
        return self.report(key, now_s) is not None
