"""The simulated puppet's pseudo-terminal: a pty behind a symlink, polled and read without blocking.

I/O only (no rospy, no decisions): robopuppet.puppet_sim.puppet_device decides how long to wait,
what the bytes read mean and what to write.
"""
import collections
import contextlib
import fcntl
import os
import select
import time
import tty

READ_SIZE = 4096  # bytes taken by one read

LOCK_SUFFIX = '.lock'  # beside the link: held (flock) by the process whose pty the link names


class LinkBusy(OSError):
    """Another live process owns the link: its lock file is locked."""

    def __init__(self, link, holder):
        super().__init__('%s belongs to another running simulated puppet (%s): stop it, or give '
                         'this one its own link (sim_link_prefix or sim_link)' % (
                             link, holder or 'pid unknown'))
        self.link, self.holder = link, holder


Chunk = collections.namedtuple('Chunk', 'data start_s end_s drained')
Chunk.__doc__ = """One read of the pty: its bytes (maybe none), the monotonic times (s) taken just
before and just after the read, and whether it drained the input (fewer than READ_SIZE bytes)."""


class PtyPort:
    """A pseudo-terminal whose slave a symlink names, as a USB serial port's device file is named.

    The simulator keeps the slave open itself, so reading the master never fails with EIO when
    the host closes the port. The slave is raw from the start: the host sees a raw port even
    before it configures it.

    The link belongs to the process that holds an exclusive flock on <link>.lock: open() takes
    it first and refuses a link that another live process holds (the kernel drops the lock
    when its holder ends, however it ends, so a crashed simulator's link is replaced).

    Args:
        link: path of the symlink; replaced when opened, removed when closed if still ours.
    """

    def __init__(self, link):
        self.link = link
        self._master = self._slave = self._lock = None

    def open(self):
        """Take the link, create the pty and point the link at it atomically; return the slave's
        device path.

        Raises:
            LinkBusy: another live process owns the link; nothing was changed.
            OSError: the pty, the lock or the link cannot be made.
        """
        directory = os.path.dirname(self.link)
        if directory:
            os.makedirs(directory, exist_ok=True)
        self._lock = self._take_lock()
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        os.set_blocking(self._master, False)
        temporary = '%s.%d.tmp' % (self.link, os.getpid())
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temporary)  # left by a crashed process that had the same pid
        os.symlink(os.ttyname(self._slave), temporary)
        os.replace(temporary, self.link)
        return os.ttyname(self._slave)

    def _take_lock(self):
        """Return the fd of <link>.lock, flocked; LinkBusy when another process holds it."""
        path = self.link + LOCK_SUFFIX
        while True:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o600)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = os.pread(fd, 100, 0).decode('utf-8', 'replace').strip()
                os.close(fd)
                raise LinkBusy(self.link, holder) from None
            try:  # its last holder may have removed the file between our open and our flock
                current = os.stat(path)
            except FileNotFoundError:
                current = None
            if current is not None and os.path.samestat(os.fstat(fd), current):
                os.ftruncate(fd, 0)
                os.pwrite(fd, ('pid %d\n' % os.getpid()).encode(), 0)
                return fd
            os.close(fd)

    def close(self):
        """Remove the link if it still names our pty, drop our lock, and close the pty.

        A port that never opened (LinkBusy) leaves everything as it is.
        """
        if self._lock is None:
            return
        if self._slave is not None:
            try:
                if os.readlink(self.link) == os.ttyname(self._slave):
                    os.unlink(self.link)
            except OSError:
                pass  # the link was removed or replaced by someone else: leave it
            os.close(self._master)
            os.close(self._slave)
            self._master = self._slave = None
        with contextlib.suppress(OSError):
            os.unlink(self.link + LOCK_SUFFIX)  # still locked: no one else can own this file
        os.close(self._lock)
        self._lock = None

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
