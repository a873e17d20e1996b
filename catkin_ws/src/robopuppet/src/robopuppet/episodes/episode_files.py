"""An episode's files: the bag written as <name>.bag.active, its metadata, the folder's lock and
crash repair.

Uses rosbag (no rospy): the bag is written raw, from the bytes and connection header that
rospy.AnyMsg received, so nothing is deserialised on the way. Times are genpy.Time (ROS time).
"""
import fcntl
import glob
import hashlib
import os
import struct

import genpy
import rosbag
import yaml

from robopuppet.episodes import recording

# Chunks are closed when they reach this size or at each flush, whichever comes first: a kill
# loses only what came after the last flush.
CHUNK_THRESHOLD_BYTES = 256 * 1024
HEADER_KEYS = ('topic', 'type', 'md5sum', 'message_definition', 'callerid', 'latching')
BAG_VERSION_LINE = b'#ROSBAG V2.0\n'
BROKEN = '.broken'   # appended to a .bag that is not whole and cannot be repaired


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


def write_metadata(path, data):
    """Write a metadata dict as YAML atomically (temp file, fsync, rename); OSError on failure."""
    temp = path + '.tmp'
    try:
        with open(temp, 'w') as out:
            yaml.safe_dump(data, out, default_flow_style=False, sort_keys=False)
            out.flush()
            os.fsync(out.fileno())
        os.replace(temp, path)
    finally:
        if os.path.exists(temp):
            os.unlink(temp)


def read_metadata(path):
    """Return the metadata dict in path, or {} when it is missing or unreadable."""
    try:
        with open(path) as source:
            data = yaml.safe_load(source)
    except (OSError, yaml.YAMLError):
        return {}
    return data if isinstance(data, dict) else {}


class BagWriter:
    """Write one episode's bag: <name>.bag.active while open, renamed to <name>.bag on close.

    Not thread safe: the node calls it under its lock. Every method may raise OSError (a full or
    read-only disk); the node then stops the episode and says why.
    """

    def __init__(self, directory, name):
        self.active_path = os.path.join(directory, name + recording.ACTIVE)
        self.path = os.path.join(directory, name + recording.BAG)
        self._file = open(self.active_path, 'w+b')  # pylint: disable=consider-using-with
        try:
            self._bag = rosbag.Bag(self._file, 'w', chunk_threshold=CHUNK_THRESHOLD_BYTES)
        except Exception:
            self._file.close()
            raise

    def write(self, topic, msg, stamp_s):
        """Write a rospy.AnyMsg received on topic at ROS time stamp_s (s); return its size."""
        received = getattr(msg, '_connection_header', None) or {}
        header = {key: received[key] for key in HEADER_KEYS if key in received}
        header['topic'] = topic
        self._bag.write(topic, (header['type'], msg._buff, header['md5sum'], None),
                        genpy.Time.from_sec(stamp_s), raw=True, connection_header=header)
        return len(msg._buff)

    def flush(self):
        """Close the open chunk and hand everything written so far to the operating system."""
        self._bag.flush()
        self._file.flush()

    def size_bytes(self):
        """Return the bag's size so far (bytes; on disk once closed, 0 when it is gone)."""
        if not self._file.closed:
            return self._file.tell()
        for path in (self.path, self.active_path):
            if os.path.exists(path):
                return os.path.getsize(path)
        return 0

    def close(self):
        """Write the index, close the file and rename it to <name>.bag: on disk (fsync) first, so
        that a .bag is always whole."""
        self._bag.close()
        self._file.close()
        sync(self.active_path)
        os.replace(self.active_path, self.path)

    def abandon(self):
        """Close the file without its index (after a write failed); repair() recovers it."""
        try:
            self._file.close()
        except OSError:
            pass


def sync(path):
    """Put a closed file's bytes on disk (before a rename says it is whole)."""
    descriptor = os.open(path, os.O_RDONLY)
    try:
        os.fsync(descriptor)
    finally:
        os.close(descriptor)


def bag_counts(path):
    """Return ({topic: messages}, duration_s) of a readable bag."""
    with rosbag.Bag(path) as bag:
        info = bag.get_type_and_topic_info()
        counts = {topic: t.message_count for topic, t in info.topics.items()}
        duration_s = bag.get_end_time() - bag.get_start_time() if counts else 0.0
    return counts, duration_s


def repair(path):
    """Make a bag that did not end whole: reindex a leftover <name>.bag.active, or a <name>.bag
    that is not whole (is_whole), in place, name it <name>.bag and mark its metadata
    ended_cleanly: false (with the counts and duration the bag holds). Return the bag's path.

    Call it only under the folder's FolderLock: a live recorder's .bag.active is not a leftover.
    Raises:
        OSError, rosbag.ROSBagException: the file cannot be repaired (it keeps its name).
    """
    active = path.endswith(recording.ACTIVE)
    base = path[:-len(recording.ACTIVE if active else recording.BAG)]
    bag = rosbag.Bag(path, 'a', allow_unindexed=True)
    try:
        for _ in bag.reindex():
            pass
    finally:
        bag.close()
    sync(path)
    os.replace(path, base + recording.BAG)
    counts, duration_s = bag_counts(base + recording.BAG)
    data = read_metadata(base + recording.META)
    data.update(ended_cleanly=False, duration_s=float(duration_s), topics=dict(sorted(
        counts.items())))
    data.setdefault('name', os.path.basename(base))
    write_metadata(base + recording.META, data)
    return base + recording.BAG


def recover(lock):
    """Repair what the folder of a held FolderLock holds of episodes that did not end: every
    leftover .bag.active and every .bag that is not whole (from a version without the lock).

    Returns:
        [(path, the repaired bag's path or '', why it could not be repaired or '')]; a .bag
        that cannot be repaired is renamed <name>.bag.broken, a .bag.active keeps its name.
    Raises:
        RuntimeError: the lock is not held (a live recorder may own the files).
    """
    if not lock.held():
        raise RuntimeError('repairing %s without its lock' % lock.directory)
    results = []
    for path in leftovers(lock.directory) + not_whole(lock.directory):
        try:
            results.append((path, repair(path), ''))
        except (OSError, rosbag.ROSBagException, struct.error, ValueError) as error:
            why = str(error) or type(error).__name__
            if path.endswith(recording.BAG):
                try:
                    os.replace(path, path + BROKEN)
                    why += ' (renamed %s)' % os.path.basename(path + BROKEN)
                except OSError:
                    pass
            results.append((path, '', why))
    return results


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
