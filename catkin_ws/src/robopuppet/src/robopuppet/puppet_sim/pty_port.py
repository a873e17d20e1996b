"""The simulated puppet's pseudo-terminal: a pty behind a symlink, polled and read without blocking.

I/O only (no rospy, no decisions): robopuppet.puppet_sim.puppet_device decides how long to wait,
what the bytes read mean and what to write.
"""
import collections
import contextlib
import os
import select
import time
import tty

READ_SIZE = 4096  # bytes taken by one read

Chunk = collections.namedtuple('Chunk', 'data start_s end_s drained')
Chunk.__doc__ = """One read of the pty: its bytes (maybe none), the monotonic times (s) taken just
before and just after the read, and whether it drained the input (fewer than READ_SIZE bytes)."""


class PtyPort:
    """A pseudo-terminal whose slave a symlink names, as a USB serial port's device file is named.

    The simulator keeps the slave open itself, so reading the master never fails with EIO when
    the host closes the port. The slave is raw from the start: the host sees a raw port even
    before it configures it.

    Args:
        link: path of the symlink; replaced when opened, removed when closed if still ours.
    """

    def __init__(self, link):
        self.link = link
        self._master = self._slave = None

    def open(self):
        """Create the pty and point the link at it atomically; return the slave's device path.

        Raises:
            OSError: the pty or the link cannot be made.
        """
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        os.set_blocking(self._master, False)
        temporary = '%s.%d.tmp' % (self.link, os.getpid())
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temporary)  # left by a crashed process that had the same pid
        os.symlink(os.ttyname(self._slave), temporary)
        os.replace(temporary, self.link)
        return os.ttyname(self._slave)

    def close(self):
        """Remove the link unless someone replaced it, and close the pty."""
        try:
            if os.readlink(self.link) == os.ttyname(self._slave):
                os.unlink(self.link)
        except OSError:
            pass  # the link was removed or replaced by someone else: leave it
        os.close(self._master)
        os.close(self._slave)

    def poll(self, timeout_s, writing):
        """Wait up to timeout_s for bytes from the host, or for room to write when `writing`.

        Returns:
            the Chunk read, or None when no byte was waiting when the wait ended.
        """
        readable, _, _ = select.select([self._master], [self._master] if writing else [], [],
                                       timeout_s)
        if not readable:
            return None
        start_s = time.monotonic()
        try:
            data = os.read(self._master, READ_SIZE)
        except (BlockingIOError, InterruptedError):
            data = b''
        return Chunk(data, start_s, time.monotonic(), len(data) < READ_SIZE)

    def write_some(self, data):
        """Write what the pty takes of data now; return how many bytes it took (0: full)."""
        try:
            return os.write(self._master, data)
        except BlockingIOError:
            return 0
