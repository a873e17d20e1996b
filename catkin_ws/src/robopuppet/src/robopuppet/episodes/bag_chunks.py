"""Read a bag one chunk at a time (rosbag, no master), skipping and counting what is unreadable.

rosbag's read_messages first loads every message's index entry (about 200 bytes each, 110 MB
for a 30-minute episode), so messages() merges the chunks' indexes itself, as rosbag merges
them, with rosbag's (ROS 1's last, frozen) chunk and record readers.
"""
import collections
import heapq
import struct

import rosbag

from robopuppet.episodes.metadata import EpisodeError


class Skipped:
    """What a bag's read skipped and why: {reason: {topic: [count, first time (s)]}}."""

    def __init__(self):
        self.reasons = collections.OrderedDict()

    def add(self, reason, topic, t_s, count=1):
        entry = self.reasons.setdefault(reason, collections.OrderedDict()).setdefault(
            topic, [0, t_s])
        entry[0] += count

    def lines(self):
        """Return a line per reason: 'skipped N <reason> (topic n, ...), the first at T s'."""
        return ['skipped %d %s (%s), the first at %.3f s into the bag' % (
            sum(n for n, _ in topics.values()), reason,
            ', '.join('%s %d' % (topic, n) for topic, (n, _) in topics.items()),
            min(t for _, t in topics.values())) for reason, topics in self.reasons.items()]


def open_bag(bag_path):
    """Return the bag opened without its message index (skip_index: messages() reads it).

    Raises:
        EpisodeError: not a bag, or its connection and chunk records are unreadable.
    """
    try:
        return rosbag.Bag(bag_path, skip_index=True)
    except (rosbag.ROSBagException, OSError, struct.error, ValueError) as error:
        raise EpisodeError('%s: cannot read the bag: %s' % (bag_path, error)) from error


def connections(bag, topics=None, wanted=None):
    """Return {connection id: rank} of the bag's connections on topics (None: all) that
    wanted(topic, datatype) accepts, ranked as rosbag ranks them."""
    return {c.id: rank for rank, c in enumerate(bag._connections.values())  # noqa: SLF001
            if (topics is None or c.topic in topics)
            and (wanted is None or wanted(c.topic, c.datatype))}


def _chunk_entries(bag, chunk, ids):
    """Return [(time, connection id, offset)] of a chunk's messages on the connections ids,
    from its index records (which follow it in the file).

    Raises:
        ValueError: the index is corrupt (an entry outside the chunk's time range, a count
            that differs from the chunk's record).
    """
    stream = bag._file  # noqa: SLF001  (rosbag reads a chunk's index so; see the docstring)
    stream.seek(chunk.pos)
    rosbag.bag._skip_record(stream)  # noqa: SLF001
    bag._curr_chunk_info = chunk  # noqa: SLF001
    entries = []
    for _ in range(len(chunk.connection_counts)):
        conn, index = bag._reader.read_connection_index_record()  # noqa: SLF001
        if chunk.connection_counts.get(conn) != len(index):
            raise ValueError('index of connection %s does not match the chunk' % conn)
        for entry in index:
            if not chunk.start_time <= entry.time <= chunk.end_time:
                raise ValueError('index entry at %s outside the chunk' % entry.time)
            if conn in ids:
                entries.append((entry.time, conn, entry.offset))
    return entries


def index_times(bag, topics):
    """Return (the first message's time, {topic: (first, last) time}) of the bag's messages on
    topics (genpy.Time), from the chunks' indexes; a chunk whose index is corrupt is left out.
    """
    ids = connections(bag, topics)
    first, spans = None, {}
    for chunk in bag._chunks:  # noqa: SLF001
        if not ids.keys() & chunk.connection_counts.keys():
            continue
        try:
            entries = _chunk_entries(bag, chunk, ids)
        except Exception:  # pylint: disable=broad-except  (garbage raises anything; skipped)
            continue
        for time, conn, _ in entries:
            topic = bag._connections[conn].topic  # noqa: SLF001
            low, high = spans.get(topic, (time, time))
            spans[topic] = (min(low, time), max(high, time))
            first = time if first is None else min(first, time)
    return first, spans


def messages(bag, topics=None, wanted=None, skipped=None, t0=None):
    """Yield (topic, msg, time) of the bag's messages on topics (None: all) that
    wanted(topic, datatype) accepts, in time order as rosbag's read_messages yields them, one
    chunk's index at a time (rosbag's own reader holds every message's index entry).

    What cannot be read is skipped and counted in skipped (a Skipped; times from t0): a chunk
    whose index is corrupt, a record that is not a message of its index entry, a message that
    does not deserialize.
    """
    ids = connections(bag, topics, wanted)
    chunks = sorted((c for c in bag._chunks  # noqa: SLF001
                     if ids.keys() & c.connection_counts.keys()),
                    key=lambda c: (c.start_time, c.pos))
    pending, loaded = [], 0
    skipped = skipped if skipped is not None else Skipped()
    t0 = t0 if t0 is not None else (chunks[0].start_time if chunks else None)
    while loaded < len(chunks) or pending:
        while loaded < len(chunks) and (
                not pending or chunks[loaded].start_time.to_nsec() <= pending[0][0]):
            chunk = chunks[loaded]
            try:
                for i, (time, conn, offset) in enumerate(_chunk_entries(bag, chunk, ids)):
                    heapq.heappush(pending, (time.to_nsec(), ids[conn], loaded, i, time,
                                             conn, chunk.pos, offset))
            except Exception:  # pylint: disable=broad-except  (garbage raises anything)
                for conn, count in chunk.connection_counts.items():
                    if conn in ids:
                        skipped.add('messages of chunks whose index is corrupt',
                                    bag._connections[conn].topic,  # noqa: SLF001
                                    (chunk.start_time - t0).to_sec(), count)
            loaded += 1
        if not pending:
            continue
        _, _, _, _, time, conn, chunk_pos, offset = heapq.heappop(pending)
        topic = bag._connections[conn].topic  # noqa: SLF001
        try:
            read = bag._reader.seek_and_read_message_data_record(  # noqa: SLF001
                (chunk_pos, offset), True)
        except Exception:  # pylint: disable=broad-except  (garbage raises anything)
            read = None
        if read is None or read.topic != topic or read.timestamp != time:
            skipped.add('unreadable message records', topic, (time - t0).to_sec())
            continue
        try:
            msg = read.message[4]()
            msg.deserialize(read.message[1])
        except Exception:  # pylint: disable=broad-except  (garbage raises anything)
            skipped.add('messages that do not deserialize', topic, (time - t0).to_sec())
            continue
        yield topic, msg, time
