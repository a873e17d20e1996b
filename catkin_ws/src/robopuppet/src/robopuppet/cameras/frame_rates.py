"""Counters of a camera node's frames, read as rates for its /diagnostics. Pure: time passed in."""
import threading


class FrameRates:
    """Count events (frames rendered, published, ...) and tell their rates between readings.

    add() and read() may run on different threads.

    Args:
        names: what is counted (hashable keys).
        now_s: when counting starts (s, monotonic).
    """

    def __init__(self, names, now_s):
        self._lock = threading.Lock()
        self._counts = dict.fromkeys(names, 0)
        self._last = (now_s, dict(self._counts))

    def add(self, name):
        """Count one event of `name`."""
        with self._lock:
            self._counts[name] += 1

    def read(self, now_s):
        """Return ({name: count since the start}, {name: events per s since the last read})."""
        with self._lock:
            counts = dict(self._counts)
        then_s, then = self._last
        self._last = (now_s, counts)
        span_s = max(now_s - then_s, 1e-3)
        return counts, {name: (counts[name] - then[name]) / span_s for name in counts}
