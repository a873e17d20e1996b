"""serial_X's threads around its core: each call under the core lock, the writes it made after it.

The transport side of serial_X, apart from the protocol (as pyserial's serial.threaded keeps
them): the core decides under its lock and queues its writes; the pacing sleep and the port
write happen outside that lock, in the core's order, under a write lock of their own. So the
reader thread hands bytes to the core while a paced write sleeps. No rospy.
"""
import collections
import threading
import time

from robopuppet.protocol import device_commands


class CoreRunner:
    """Call serial_X's core from several threads; write what it queued, in order and paced.

    Args:
        link: the port (serial_link.SerialLink): connected, connects, write(data) -> bool.
        make_core(write): return the core (serial_core.SerialCore), given its write callable.
        clock(), sleep(s): monotonic time and a sleep (time's; tests may replace them).
    Attributes:
        core: the core, whose methods call() takes.
    The core's write(data) queues the bytes (False while the port is closed); a queued write
    that the port then refuses is reported to the core's on_write_failed, unless the port was
    re-opened meanwhile (then its on_connect has unloaded the device already).
    """

    def __init__(self, link, make_core, clock=time.monotonic, sleep=time.sleep):
        self._link, self._clock, self._sleep = link, clock, sleep
        self._lock = threading.Lock()  # the core: every call under it
        self._write_lock = threading.Lock()  # the port's writes and the pacer, in queue order
        self._queue = collections.deque()  # (data, link.connects when queued)
        self._queued = 0  # writes queued so far
        self._pacer = device_commands.WritePacer()
        self.core = make_core(self._write)

    def call(self, method, *args):
        """Call a core method under the core lock, then write what it queued.

        Returns:
            (what the method returned, whether the core's step() has work now).
        """
        with self._lock:
            queued = self._queued
            result = method(*args)
            due = self.core.step_due()
            wrote = self._queued != queued
        if wrote:
            self._flush()
        return result, due

    def _write(self, data):
        """The core's write (under the core lock): queue one write; False if the port is closed."""
        if not self._link.connected:
            return False
        self._queue.append((data, self._link.connects))
        self._queued += 1
        return True

    def _flush(self):
        """Write everything queued, in order: each write waits as WritePacer says."""
        failed = []  # link.connects of the writes the port refused
        with self._write_lock:
            while self._queue:
                data, connects = self._queue.popleft()
                delay_s = self._pacer.delay_s(self._clock(), len(data))
                if delay_s > 0.0:
                    self._sleep(delay_s)
                if not self._link.write(data):
                    failed.append(connects)
                self._pacer.wrote(self._clock(), len(data))
        if failed:
            with self._lock:
                if self._link.connects in failed:
                    self.core.on_write_failed()
