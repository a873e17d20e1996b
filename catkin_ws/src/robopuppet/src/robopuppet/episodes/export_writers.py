"""The exporter's writers: ALOHA's HDF5 (written in blocks of grid steps as they come, then the
camera images frame by frame), Rethink's CSV and the episode's plot (PNG). The rows come from
robopuppet.episodes.export (export_stream), the camera images from
robopuppet.episodes.export_images.

Pure (numpy, h5py, matplotlib with the Agg backend: no display needed). h5py and matplotlib are
imported where they write, so that the replay command, which only reads bags, starts seconds
sooner.
"""
import numpy as np

from robopuppet.arm.joint_motion import mirror
from robopuppet.baxter_description import arm_joint_names
from robopuppet.episodes import export, export_images
from robopuppet.episodes.export import COLUMNS
from robopuppet.interface import BAXTER_SIDE

# The images' HDF5 filter. lzf (h5py's own): 15 s of CPU per minute of three simulated cameras
# at 50 Hz, 40 s for photographs; gzip (level 4): 37 and 116 s for 22 and 13 % fewer bytes
# (benchmarks/bench_export.py --compression, docs/demonstrations.md). h5py reads both.
IMAGE_COMPRESSION = 'lzf'
JOINT_LABELS = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
ROW_DATASETS = ('observations/qpos', 'observations/qvel', 'observations/effort', 'action')


class Hdf5File:
    """ALOHA's layout, written as it comes: attrs sim, columns (the column names), rate_hz
    and episode; /observations/qpos, qvel, effort and /action (steps, 16) float32 in COLUMNS
    order, written a block of rows at a time (write_rows); then the images (write_images).
    """

    def __init__(self, path, steps, sim, rate_hz, name):
        import h5py  # pylint: disable=import-outside-toplevel  (see the module docstring)
        self.steps = steps
        self.root = h5py.File(path, 'w')
        self.root.attrs['sim'] = bool(sim)
        self.root.attrs['columns'] = np.array(COLUMNS, dtype=h5py.string_dtype())
        self.root.attrs['rate_hz'] = float(rate_hz)
        self.root.attrs['episode'] = name
        self.root.create_group('observations')
        for dataset in ROW_DATASETS:
            self.root.create_dataset(dataset, (steps, len(COLUMNS)), dtype=np.float32)

    def write_rows(self, block):
        """Write a block's rows (a dict with start and (n, 16) qpos, qvel, effort, action)."""
        start, stop = block['start'], block['start'] + len(block['qpos'])
        for dataset in ROW_DATASETS:
            self.root[dataset][start:stop] = block[dataset.split('/')[-1]].astype(np.float32)

    def write_images(self, time_s, frames=(), progress=None, compression=IMAGE_COMPRESSION):
        """Write the group /observations/images: per camera of frames ((camera, t, JPEG bytes)
        in time order, t on time_s's clock) a dataset <camera> (steps, H, W, 3) uint8 RGB with
        chunks of one image, like ALOHA's, compressed by the filter compression (h5py undoes it
        when reading). Each frame is decoded and compressed once; the steps that repeat it get
        a copy of its stored chunk. progress(fraction 0..1) is called after each run of steps.

        Returns:
            lines worth reporting about the images (export_images.ImageResampler.report).
        Raises:
            export.ExportError: a camera has no frame that decodes.
        """
        resampler = export_images.ImageResampler(time_s)
        images, datasets = self.root['observations'].create_group('images'), {}
        for run in _runs(resampler, frames):
            if run.camera not in datasets:
                datasets[run.camera] = images.create_dataset(
                    run.camera, (self.steps,) + run.image.shape, dtype=np.uint8,
                    chunks=(1,) + run.image.shape, compression=compression)
            _write_run(datasets[run.camera], run)
            if progress:
                progress(run.stop / self.steps)
        return resampler.report()

    def close(self):
        self.root.close()


def write_hdf5(path, arrays, sim, rate_hz, name, frames=(), progress=None,
               compression=IMAGE_COMPRESSION):
    """Write whole arrays (export.aloha_arrays) and frames as Hdf5File does; return its report
    of the images."""
    hdf5 = Hdf5File(path, len(arrays['time']), sim, rate_hz, name)
    try:
        hdf5.write_rows(dict(arrays, start=0))
        return hdf5.write_images(arrays['time'], frames, progress, compression)
    finally:
        hdf5.close()


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


def puppet_driver(follow, puppet_sides, baxter_side):
    """Return the puppet side that drove a Baxter arm: the first whose teleop_state said it
    followed (follow: {Baxter side: puppet sides}), else the puppet side with angles
    (puppet_sides) on that side, else any with angles (None)."""
    with_angles = [s for s in export.PUPPET_SIDES if s in puppet_sides]
    if follow[baxter_side]:
        return follow[baxter_side][0]
    same = [s for s in with_angles if BAXTER_SIDE[s] == baxter_side]
    return (same or with_angles or [None])[0]


def plot_series(recording, arrays):
    """Return plot_rows' series of a Recording and its aloha_arrays."""
    grid = arrays['time'] + recording.position.times[0]
    sides = export.PUPPET_SIDES
    return plot_rows(arrays, {s: export.interpolate(recording.puppet[s], grid) for s in sides},
                     {s: export.interpolate(recording.end_piece[s], grid)[:, 0] for s in sides},
                     {s for s in export.BAXTER_SIDES if len(recording.command[s].times)},
                     {s for s in export.PUPPET_SIDES if len(recording.puppet[s].times)},
                     recording.follow)


def plot_rows(arrays, puppet, end_piece, commanded_sides, puppet_sides, follow):
    """Return {Baxter side: dict} for the plot, of each arm that got position commands
    (commanded_sides; of the recorded puppet sides' arms if none did): puppet (T, 7) the
    driving puppet's angles as that arm takes them (mirrored on the opposite side; NaN without
    a puppet), commanded, measured and error = commanded - measured (T, 7) rad,
    gripper_commanded and gripper_measured (T,) opening 0..1, end_piece (T,) the puppet's
    end-piece reading (~1 released). puppet, end_piece: {puppet side: its rows on the grid}."""
    steps = len(arrays['time'])
    sides = [s for s in export.BAXTER_SIDES if s in commanded_sides]
    sides = sides or [BAXTER_SIDE[s] for s in export.PUPPET_SIDES
                      if s in puppet_sides]
    series = {}
    for side in sides:
        columns = [export.COLUMNS.index(name) for name in arm_joint_names(side)]
        g = export.COLUMNS.index('%s_gripper' % side)
        driver = puppet_driver(follow, puppet_sides, side)
        angles, piece = np.full((steps, 7), np.nan), np.full(steps, np.nan)
        if driver is not None:
            angles, piece = puppet[driver], end_piece[driver]
            if BAXTER_SIDE[driver] != side:
                angles = np.array([mirror(row) for row in angles])
        commanded = arrays['commanded'][:, columns]
        measured = arrays['qpos'][:, columns]
        series[side] = {'driver': driver, 'puppet': angles, 'commanded': commanded,
                        'measured': measured, 'error': commanded - measured,
                        'gripper_commanded': arrays['commanded'][:, g],
                        'gripper_measured': arrays['qpos'][:, g], 'end_piece': piece}
    return series
