"""An episode's bag: written raw as <name>.bag.active, renamed <name>.bag when whole, and the
repair of one that did not end.

Uses rosbag (no rospy): the bag is written from the bytes and connection header that
rospy.AnyMsg received, so nothing is deserialised on the way. Times are genpy.Time (ROS time).
"""
import os
import struct

import genpy
import rosbag

from robopuppet.episodes import recording
from robopuppet.episodes.episode_folder import leftovers, not_whole, sync
from robopuppet.episodes.metadata import metadata_or_empty, write_metadata

# Chunks are closed when they reach this size or at each flush, whichever comes first: a kill
# loses only what came after the last flush.
CHUNK_THRESHOLD_BYTES = 256 * 1024
HEADER_KEYS = ('topic', 'type', 'md5sum', 'message_definition', 'callerid', 'latching')
BROKEN = '.broken'   # appended to a .bag that is not whole and cannot be repaired


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
    data = metadata_or_empty(base + recording.META)
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

