"""The exporter's files: read an episode (bag and yaml), write ALOHA's HDF5, Rethink's CSV and
the episode's plot (PNG). The arrays come from robopuppet.episodes.export, the camera images
from robopuppet.episodes.export_images.

Reads the bag with rosbag (a file library: no ROS master needed), writes with h5py and
matplotlib (Agg backend, no display needed). Those two are imported where they write, so that
the replay command, which only reads bags, starts seconds sooner.
"""
import os

import numpy as np
import rosbag
import rospkg
import yaml

from robopuppet.episodes import export_images, recording
from robopuppet.episodes.export import COLUMNS
from robopuppet.interface import ROBOT_JOINT_STATES

ACTIVE_SUFFIX = '.active'
# The images' HDF5 filter. lzf (h5py's own): 15 s of CPU per minute of three simulated cameras
# at 50 Hz, 40 s for photographs; gzip (level 4): 37 and 116 s for 22 and 13 % fewer bytes
# (benchmarks/bench_export.py --compression, docs/demonstrations.md). h5py reads both.
IMAGE_COMPRESSION = 'lzf'
JOINT_LABELS = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')


class EpisodeError(Exception):
    """An episode's files cannot be read (missing, still being recorded, or not a bag)."""


def default_episodes_dir():
    """Return the recorder's default episodes directory: $ROS_HOME/robopuppet/episodes."""
    return recording.episodes_dir(rospkg.get_ros_home())


def episode_paths(episode):
    """Return (bag path, yaml path) of an episode given as its name, .bag or .yaml path.

    Raises:
        EpisodeError: only a .bag.active exists (a recording that is running or crashed), or
            the bag is missing.
    """
    base = episode
    for suffix in ('.bag' + ACTIVE_SUFFIX, '.bag', '.yaml'):
        if base.endswith(suffix):
            base = base[:-len(suffix)]
            break
    bag_path, yaml_path = base + '.bag', base + '.yaml'
    if not os.path.exists(bag_path):
        if os.path.exists(bag_path + ACTIVE_SUFFIX):
            raise EpisodeError(
                '%s%s is still being recorded or its recording crashed: stop the recording, '
                'or start the recorder (it repairs leftover .active bags) or run '
                '`rosbag reindex` on it and rename it to .bag' % (bag_path, ACTIVE_SUFFIX))
        raise EpisodeError('%s: no such bag' % bag_path)
    return bag_path, yaml_path


def read_metadata(yaml_path):
    """Return the episode's metadata dict ({} when the .yaml is missing)."""
    if not os.path.exists(yaml_path):
        return {}
    with open(yaml_path) as stream:
        metadata = yaml.safe_load(stream)
    if not isinstance(metadata, dict):
        raise EpisodeError('%s: not an episode metadata file' % yaml_path)
    return metadata


def read_messages(bag_path, topics):
    """Return [(topic, msg, t)] of the bag's messages on topics in time order, t its record
    time in s since the first of them (subtracted in integer ns: a float of ROS time since 1970
    keeps only ~0.2 us)."""
    try:
        with rosbag.Bag(bag_path) as bag:
            messages = list(bag.read_messages(topics=topics))
    except (rosbag.ROSBagException, OSError) as error:
        raise EpisodeError('%s: cannot read the bag: %s' % (bag_path, error)) from error
    return [(topic, msg, (t - messages[0][2]).to_sec()) for topic, msg, t in messages]


def frame_counts(bag_path, cameras):
    """Return {camera: the number of its frames in the bag} (from the bag's index)."""
    try:
        with rosbag.Bag(bag_path) as bag:
            return {camera: bag.get_message_count(export_images.frame_topic(camera))
                    for camera in cameras}
    except (rosbag.ROSBagException, OSError) as error:
        raise EpisodeError('%s: cannot read the bag: %s' % (bag_path, error)) from error


def read_frames(bag_path, cameras=None):
    """Yield (camera, t, JPEG bytes) of the bag's camera frames (export_images.frame_topic) in
    time order, one at a time, t the record time in s since the first /robot/joint_states
    (the export grid's time 0). cameras: the cameras to read, None for all in the bag."""
    def wanted(topic, datatype, *_):
        camera = export_images.camera_of(topic)
        return (datatype == 'sensor_msgs/CompressedImage' and camera is not None
                and (cameras is None or camera in cameras))
    try:
        with rosbag.Bag(bag_path) as bag:
            start = next(bag.read_messages(topics=[ROBOT_JOINT_STATES]), (None, None, None))[2]
            if start is None:
                return
            for topic, msg, t in bag.read_messages(connection_filter=wanted):
                yield export_images.camera_of(topic), (t - start).to_sec(), msg.data
    except (rosbag.ROSBagException, OSError) as error:
        raise EpisodeError('%s: cannot read the bag: %s' % (bag_path, error)) from error


def write_hdf5(path, arrays, sim, rate_hz, name, frames=(), progress=None,
               compression=IMAGE_COMPRESSION):
    """Write ALOHA's layout: attrs sim, /observations/qpos, qvel, effort and /action (T, 16)
    float32 in COLUMNS order; also attrs columns (the column names), rate_hz and episode.

    The group /observations/images holds, per camera of frames ((camera, t, JPEG bytes) in
    time order, as read_frames yields them), a dataset <camera> (T, H, W, 3) uint8 RGB with
    chunks of one image, like ALOHA's, compressed by the filter compression (h5py undoes it
    when reading). Each frame is decoded and compressed once; the steps that repeat it get a
    copy of its stored chunk. progress(fraction 0..1) is called after each run of steps.

    Returns:
        lines worth reporting about the images (export_images.ImageResampler.report).
    Raises:
        export.ExportError: a camera has no frame that decodes.
    """
    import h5py  # pylint: disable=import-outside-toplevel  (see the module docstring)
    resampler = export_images.ImageResampler(arrays['time'])
    steps = len(arrays['time'])
    with h5py.File(path, 'w') as root:
        root.attrs['sim'] = bool(sim)
        root.attrs['columns'] = np.array(COLUMNS, dtype=h5py.string_dtype())
        root.attrs['rate_hz'] = float(rate_hz)
        root.attrs['episode'] = name
        observations = root.create_group('observations')
        for dataset in ('qpos', 'qvel', 'effort'):
            observations.create_dataset(dataset, data=arrays[dataset].astype(np.float32))
        root.create_dataset('action', data=arrays['action'].astype(np.float32))
        images, datasets = observations.create_group('images'), {}
        for run in _runs(resampler, frames):
            if run.camera not in datasets:
                datasets[run.camera] = images.create_dataset(
                    run.camera, (steps,) + run.image.shape, dtype=np.uint8,
                    chunks=(1,) + run.image.shape, compression=compression)
            _write_run(datasets[run.camera], run)
            if progress:
                progress(run.stop / steps)
    return resampler.report()


def _runs(resampler, frames):
    """Yield the resampler's runs of the frames, then its last ones."""
    for camera, t_s, data in frames:
        yield from resampler.add(camera, t_s, data)
    yield from resampler.finish()


def _write_run(dataset, run):
    """Write a run's image to its steps run.start..run.stop-1 of the camera's dataset:
    compressed once, then its stored chunk copied."""
    dataset[run.start] = run.image
    if run.stop - run.start > 1:
        mask, chunk = dataset.id.read_direct_chunk((run.start, 0, 0, 0))
        for step in range(run.start + 1, run.stop):
            dataset.id.write_direct_chunk((step, 0, 0, 0), chunk, mask)


def write_csv(path, lines):
    """Write the CSV lines, each ended by a newline."""
    with open(path, 'w') as stream:
        stream.write(''.join(line + '\n' for line in lines))


def write_plot(path, series, time_s, title):
    """Write a PNG: per plotted arm two columns of 8 panels. Left: per joint the puppet's angle
    as that arm takes it, the commanded and the measured angle (deg), then the gripper's
    commanded and measured opening with the puppet's end-piece reading (0..1). Right: the
    tracking error commanded - measured of each (deg; opening for the gripper)."""
    import matplotlib  # pylint: disable=import-outside-toplevel  (see the module docstring)
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt  # pylint: disable=import-outside-toplevel
    figure, axes = plt.subplots(8, 2 * max(len(series), 1), sharex=True, squeeze=False,
                                figsize=(11 * max(len(series), 1), 17),
                                gridspec_kw={'width_ratios': [3, 2] * max(len(series), 1)})
    figure.suptitle(title)
    for c, (side, data) in enumerate(sorted(series.items())):
        value_axes, error_axes = axes[:, 2 * c], axes[:, 2 * c + 1]
        for j, label in enumerate(JOINT_LABELS):
            value_axes[j].plot(time_s, np.degrees(data['puppet'][:, j]), color='0.6', lw=3,
                               label='puppet %s, mapped' % data['driver'])
            value_axes[j].plot(time_s, np.degrees(data['commanded'][:, j]), 'C0', lw=1,
                               label='commanded')
            value_axes[j].plot(time_s, np.degrees(data['measured'][:, j]), 'C1--', lw=1,
                               label='measured')
            value_axes[j].set_ylabel('%s_%s (deg)' % (side, label))
            error_axes[j].plot(time_s, np.degrees(data['error'][:, j]), 'C3', lw=0.8)
            error_axes[j].axhline(0.0, color='0.7', lw=0.5)
            error_axes[j].set_ylabel('%s_%s error (deg)' % (side, label))
        value_axes[0].legend(fontsize=7, loc='upper right', ncol=3)
        error_axes[0].set_title('tracking error: commanded - measured', fontsize=9)
        value_axes[7].plot(time_s, data['end_piece'], color='0.6', lw=3,
                           label='puppet end piece (1 released)')
        value_axes[7].plot(time_s, data['gripper_commanded'], 'C0', lw=1,
                           label='commanded opening')
        value_axes[7].plot(time_s, data['gripper_measured'], 'C1--', lw=1,
                           label='measured opening')
        value_axes[7].set_ylim(-0.05, 1.2)
        value_axes[7].set_ylabel('%s gripper (0..1)' % side)
        value_axes[7].legend(fontsize=7, loc='upper right', ncol=3)
        error_axes[7].plot(time_s, data['gripper_commanded'] - data['gripper_measured'], 'C3',
                           lw=0.8)
        error_axes[7].set_ylabel('%s gripper error' % side)
        for axis in (value_axes[7], error_axes[7]):
            axis.set_xlabel('time (s)')
    figure.tight_layout(rect=(0, 0, 1, 0.98))
    figure.savefig(path, format='png', dpi=80)
    plt.close(figure)
