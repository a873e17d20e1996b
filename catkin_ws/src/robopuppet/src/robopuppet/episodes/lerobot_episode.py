"""One episode made into a LeRobot dataset's frames: its rows on the export's time grid at the
dataset's fps (export_stream: the HDF5's numbers), each camera's frames held onto the same grid
(export_images) and piped into a video (lerobot_video), and the statistics of both.

Nothing of the dataset is touched here: the rows come back as arrays and the videos as files
in a work folder, which lerobot_export adds to the dataset once the whole episode succeeded.
"""
import collections
import os
import time

import numpy as np

from robopuppet.episodes import (bag_chunks, export, export_files, export_images, export_stream,
                                 lerobot_meta, lerobot_video)
from robopuppet.interface import PUPPET_SIDES, ROBOT_JOINT_STATES

ROW_FEATURES = ((lerobot_meta.STATE, 'qpos'), (lerobot_meta.ACTION, 'action'),
                (lerobot_meta.VELOCITY, 'qvel'), (lerobot_meta.EFFORT, 'effort'))

Episode = collections.namedtuple('Episode', 'name task steps columns videos stats skipped')
Episode.__doc__ = """An episode ready to add: name, task (text), steps (frames), columns
({feature: (steps, k) float32 array} of the rows' vectors), videos ({camera: (path, (W, H))}),
stats ({feature: stats} of the vectors and videos; the index columns' come with the dataset's
indices), skipped (bag_chunks.Skipped)."""


def task_of(metadata):
    """Return an episode's task: its metadata's task, else its notes, else
    lerobot_meta.DEFAULT_TASK."""
    for key in ('task', 'notes'):
        text = metadata.get(key)
        if isinstance(text, str) and text.strip():
            return text.strip()
    return lerobot_meta.DEFAULT_TASK


def check_cameras(bag_path, cameras):
    """Raise export.ExportError unless the bag has frames of every camera."""
    counts = export_files.frame_counts(bag_path, cameras)
    missing = [camera for camera in cameras if not counts[camera]]
    if missing:
        raise export.ExportError('no frames of %s in the bag (topics %s): every episode of '
                                 'a dataset has the same cameras' % (
                                     ', '.join(missing),
                                     ', '.join(map(export_images.frame_topic, missing))))


def read(bag_path, name, metadata, options, work_dir, progress):
    """Return the Episode of a bag: options has fps, cameras (list), size ((W, H) or None),
    puppet (bool), codec; the videos are written into work_dir; progress(fraction) is called
    as the frames are encoded.

    Raises:
        metadata.EpisodeError, export.ExportError: the episode cannot be exported.
        lerobot_video.VideoError: ffmpeg failed (e.g. the disk is full).
    """
    check_cameras(bag_path, options.cameras)
    skipped = bag_chunks.Skipped()
    bag = bag_chunks.open_bag(bag_path)
    with bag:
        t0, spans = bag_chunks.index_times(bag, export.episode_topics())
        if ROBOT_JOINT_STATES not in spans:
            raise export.no_joint_states()
        start, end = spans[ROBOT_JOINT_STATES]
        start_s, end_s = (start - t0).to_sec(), (end - t0).to_sec()
        stream = export_stream.EpisodeStream(
            options.fps, start_s, end_s,
            {topic: (last - t0).to_sec() for topic, (_, last) in spans.items()},
            plot=options.puppet)
        blocks = []
        for topic, msg, t in bag_chunks.messages(bag, export.episode_topics(),
                                                 skipped=skipped, t0=t0):
            blocks += stream.add(topic, msg, (t - t0).to_sec())
        blocks += stream.finish()
    columns = {feature: np.concatenate([b[key] for b in blocks]).astype(np.float32)
               for feature, key in ROW_FEATURES}
    if options.puppet:
        columns[lerobot_meta.PUPPET] = np.nan_to_num(np.concatenate(
            [np.hstack([b['puppet'][side] for side in PUPPET_SIDES]) for b in blocks]),
            nan=0.0).astype(np.float32)
    stats = {feature: lerobot_meta.vector_stats(values) for feature, values in columns.items()}
    videos, image_stats = _videos(bag_path, name, start, stream.steps, options, work_dir,
                                  skipped, progress)
    stats.update({lerobot_meta.video_key(c): s.stats() for c, s in image_stats.items()})
    return Episode(name, task_of(metadata), stream.steps, columns, videos, stats, skipped)


def _videos(bag_path, name, start, steps, options, work_dir, skipped, progress):
    """Encode each camera's frames held onto the grid; return ({camera: (path, (W, H))},
    {camera: ImageStats})."""
    if not options.cameras:
        return {}, {}
    grid_s = np.arange(steps) / float(options.fps)
    resampler = export_images.ImageResampler(grid_s, options.size)
    sampled = np.array(lerobot_meta.sample_indices(steps))
    encoders, image_stats = {}, {}
    try:
        frames = export_files.read_frames(bag_path, start, options.cameras, skipped)
        for run in _runs(resampler, frames):
            encoder = encoders.get(run.camera)
            if encoder is None:
                size = (run.image.shape[1], run.image.shape[0])
                if size[0] % 2 or size[1] % 2:
                    raise export.ExportError(
                        '%s: %dx%d images: the video needs an even width and height (give '
                        '--image-size)' % (run.camera, size[0], size[1]))
                path = os.path.join(work_dir, '%s.%s.mp4' % (name, run.camera))
                encoder = encoders[run.camera] = lerobot_video.Encoder(
                    path, size, options.fps, options.codec)
                image_stats[run.camera] = lerobot_meta.ImageStats()
            encoder.write(run.image, run.stop - run.start)
            for _ in range(np.count_nonzero((sampled >= run.start) & (sampled < run.stop))):
                image_stats[run.camera].add(run.image)
            progress(min(e.frames for e in encoders.values()) / steps
                     if len(encoders) == len(options.cameras) else 0.0)
        videos = {}
        for camera, encoder in encoders.items():
            frames_written = encoder.close()
            if frames_written != steps:
                raise export.ExportError('%s: %d video frames for %d steps' % (
                    camera, frames_written, steps))
            videos[camera] = (encoder.path, encoder.size)
        return videos, image_stats
    except BaseException:
        for encoder in encoders.values():
            encoder.abort()
            if os.path.exists(encoder.path):
                os.remove(encoder.path)
        raise


def _runs(resampler, frames):
    for camera, t_s, data in frames:
        yield from resampler.add(camera, t_s, data)
    yield from resampler.finish()


def index_columns(episode, episode_index, first_index, task_index, fps):
    """Return the five index columns of an episode's rows and their statistics."""
    frames = np.arange(episode.steps)
    columns = {'timestamp': (frames / float(fps)).astype(np.float32),
               'frame_index': frames.astype(np.int64),
               'episode_index': np.full(episode.steps, episode_index, np.int64),
               'index': (first_index + frames).astype(np.int64),
               'task_index': np.full(episode.steps, task_index, np.int64)}
    return columns, {key: lerobot_meta.vector_stats(values) for key, values in columns.items()}


class Progress:
    """A progress bar, one line every period_s: the episodes done and the current one's
    frames, e.g. 'lerobot: [#####...............] 26 %: episode 2 of 4, its frames 4 %, 31 s'."""

    def __init__(self, total, say, period_s, width=20):
        self.total, self.say, self.period_s, self.width = total, say, period_s, width
        self.started = self.last = time.monotonic()

    def update(self, done, fraction):
        now = time.monotonic()
        if now - self.last < self.period_s:
            return
        self.last = now
        whole = (done + fraction) / self.total
        filled = int(round(whole * self.width))
        self.say('lerobot: [%s%s] %3.0f %%: episode %d of %d, its frames %.0f %%, %.0f s' % (
            '#' * filled, '.' * (self.width - filled), 100 * whole, done + 1, self.total,
            100 * fraction, now - self.started))
