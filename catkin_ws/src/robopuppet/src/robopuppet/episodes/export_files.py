"""The exporter's and the replay's reads of an episode's bag (through bag_chunks) and the
default episodes folder. The files are written by robopuppet.episodes.export_writers.
"""
import rospkg

from robopuppet.episodes import export_images, recording
from robopuppet.episodes.bag_chunks import connections, index_times, messages, open_bag


def default_episodes_dir():
    """Return the recorder's default episodes directory: $ROS_HOME/robopuppet/episodes."""
    return recording.episodes_dir(rospkg.get_ros_home())


def read_messages(bag_path, topics):
    """Return [(topic, msg, t)] of the bag's messages on topics in time order, t its record
    time in s since the first of them (subtracted in integer ns: a float of ROS time since 1970
    keeps only ~0.2 us). Unreadable messages are left out."""
    bag = open_bag(bag_path)
    with bag:
        t0, _ = index_times(bag, topics)
        return [(topic, msg, (t - t0).to_sec()) for topic, msg, t in messages(bag, topics)]


def frame_counts(bag_path, cameras):
    """Return {camera: the number of its frames in the bag} (from the bag's chunk records)."""
    bag = open_bag(bag_path)
    with bag:
        counts = {}
        for camera in cameras:
            ids = connections(bag, [export_images.frame_topic(camera)])
            counts[camera] = sum(c.connection_counts.get(i, 0)
                                 for c in bag._chunks for i in ids)  # noqa: SLF001
        return counts


def read_frames(bag_path, start, cameras=None, skipped=None):
    """Yield (camera, t, JPEG bytes) of the bag's camera frames (export_images.frame_topic) in
    time order, one at a time, t the record time in s since start (genpy.Time: the first
    /robot/joint_states, the export grid's time 0; None: the first frame's). cameras: the
    cameras to read, None for all in the bag; skipped: a Skipped that counts what cannot be
    read."""
    def wanted(topic, datatype):
        camera = export_images.camera_of(topic)
        return (datatype == 'sensor_msgs/CompressedImage' and camera is not None
                and (cameras is None or camera in cameras))
    bag = open_bag(bag_path)
    with bag:
        for topic, msg, t in messages(bag, wanted=wanted, skipped=skipped, t0=start):
            start = t if start is None else start
            yield export_images.camera_of(topic), (t - start).to_sec(), msg.data


def frame_cameras(bag_path):
    """Return the cameras with frames in the bag (export_images.frame_topic), sorted."""
    bag = open_bag(bag_path)
    with bag:
        ids = connections(bag, wanted=lambda topic, _: export_images.camera_of(topic))
        return sorted({export_images.camera_of(bag._connections[i].topic)  # noqa: SLF001
                       for c in bag._chunks for i in c.connection_counts  # noqa: SLF001
                       if i in ids})


def span_s(bag_path, topic):
    """Return the time (s) from topic's first to its last message (from the bag's index); None
    when the bag has none."""
    bag = open_bag(bag_path)
    with bag:
        _, spans = index_times(bag, [topic])
    return None if topic not in spans else (spans[topic][1] - spans[topic][0]).to_sec()
