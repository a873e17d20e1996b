"""An episode's files: the bag written as <name>.bag.active, its metadata, and crash repair.

Uses rosbag (no rospy): the bag is written raw, from the bytes and connection header that
rospy.AnyMsg received, so nothing is deserialised on the way. Times are genpy.Time (ROS time).
"""
import glob
import hashlib
import os

import genpy
import rosbag
import yaml

from robopuppet.episodes import recording

# Chunks are closed when they reach this size or at each flush, whichever comes first: a kill
# loses only what came after the last flush.
CHUNK_THRESHOLD_BYTES = 256 * 1024
HEADER_KEYS = ('topic', 'type', 'md5sum', 'message_definition', 'callerid', 'latching')


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
        """Write the index, close the file and rename it to <name>.bag."""
        self._bag.close()
        self._file.close()
        os.replace(self.active_path, self.path)

    def abandon(self):
        """Close the file without its index (after a write failed); repair() recovers it."""
        try:
            self._file.close()
        except OSError:
            pass


def bag_counts(path):
    """Return ({topic: messages}, duration_s) of a readable bag."""
    with rosbag.Bag(path) as bag:
        info = bag.get_type_and_topic_info()
        counts = {topic: t.message_count for topic, t in info.topics.items()}
        duration_s = bag.get_end_time() - bag.get_start_time() if counts else 0.0
    return counts, duration_s


def repair(active_path):
    """Reindex a leftover <name>.bag.active in place, rename it to <name>.bag and mark its
    metadata ended_cleanly: false (with the counts and duration the bag holds). Return the path
    of the bag.

    Raises:
        OSError, rosbag.ROSBagException: the file cannot be repaired (it is left as it was).
    """
    bag = rosbag.Bag(active_path, 'a', allow_unindexed=True)
    try:
        for _ in bag.reindex():
            pass
    finally:
        bag.close()
    path = active_path[:-len(recording.ACTIVE)] + recording.BAG
    os.replace(active_path, path)
    counts, duration_s = bag_counts(path)
    meta_path = active_path[:-len(recording.ACTIVE)] + recording.META
    data = read_metadata(meta_path)
    data.update(ended_cleanly=False, duration_s=float(duration_s), topics=dict(sorted(
        counts.items())))
    data.setdefault('name', os.path.basename(path)[:-len(recording.BAG)])
    write_metadata(meta_path, data)
    return path


def leftovers(directory):
    """Return the .bag.active files in directory (those of an episode that did not end)."""
    return sorted(glob.glob(os.path.join(glob.escape(directory), '*' + recording.ACTIVE)))


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
