"""export --format lerobot: episodes into one LeRobotDataset v3.0 folder (--out DIR), a new one
or appended to the one there (docs/demonstrations.md, "LeRobot dataset").

All or nothing: the run writes into a work folder beside DIR (.<DIR>.lerobot.<pid>.part),
which holds hard links to an existing dataset's files (never written: a run appends new data,
video and episodes files, and writes info.json, stats.json and tasks.parquet anew), and swaps
it with DIR at the end (one renameat2 exchange). A failure, Ctrl-C or SIGTERM removes the work
folder, and the dataset in DIR stays as it was; a killed run's folder is removed by the next.
An episode that cannot be exported gets an error line and is left out; the others go in.
"""
import ctypes
import errno
import os
import shutil

from robopuppet.episodes import (export, export_files, lerobot_episode, lerobot_meta,
                                 lerobot_parquet, lerobot_video)
from robopuppet.episodes.metadata import EpisodeError, episode_paths, read_metadata

MB = 1024 * 1024
SOURCES_PATH = 'meta/robopuppet_episodes.json'  # ours: {episode_index: episode name}


def run(args, say, error, progress_period_s, resolve):
    """Export args.episodes into the dataset args.out; return the exit code (0: every
    episode in, or in already; 1: one failed, or nothing could be written). resolve(argument)
    gives an episode argument's path (export_cli.resolve)."""
    out = os.path.abspath(args.out)
    try:
        lerobot_parquet.pyarrow()
        if args.cameras != []:
            lerobot_video.ffmpeg()
        _remove_stale(out)
    except (ImportError, OSError) as problem:
        error('export: lerobot: error: %s' % problem)
        return 1
    work = os.path.join(os.path.dirname(out), '.%s.lerobot.%d.part' % (
        os.path.basename(out), os.getpid()))
    failed = 0
    try:
        dataset = _Dataset(out, work, args, say, resolve)
        progress = lerobot_episode.Progress(len(args.episodes), say, progress_period_s)
        for done, episode in enumerate(args.episodes):
            try:
                dataset.add(episode, lambda f, d=done: progress.update(d, f))
            except (EpisodeError, export.ExportError) as problem:
                failed += 1
                error('export: %s: error: %s' % (episode, problem))
        if dataset.added:
            dataset.finish()
            say('lerobot: %s: %d episodes added (%d frames), %d in all' % (
                out, len(dataset.added), dataset.new_frames, dataset.total_episodes))
        else:
            say('lerobot: no episode exported: %s left as it was' % out)
    except (OSError, ValueError) as problem:
        error('export: lerobot: error: %s; nothing written: %s is as it was' % (problem, out))
        return 1
    finally:
        if os.path.exists(work):
            shutil.rmtree(work, ignore_errors=True)
    if failed:
        error('export: %d of %d episodes failed (left out of the dataset)' % (
            failed, len(args.episodes)))
    return 1 if failed else 0


class _Dataset:
    """The dataset being written in the work folder."""

    def __init__(self, out, work, args, say, resolve):
        self.out, self.work, self.args, self.say = out, work, args, say
        self.resolve = resolve
        self.added, self.rows, self.stats, self.new_frames = [], [], [], 0
        info_path = os.path.join(out, lerobot_meta.INFO_PATH)
        self.info = None
        if os.path.exists(info_path):
            self.info = lerobot_parquet.read_json(info_path)
            _check_info(self.info, args.fps, out)
        elif os.path.isdir(out) and os.listdir(out):
            raise ValueError('%s is neither empty nor a LeRobot dataset (no %s)' % (
                out, lerobot_meta.INFO_PATH))
        os.makedirs(os.path.join(work, 'tmp'))
        sources = os.path.join(out, SOURCES_PATH)
        self.sources = lerobot_parquet.read_json(sources) if os.path.exists(sources) else {}
        if self.info:
            _link_tree(out, work)
            self.tasks = lerobot_parquet.read_tasks(os.path.join(out, lerobot_meta.TASKS_PATH))
            self.old_rows = lerobot_parquet.read_episodes(out)
            self.stats.append(lerobot_meta.from_json(lerobot_parquet.read_json(
                os.path.join(out, lerobot_meta.STATS_PATH))))
            self.cameras = sorted(k[len(lerobot_meta.IMAGE_PREFIX):]
                                  for k, f in self.info['features'].items()
                                  if f['dtype'] == 'video')
            say('lerobot: appending to %s (%d episodes, %d frames, cameras %s)' % (
                out, self.info['total_episodes'], self.info['total_frames'],
                ', '.join(self.cameras) or 'none'))
        else:
            self.tasks, self.old_rows, self.cameras = [], [], args.cameras
        self.total_episodes = self.info['total_episodes'] if self.info else 0
        self.total_frames = self.info['total_frames'] if self.info else 0
        self.features, self.schema, self.data_file = None, None, None
        self.videos = {}  # video key: [(chunk, file), [paths], frames in the file]

    def add(self, episode, progress):
        """Add one episode, or raise EpisodeError or export.ExportError leaving it out."""
        bag_path, yaml_path = episode_paths(self.resolve(episode))
        name = os.path.basename(bag_path)[:-len('.bag')]
        if name in self.sources.values():
            self.say('lerobot: %s: in the dataset already, as episode %s: skipped' % (
                name, next(i for i, n in self.sources.items() if n == name)))
            return
        metadata = read_metadata(yaml_path)
        cameras = self.cameras
        if cameras is None:  # a new dataset's: those of its first episode
            cameras = export_files.frame_cameras(bag_path)
        options = _Options(self.args.fps, cameras, self.args.image_size, self.args.puppet,
                           self.args.video_codec)
        self.say('lerobot: %s: reading %s (%.1f MB), cameras %s' % (
            name, bag_path, os.path.getsize(bag_path) / 1e6, ', '.join(cameras) or 'none'))
        progress(0.0)
        got = lerobot_episode.read(bag_path, name, metadata, options,
                                   os.path.join(self.work, 'tmp'), progress)
        features = lerobot_meta.features(
            self.args.fps, {c: size for c, (_, size) in got.videos.items()}, self.args.puppet,
            lerobot_video.settings(self.args.video_codec))
        why = lerobot_meta.same_features(
            self.info['features'] if self.info else self.features or features, features)
        if why:
            for path, _ in got.videos.values():
                os.remove(path)
            raise export.ExportError('it does not fit the dataset: %s' % why)
        self._write(got, features)
        self.cameras = cameras
        for line in got.skipped.lines():
            self.say('lerobot: %s: %s' % (name, line))
        self.say('lerobot: %s: episode %d, %d frames, task %r' % (
            name, self.total_episodes - 1, got.steps, got.task))

    def _write(self, got, features):
        if self.schema is None:
            self.features = features
            self.schema = lerobot_parquet.data_schema(features)
            self.files = lerobot_parquet.last_files(
                self.old_rows, [lerobot_meta.video_key(c) for c in got.videos])
        index = lerobot_parquet.task_index(self.tasks, got.task)
        columns, index_stats = lerobot_episode.index_columns(
            got, self.total_episodes, self.total_frames, index, self.args.fps)
        columns.update(got.columns)
        table = lerobot_parquet.data_table(self.schema, columns)
        if self.data_file and self.data_file.bytes + table.nbytes >= \
                lerobot_meta.DATA_FILES_SIZE_IN_MB * MB:
            self.data_file.close()
            self.data_file = None
            self.files['data'] = lerobot_meta.next_file(*self.files['data'])
        if self.data_file is None:
            self.data_file = lerobot_parquet.DataFile(self._path(
                lerobot_meta.DATA_PATH, *self.files['data']), self.schema)
        self.data_file.append(table)
        videos = {}
        for camera, (path, _) in sorted(got.videos.items()):
            videos[lerobot_meta.video_key(camera)] = self._add_video(camera, path, got.steps)
        stats = dict(got.stats, **index_stats)
        self.rows.append(lerobot_meta.episode_row(
            self.total_episodes, got.task, got.steps, self.files['data'], self.total_frames,
            self.files['meta'], videos, stats))
        self.stats.append(stats)
        self.added.append(got.name)
        self.sources[str(self.total_episodes)] = got.name
        self.total_episodes += 1
        self.total_frames += got.steps
        self.new_frames += got.steps

    def _add_video(self, camera, path, steps):
        """Queue an episode's video into its camera's current file; return its place."""
        key = lerobot_meta.video_key(camera)
        entry = self.videos.get(key)
        size = os.path.getsize(path)
        if entry and sum(map(os.path.getsize, entry[1])) + size >= \
                lerobot_meta.VIDEO_FILES_SIZE_IN_MB * MB:
            self._join(key, entry)
            entry = [lerobot_meta.next_file(*entry[0]), [], 0]
        if entry is None:
            entry = [self.files[key], [], 0]
        self.videos[key] = entry
        entry[1].append(path)
        from_s = entry[2] / float(self.args.fps)
        entry[2] += steps
        return entry[0] + (from_s, entry[2] / float(self.args.fps))

    def _join(self, key, entry):
        lerobot_video.join(entry[1], self._path(lerobot_meta.VIDEO_PATH, *entry[0],
                                                video_key=key))

    def finish(self):
        """Write the files that say what the dataset holds, then swap it in."""
        self.data_file.close()
        for key, entry in self.videos.items():
            self._join(key, entry)
        lerobot_parquet.write_episodes(self._path(lerobot_meta.EPISODES_PATH,
                                                  *self.files['meta']), self.rows)
        features = self.info['features'] if self.info else self.features
        for relative in (SOURCES_PATH, lerobot_meta.TASKS_PATH, lerobot_meta.STATS_PATH,
                         lerobot_meta.INFO_PATH):
            if os.path.exists(os.path.join(self.work, relative)):
                os.remove(os.path.join(self.work, relative))  # a link to the old file
        lerobot_parquet.write_json(os.path.join(self.work, SOURCES_PATH), self.sources)
        lerobot_parquet.write_tasks(os.path.join(self.work, lerobot_meta.TASKS_PATH),
                                    self.tasks)
        lerobot_parquet.write_json(os.path.join(self.work, lerobot_meta.STATS_PATH),
                                   lerobot_meta.to_json(lerobot_meta.aggregate_all(self.stats)))
        lerobot_parquet.write_json(os.path.join(self.work, lerobot_meta.INFO_PATH),
                                   lerobot_meta.info(self.args.fps, features,
                                                     self.total_episodes, self.total_frames,
                                                     len(self.tasks)))
        shutil.rmtree(os.path.join(self.work, 'tmp'))
        _swap(self.work, self.out)

    def _path(self, template, chunk_index, file_index, **keys):
        path = os.path.join(self.work, template.format(chunk_index=chunk_index,
                                                       file_index=file_index, **keys))
        os.makedirs(os.path.dirname(path), exist_ok=True)
        return path


class _Options:
    def __init__(self, fps, cameras, size, puppet, codec):
        self.fps, self.cameras, self.size = fps, list(cameras), size
        self.puppet, self.codec = puppet, codec


def _check_info(info, fps, out):
    if info.get('codebase_version') != lerobot_meta.CODEBASE_VERSION:
        raise ValueError('%s is a LeRobot dataset of format %s, not %s: export into a new '
                         'folder' % (out, info.get('codebase_version'),
                                     lerobot_meta.CODEBASE_VERSION))
    if info.get('fps') != fps:
        raise ValueError('%s is at %s frames/s: give --fps %s' % (out, info.get('fps'),
                                                                   info.get('fps')))


def _link_tree(source, target):
    """Hard-link every file of source into target (same file system: beside it)."""
    for folder, _, files in os.walk(source):
        into = os.path.join(target, os.path.relpath(folder, source))
        os.makedirs(into, exist_ok=True)
        for name in files:
            os.link(os.path.join(folder, name), os.path.join(into, name))


def _swap(work, out):
    """Put the work folder at out: a rename, or an atomic exchange with the old dataset (then
    removed)."""
    if not os.path.exists(out) or (os.path.isdir(out) and not os.listdir(out)):
        os.rename(work, out)
        return
    libc = ctypes.CDLL(None, use_errno=True)
    at_fdcwd, rename_exchange = -100, 2
    if libc.renameat2(at_fdcwd, work.encode(), at_fdcwd, out.encode(), rename_exchange) == 0:
        shutil.rmtree(work)  # now the old dataset's links
        return
    code = ctypes.get_errno()
    if code not in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        raise OSError(code, 'cannot swap %s into %s: %s' % (work, out, os.strerror(code)))
    # A file system without the exchange (e.g. NFS): two renames; between them DIR is absent
    # for an instant, never half-written, and the old dataset is kept aside until then.
    aside = work + '.old'
    os.rename(out, aside)
    os.rename(work, out)
    shutil.rmtree(aside)


def _remove_stale(out):
    """Remove the work folders of killed runs into out (their process gone)."""
    folder, base = os.path.split(out)
    prefix = '.%s.lerobot.' % base
    for name in os.listdir(folder or '.') if os.path.isdir(folder or '.') else []:
        pid = name[len(prefix):-len('.part')]
        if name.startswith(prefix) and name.endswith('.part') and pid.isdigit():
            try:
                os.kill(int(pid), 0)
            except ProcessLookupError:
                shutil.rmtree(os.path.join(folder, name), ignore_errors=True)
            except PermissionError:
                pass
