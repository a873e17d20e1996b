"""Periodic work that survives its own failures: guarded calls and a steady loop thread.

A rospy.Timer (or any thread) whose callback raises stops for good, silently. Every periodic
callback of every node goes through a Guard instead: an exception is logged with its traceback
(at most once per throttle interval and kind of callback), counted for /diagnostics, and the
next period runs as usual. Pure: no rospy; the node passes its log function and the clock.
"""
import threading
import time
import traceback


class Guard:
    """Call functions so that any exception is logged and counted, never propagated.

    Args:
        name: who runs the callbacks (the node's name), for log lines.
        log_error(text): where a failure is reported (e.g. rospy.logerr).
        throttle_s: the same callback's failures are logged at most once per this interval
            (each log line says how many failed since the last one).
        clock(): monotonic seconds.
    Attributes:
        errors: failures so far, all callbacks together.
        last_error: 'what: ExceptionType: text' of the newest failure, or ''.
    """

    def __init__(self, name, log_error, throttle_s=5.0, clock=time.monotonic):
        self._name = name
        self._log_error = log_error
        self._throttle_s = throttle_s
        self._clock = clock
        self._lock = threading.Lock()
        self._logged = {}  # what -> (time of the last log line, failures not yet logged)
        self.errors = 0
        self.last_error = ''

    def call(self, what, function, *args):
        """Return function(*args), or None if it raised (the failure is logged and counted).

        Args:
            what: a short name of the callback ('command loop'), for log lines.
        """
        try:
            return function(*args)
        except Exception as error:  # pylint: disable=broad-except
            self._failed(what, error)
            return None

    def _failed(self, what, error):
        now = self._clock()
        with self._lock:
            self.errors += 1
            self.last_error = '%s: %s: %s' % (what, type(error).__name__, error)
            last_t, unlogged = self._logged.get(what, (None, 0))
            if last_t is not None and now - last_t < self._throttle_s:
                self._logged[what] = (last_t, unlogged + 1)
                return
            self._logged[what] = (now, 0)
        more = ' (and %d more since the last report)' % unlogged if unlogged else ''
        self._log_error('%s: %s failed%s; it keeps running: %s\n%s' % (
            self._name, what, more, self.last_error, traceback.format_exc().rstrip()))


class Loop:
    """Call a function every period on a daemon thread of its own, through a Guard.

    The loop keeps a fixed rate (a late period is not made up twice) and never dies of an
    exception in the function. `last_run_s` is the monotonic time at which the newest call
    returned without raising (None before), so another thread can tell that this loop stalls.

    Args:
        guard: the Guard that runs each call.
        what: the loop's name, for log lines and the thread's name.
        period_s: seconds between calls.
        function(): the work of one period.
    """

    def __init__(self, guard, what, period_s, function):
        if not period_s > 0.0:
            raise ValueError('%s: period must be positive, got %r' % (what, period_s))
        self._guard, self._what, self._period_s = guard, what, period_s
        self._function = function
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name=what, daemon=True)
        self.last_run_s = None

    def start(self):
        """Start calling the function; returns self."""
        self._thread.start()
        return self

    def stop(self, timeout_s=1.0):
        """Stop the loop and wait up to timeout_s for its thread to end."""
        self._stop.set()
        if self._thread.is_alive() and self._thread is not threading.current_thread():
            self._thread.join(timeout_s)

    def _once(self):
        self._function()
        self.last_run_s = time.monotonic()

    def _run(self):
        next_s = time.monotonic()
        while not self._stop.is_set():
            self._guard.call(self._what, self._once)
            next_s += self._period_s
            now = time.monotonic()
            if next_s < now:
                next_s = now  # behind (a stall): run again at once, then at the period
            self._stop.wait(next_s - now)
