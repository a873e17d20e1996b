"""The terminal command export: recorded episodes to ALOHA's HDF5, Rethink's CSV and a plot.

    rosrun robopuppet export EPISODE... [--format aloha-hdf5|csv|all]... [--rate HZ]
                                        [--out DIR] [--plot] [--cameras NAME,... | --no-images]
                                        [--image-size WxH|full] [--compression lzf|gzip|none]
                                        [--act-dir DIR] [--yes]

An EPISODE is a name (looked up in $ROS_HOME/robopuppet/episodes/, ROS_HOME defaulting to
~/.ros) or the path of its .bag or .yaml. Each episode exports on its own: a bad one gets an
error line and the others still export; the exit code is 1 if any failed. The HDF5 gets the
images of every camera with frames in the bag, of the --cameras named (each must have frames),
or none (--no-images), scaled to --image-size (default 320x240). Before writing it, export says
its estimated size, and refuses one above 1 GB without --yes. --act-dir writes it as ACT's
loader opens it (export_act). --format lerobot: one LeRobotDataset in --out (lerobot_export).
"""
import argparse
import contextlib
import os
import shutil
import signal
import sys
import time

from robopuppet.episodes import (bag_chunks, export, export_act, export_files, export_images,
                                 export_run, export_size, export_writers, lerobot_export,
                                 lerobot_options)
from robopuppet.episodes.metadata import EpisodeError, episode_paths, read_metadata
from robopuppet.interface import ROBOT_JOINT_STATES

FORMATS = {'aloha-hdf5': '.hdf5', 'csv': '.csv'}
OUTPUT_SUFFIXES = ('.hdf5', '.csv', '.png')
PROGRESS_PERIOD_S = 10.0  # between the progress lines of a long image export


def resolve(episode):
    """Return an episode argument as a path: a bare name that is no file is looked up in
    the default episodes directory."""
    if os.sep in episode or os.path.exists(episode) or os.path.exists(episode + '.bag'):
        return episode
    return os.path.join(export_files.default_episodes_dir(), episode)


def remove_stale_parts(path):
    """Remove the <path>.<pid>.part files of runs that were killed (their process gone)."""
    folder, base = os.path.split(os.path.abspath(path))
    for leftover in os.listdir(folder or '.'):
        pid = leftover[len(base) + 1:-len('.part')]
        if leftover.startswith(base + '.') and leftover.endswith('.part') and pid.isdigit():
            try:
                os.kill(int(pid), 0)
            except ProcessLookupError:
                os.remove(os.path.join(folder, leftover))
            except PermissionError:
                pass  # another user's live process


class _Output:
    """A file written through its .part (so a failed or killed export leaves no half file),
    renamed to its name by done()."""

    def __init__(self, path):
        self.path, self.partial = path, '%s.%d.part' % (path, os.getpid())

    def done(self):
        os.replace(self.partial, self.path)

    def discard(self):
        if os.path.exists(self.partial):
            os.remove(self.partial)


def _cameras(bag_path, name, metadata, cameras, say):
    """Return the cameras to export: those named (each must have frames; [] for none) or, for
    None, all in the bag (read_frames finds them); say which listed ones have no frames."""
    listed = cameras if cameras is not None else metadata.get('cameras')
    listed = [c for c in listed if isinstance(c, str)] if isinstance(listed, list) else []
    counts = export_files.frame_counts(bag_path, listed)
    missing = [camera for camera in listed if not counts[camera]]
    if cameras is not None and missing:
        raise export.ExportError('no frames of %s in the bag (topics %s)' % (
            ', '.join(missing), ', '.join(map(export_images.frame_topic, missing))))
    if missing:
        say('%s: the metadata lists %s, but the bag has no frames of them' % (
            name, ', '.join(missing)))
    return cameras


def _progress(name, say, started):
    """Return a progress(fraction) that says how far the images are every PROGRESS_PERIOD_S."""
    last = [started]

    def progress(fraction):
        now = time.monotonic()
        if now - last[0] >= PROGRESS_PERIOD_S:
            last[0] = now
            say('%s: images %.0f %% (%.0f s)' % (name, 100.0 * fraction, now - started))
    return progress


def export_episode(episode, args, say):
    """Export one episode as args (parse_args) say; return the paths written and what was
    skipped. say(text) reports progress, and what could not be read and was skipped.

    Raises:
        EpisodeError, export.ExportError: the episode cannot be exported.
    """
    bag_path, yaml_path = episode_paths(resolve(episode))
    name = os.path.basename(bag_path)[:-len('.bag')]
    metadata = read_metadata(yaml_path)
    if not metadata:
        say('%s: no %s: taking sim as false' % (name, os.path.basename(yaml_path)))
    out_dir = args.out or os.path.dirname(os.path.abspath(bag_path))
    say('%s: reading %s (%.1f MB)' % (name, bag_path, os.path.getsize(bag_path) / 1e6))
    act = args.act_dir if 'aloha-hdf5' in args.formats else None
    with (export_act.locked(act, say) if act else contextlib.nullcontext()):
        paths = {kind: os.path.join(out_dir, name + suffix) for kind, suffix in
                 (('aloha-hdf5', '.hdf5'), ('csv', '.csv'), ('plot', '.png'))
                 if kind in args.formats or (kind == 'plot' and args.plot)}
        if act:
            index, reused = export_act.choose_index(act, name)
            paths['aloha-hdf5'] = os.path.join(act, export_act.file_name(index))
            say('%s: ACT index %d%s' % (name, index, ' (exported there before: written again)'
                                        if reused else ''))
        for path in set(paths.values()) | {os.path.join(out_dir, name + suffix)
                                           for suffix in OUTPUT_SUFFIXES}:
            remove_stale_parts(path)  # also of the formats not written this time
        outputs = {kind: _Output(path) for kind, path in paths.items()}
        cameras = args.cameras
        if 'aloha-hdf5' in outputs:
            cameras = _cameras(bag_path, name, metadata, cameras, say)
            _check_size(bag_path, name, cameras, args, os.path.dirname(paths['aloha-hdf5']),
                        say)
        skipped = bag_chunks.Skipped()
        try:
            export_run.write(bag_path, name, outputs, args.rate, bool(metadata.get('sim')),
                             cameras, skipped, lambda text: say('%s: %s' % (name, text)),
                             _progress(name, say, time.monotonic()), args.image_size,
                             export_writers.COMPRESSIONS[args.compression])
            for output in outputs.values():
                output.done()
        finally:
            for output in outputs.values():
                output.discard()
        if act:
            export_act.record(act, index, name)
            _check_act_dir(act, index, lambda text: say('%s: %s' % (name, text)))
    for line in skipped.lines():
        say('%s: %s' % (name, line))
    for output in outputs.values():
        say('%s: wrote %s' % (name, output.path))
    return [output.path for output in outputs.values()], skipped


def _check_size(bag_path, name, cameras, args, out_dir, say):
    """Say what the HDF5 will cost; refuse above export_size.LIMIT_BYTES without --yes.

    Raises:
        export.ExportError: too big without --yes.
    """
    span_s = export_files.span_s(bag_path, ROBOT_JOINT_STATES)
    if span_s is None:
        return  # export_run says so
    chosen = export_files.frame_cameras(bag_path) if cameras is None else cameras
    images = export_size.sample_images(export_files.read_frames(bag_path, None, chosen),
                                       chosen, args.image_size) if chosen else {}
    compression = export_writers.COMPRESSIONS[args.compression]
    estimate = export_size.estimate(len(export.time_grid(0.0, span_s, args.rate)), images,
                                    compression)
    say('%s: %s' % (name, export_size.text(estimate, compression)))
    why = export_size.too_big(estimate)
    if why and not args.yes:
        raise export.ExportError('the HDF5 would be about %s, %s' % (
            export_size.megabytes(estimate.total_bytes), why))
    free = shutil.disk_usage(out_dir).free
    if estimate.total_bytes > free:
        say('%s: warning: only %s free in %s' % (name, export_size.megabytes(free), out_dir))


def _check_act_dir(directory, index, say):
    """Say what would stop ACT's loader from reading the folder: missing indices (it opens
    0 .. N-1), episodes of other lengths (it stacks every episode's rows)."""
    missing = export_act.gaps(directory)
    if missing:
        say('warning: %s has no %s: ACT opens episode_0 .. episode_N-1' % (
            directory, ', '.join(map(export_act.file_name, missing))))
    counts = export_act.step_counts(directory)
    others = sorted({n for i, n in counts.items() if i != index and n != counts.get(index)})
    if others:
        say('warning: episode_%d has %d steps, others in %s have %s: ACT\'s loader stacks '
            'every episode\'s rows (its get_norm_stats), so they must be equally long' % (
                index, counts.get(index, 0), directory, ', '.join(map(str, others))))


def parse_args(argv):
    """Return the parsed command line (formats: a set; aloha-hdf5 when neither --format nor
    --plot is given)."""
    parser = argparse.ArgumentParser(
        prog='export', description='Export recorded demonstration episodes.')
    parser.add_argument('episodes', nargs='+', metavar='EPISODE',
                        help='episode name (in %s) or its .bag/.yaml path'
                        % export_files.default_episodes_dir())
    parser.add_argument('--format', action='append', dest='formats',
                        choices=sorted(FORMATS) + ['all', 'lerobot'],
                        help='aloha-hdf5 (one .hdf5 per episode), csv (Rethink joint_recorder) '
                             'or all; repeatable (default aloha-hdf5 unless only --plot); '
                             'lerobot: one LeRobotDataset v3.0 in --out DIR')
    parser.add_argument('--rate', type=float, default=export.DEFAULT_RATE_HZ, metavar='HZ',
                        help='resampling rate in Hz (default %(default)g)')
    parser.add_argument('--out', metavar='DIR',
                        help='output directory (default: beside each episode)')
    parser.add_argument('--plot', action='store_true',
                        help='also write <name>.png: puppet, commanded, measured, error, gripper')
    images = parser.add_mutually_exclusive_group()
    images.add_argument('--cameras', metavar='NAME,...', type=_names,
                        help='the HDF5 gets the images of these cameras only, e.g. '
                             'room_camera,right_hand_camera (default: every camera in the bag)')
    images.add_argument('--no-images', dest='cameras', action='store_const', const=[],
                        help='the HDF5 gets no images')
    parser.add_argument('--image-size', metavar='WxH|full', type=_size,
                        help='scale every image to W x H pixels, or keep them as recorded '
                             '(full); default %dx%d' % export_size.DEFAULT_IMAGE_SIZE)
    parser.add_argument('--compression', choices=sorted(export_writers.COMPRESSIONS),
                        help='the images\' HDF5 filter (default %s)'
                        % export_writers.IMAGE_COMPRESSION)
    parser.add_argument('--act-dir', metavar='DIR',
                        help='write the HDF5 as DIR/episode_<i>.hdf5, i after the highest there, '
                             'as ACT\'s loader opens them; DIR/%s maps i to the episode'
                             % export_act.INDEX_FILE)
    parser.add_argument('--yes', action='store_true',
                        help='write an HDF5 estimated above %s too'
                        % export_size.megabytes(export_size.LIMIT_BYTES))
    lerobot_options.add_arguments(parser)
    args = parser.parse_args(argv)
    if not (args.rate > 0 and args.rate < float('inf')):
        parser.error('--rate must be a positive number of Hz')
    chosen = set(args.formats or ([] if args.plot and not args.act_dir else ['aloha-hdf5']))
    args.formats = set(FORMATS) if 'all' in chosen else chosen
    if lerobot_options.check_arguments(parser, args, chosen):
        return args
    hdf5_only = [option for option, value in (
        ('--cameras and --no-images', args.cameras is not None),
        ('--image-size', args.image_size is not None), ('--compression', args.compression),
        ('--act-dir', args.act_dir)) if value]
    if hdf5_only and 'aloha-hdf5' not in args.formats:
        parser.error('%s apply to --format aloha-hdf5' % ', '.join(hdf5_only))
    args.image_size = (export_size.DEFAULT_IMAGE_SIZE if args.image_size is None
                       else args.image_size or None)  # 'full' parses as (): as recorded
    args.compression = args.compression or export_writers.IMAGE_COMPRESSION
    return args


def _size(text):
    """Return an --image-size as (W, H), () for full (argparse type)."""
    try:
        return export_size.parse_size(text) or ()
    except export_size.SizeError as error:
        raise argparse.ArgumentTypeError(str(error)) from error


def _names(text):
    """Return the names of a comma-separated list (argparse type)."""
    names = [name.strip() for name in text.split(',') if name.strip()]
    if not names:
        raise argparse.ArgumentTypeError('give one or more camera names')
    return names


def main(argv=None):
    """Run the command; exit 0 when every episode exported, 1 otherwise."""
    args = parse_args(sys.argv[1:] if argv is None else argv)
    for directory in (args.out, args.act_dir):
        if directory:
            os.makedirs(directory, exist_ok=True)
    signal.signal(signal.SIGTERM, _terminated)  # so that the .part files are removed
    if 'lerobot' in args.formats:
        sys.exit(lerobot_export.run(args, lambda text: print('export: ' + text, flush=True),
                                    lambda text: print(text, file=sys.stderr, flush=True),
                                    PROGRESS_PERIOD_S, resolve))
    failed, damaged = 0, 0
    for episode in args.episodes:
        try:
            _, skipped = export_episode(
                episode, args, lambda text: print('export: ' + text, flush=True))
            damaged += bool(skipped.reasons)
        except (EpisodeError, export.ExportError, OSError) as error:
            failed += 1
            print('export: %s: error: %s' % (episode, error), file=sys.stderr, flush=True)
    if damaged:
        print('export: %d of %d episodes exported without what could not be read (see '
              '"skipped" above)' % (damaged, len(args.episodes)), file=sys.stderr)
    if failed:
        print('export: %d of %d episodes failed' % (failed, len(args.episodes)),
              file=sys.stderr)
    sys.exit(1 if failed else 0)


def _terminated(signum, _frame):
    """Exit on SIGTERM as on Ctrl-C: through the finally clauses that remove .part files."""
    sys.exit(128 + signum)
