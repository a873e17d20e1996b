"""The exporter's writers: ALOHA's HDF5 (written in blocks of grid steps as they come, then the
camera images frame by frame) and Rethink's CSV; the plot is robopuppet.episodes.export_plot.
The rows come from robopuppet.episodes.export (export_stream), the camera images from
robopuppet.episodes.export_images.

Pure (numpy, h5py). h5py is imported where it writes, so that the replay command, which only
reads bags, starts sooner.
"""
import numpy as np

from robopuppet.episodes import export_images
from robopuppet.episodes.export import COLUMNS

# The images' HDF5 filter. lzf (h5py's own): 15 s of CPU per minute of three simulated cameras
# at 50 Hz, 40 s for photographs; gzip (level 4): 37 and 116 s for 22 and 13 % fewer bytes
# (benchmarks/bench_export.py --compression, docs/demonstrations.md). h5py reads both.
IMAGE_COMPRESSION = 'lzf'
COMPRESSIONS = {'lzf': 'lzf', 'gzip': 'gzip', 'none': None}  # export --compression: filter
ROW_DATASETS = ('observations/qpos', 'observations/qvel', 'observations/effort', 'action')


class Hdf5File:
    """ALOHA's layout, written as it comes: attrs sim, columns (the column names), rate_hz,
    fps (the same rate, the name LeRobot's ALOHA datasets give it) and episode;
    /observations/qpos, qvel, effort and /action (steps, 16) float32 in COLUMNS order, written
    a block of rows at a time (write_rows); then the images (write_images).
    """

    def __init__(self, path, steps, sim, rate_hz, name):
        import h5py  # pylint: disable=import-outside-toplevel  (see the module docstring)
        self.steps = steps
        self.root = h5py.File(path, 'w')
        self.root.attrs['sim'] = bool(sim)
        self.root.attrs['columns'] = np.array(COLUMNS, dtype=h5py.string_dtype())
        self.root.attrs['rate_hz'] = float(rate_hz)
        self.root.attrs['fps'] = float(rate_hz)
        self.root.attrs['episode'] = name
        self.root.create_group('observations')
        for dataset in ROW_DATASETS:
            self.root.create_dataset(dataset, (steps, len(COLUMNS)), dtype=np.float32)

    def write_rows(self, block):
        """Write a block's rows (a dict with start and (n, 16) qpos, qvel, effort, action)."""
        start, stop = block['start'], block['start'] + len(block['qpos'])
        for dataset in ROW_DATASETS:
            self.root[dataset][start:stop] = block[dataset.split('/')[-1]].astype(np.float32)

    def write_images(self, time_s, frames=(), progress=None, compression=IMAGE_COMPRESSION,
                     size=None):
        """Write the group /observations/images: per camera of frames ((camera, t, JPEG bytes)
        in time order, t on time_s's clock) a dataset <camera> (steps, H, W, 3) uint8 RGB with
        chunks of one image, like ALOHA's, compressed by the filter compression (h5py undoes it
        when reading); size (W, H) scales every image to it (None: as recorded). Each frame is
        decoded and compressed once; the steps that repeat it get a copy of its stored chunk.
        progress(fraction 0..1) is called after each run of steps.

        Returns:
            lines worth reporting about the images (export_images.ImageResampler.report).
        Raises:
            export.ExportError: a camera has no frame that decodes.
        """
        resampler = export_images.ImageResampler(time_s, size)
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
               compression=IMAGE_COMPRESSION, size=None):
    """Write whole arrays (export.aloha_arrays) and frames as Hdf5File does; return its report
    of the images."""
    hdf5 = Hdf5File(path, len(arrays['time']), sim, rate_hz, name)
    try:
        hdf5.write_rows(dict(arrays, start=0))
        return hdf5.write_images(arrays['time'], frames, progress, compression, size)
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
