"""The episodes folder: one recorder's lock on it, which of its bags did not end whole, its free
space, and the fingerprint of an ini file an episode was recorded with.

Pure: no ROS (a bag's header is read with struct); the recorder holds the lock and
episode_files repairs what this finds.
"""
import fcntl
import glob
import hashlib
import os
import struct

from robopuppet.episodes import recording

BAG_VERSION_LINE = b'#ROSBAG V2.0\n'


class FolderBusy(Exception):
    """Another live process holds an episodes folder's lock (nothing in the folder was touched).

    Attributes: directory, holder (what the holder wrote into the lock file, e.g.
    'pid 4242 /recorder', or '' when unknown).
    """

    def __init__(self, directory, holder):
        super().__init__('episodes folder %s is in use by another recorder (%s): one recorder '
                         'per folder; stop that one, or give this one its own episodes_dir' % (
                             directory, holder or 'pid unknown'))
        self.directory, self.holder = directory, holder


class FolderLock:
    """One recorder per episodes folder: an exclusive flock on <directory>/recording.LOCK_FILE.

    The kernel releases it when the holder's process ends, however it ends (kill -9 too), so a
    crashed recorder never leaves it behind. The file stays (removing it would let two processes
    lock two files of the same name); it holds 'pid <pid> <owner>' of the holder.

    Raises:
        FolderBusy: another live process holds it.
        OSError: the folder or the lock file cannot be created or opened.
    """

    def __init__(self, directory, owner=''):
        self.directory = directory
        self.path = os.path.join(directory, recording.LOCK_FILE)
        os.makedirs(directory, exist_ok=True)
        try:
            self._fd = os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except PermissionError:  # another user's lock file: it can be locked all the same
            self._fd = os.open(self.path, os.O_RDONLY | os.O_CLOEXEC)
        try:
            fcntl.flock(self._fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(self._fd, 200, 0).decode('utf-8', 'replace').strip()
            self.release()
            raise FolderBusy(directory, holder) from None
        except OSError:
            self.release()
            raise
        try:
            os.ftruncate(self._fd, 0)
            os.pwrite(self._fd, ('pid %d %s\n' % (os.getpid(), owner)).encode(), 0)
        except OSError:
            pass  # read-only: locked all the same, only the holder is not named

    def held(self):
        """Return True while this process holds the lock."""
        return self._fd is not None

    def release(self):
        """Release the lock (the process's end does the same)."""
        if self._fd is not None:
            os.close(self._fd)
            self._fd = None



def sync(path):
    """Put a closed file's bytes on disk (before a rename says it is whole)."""
    descriptor = os.open(path, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def leftovers(directory):
    """Return the .bag.active files in directory (those of an episode that did not end)."""
    return sorted(glob.glob(os.path.join(glob.escape(directory), '*' + recording.ACTIVE)))


def not_whole(directory):
    """Return the .bag files in directory that are not whole (is_whole false)."""
    return [path for path in sorted(glob.glob(os.path.join(glob.escape(directory),
                                                           '*' + recording.BAG)))
            if not is_whole(path)]


def is_whole(path):
    """Return False when path is a rosbag 2.0 without a valid index (its header's index_pos is 0,
    as while it is written, or beyond the file's end); True otherwise (only the header is read,
    so that a start with many episodes stays quick)."""
    try:
        with open(path, 'rb') as source:
            if source.readline() != BAG_VERSION_LINE:
                return True  # not a bag this recorder wrote: not ours to judge
            header = source.read(4096)
            size = os.fstat(source.fileno()).st_size
    except OSError:
        return True
    if len(header) < 4:
        return False
    (length,), pos, fields = struct.unpack_from('<i', header), 4, {}
    while pos + 4 <= min(len(header), 4 + length):
        (field_length,) = struct.unpack_from('<i', header, pos)
        name, _, value = header[pos + 4:pos + 4 + field_length].partition(b'=')
        fields[name] = value
        pos += 4 + field_length
    index = fields.get(b'index_pos', b'')
    return len(index) == 8 and 0 < struct.unpack('<Q', index)[0] < size


def ini_fingerprint(path):
    """Return the sha256 hex digest of a file's bytes, or None when it cannot be read."""
    try:
        with open(path, 'rb') as source:
            return hashlib.sha256(source.read()).hexdigest()
    except OSError:
        return None


def free_bytes(directory):
    """Return the bytes free for an unprivileged writer on directory's file system."""
    stats = os.statvfs(directory)
    return stats.f_bavail * stats.f_frsize
