"""One episode's export, streamed: the bag's messages read one chunk at a time, resampled onto
the grid as they come (export_stream) and written in blocks of steps to the HDF5 and the CSV;
then the camera frames, one at a time, into the HDF5. Memory holds a few seconds of messages
and one image per camera, whatever the episode's length; only the plot (--plot) keeps its
series, about 0.5 kB per grid step.
"""
import time

import numpy as np

from robopuppet.episodes import (bag_chunks, export, export_files, export_plot, export_stream,
                                 export_writers)
from robopuppet.interface import ROBOT_JOINT_STATES


def write(bag_path, name, outputs, rate_hz, sim, cameras, skipped, say, progress, size=None,
          compression=export_writers.IMAGE_COMPRESSION):
    """Write an episode's outputs ({'aloha-hdf5' | 'csv' | 'plot': an object with .partial,
    the path to write}); skipped (bag_chunks.Skipped) counts what cannot be read. The HDF5's
    images are scaled to size (W, H; None: as recorded) and stored with the HDF5 filter
    compression.

    Raises:
        metadata.EpisodeError, export.ExportError: the episode cannot be exported.
    """
    started = time.monotonic()
    bag = bag_chunks.open_bag(bag_path)
    with bag:
        topics = export.episode_topics()
        t0, spans = bag_chunks.index_times(bag, topics)
        if ROBOT_JOINT_STATES not in spans:
            raise export.no_joint_states()
        start, end = spans[ROBOT_JOINT_STATES]
        start_s, end_s = (start - t0).to_sec(), (end - t0).to_sec()
        stream = export_stream.EpisodeStream(
            rate_hz, start_s, end_s,
            {topic: (last - t0).to_sec() for topic, (_, last) in spans.items()},
            plot='plot' in outputs)
        writers = _Writers(outputs, stream.steps, sim, rate_hz, name)
        try:
            for topic, msg, t in bag_chunks.messages(bag, topics, skipped=skipped, t0=t0):
                writers.add(stream.add(topic, msg, (t - t0).to_sec()))
            writers.add(stream.finish())
            say('%.1f s of episode, %d steps at %g Hz (%.1f s)' % (
                (stream.steps - 1) / rate_hz, stream.steps, rate_hz,
                time.monotonic() - started))
            if writers.hdf5 is not None:
                frames = (export_files.read_frames(bag_path, start, cameras, skipped)
                          if cameras != [] else ())
                grid_s = export.time_grid(start_s, end_s, rate_hz)
                for note in writers.hdf5.write_images(grid_s - grid_s[0], frames, progress,
                                                      compression, size):
                    say(note)
        finally:
            writers.close()
    if 'plot' in outputs:
        rows = {key: np.concatenate([b[key] for b in writers.plot_blocks])
                for key in ('time', 'qpos', 'commanded')}
        series = export_plot.plot_rows(
            rows, *[{s: np.concatenate([b[key][s] for b in writers.plot_blocks])
                     for s in export.PUPPET_SIDES} for key in ('puppet', 'end_piece')],
            stream.commanded_sides, stream.puppet_sides, stream.follow)
        title = '%s%s: puppet, commanded and measured Baxter angles' % (
            name, ' (sim)' if sim else '')
        export_plot.write_plot(outputs['plot'].partial, series, rows['time'], title)


class _Writers:
    """The outputs open while the rows stream: the HDF5, the CSV, the plot's rows."""

    def __init__(self, outputs, steps, sim, rate_hz, name):
        self.hdf5 = self.csv = None
        self.plot_blocks = [] if 'plot' in outputs else None
        if 'aloha-hdf5' in outputs:
            self.hdf5 = export_writers.Hdf5File(outputs['aloha-hdf5'].partial, steps, sim,
                                                rate_hz, name)
        if 'csv' in outputs:
            self.csv = open(outputs['csv'].partial, 'w')
            self.csv.write(','.join(export.CSV_HEADER) + '\n')

    def add(self, blocks):
        for block in blocks:
            if self.hdf5 is not None:
                self.hdf5.write_rows(block)
            if self.csv is not None:
                self.csv.write(''.join(line + '\n' for line in export.csv_lines(block)[1:]))
            if self.plot_blocks is not None:
                self.plot_blocks.append({key: block[key] for key in (
                    'time', 'qpos', 'commanded', 'puppet', 'end_piece')})

    def close(self):
        for output in (self.hdf5, self.csv):
            if output is not None:
                output.close()
