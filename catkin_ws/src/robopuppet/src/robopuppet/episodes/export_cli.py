"""The terminal command export: recorded episodes to ALOHA's HDF5, Rethink's CSV and a plot.

    rosrun robopuppet export EPISODE... [--format aloha-hdf5|csv|all]... [--rate HZ]
                                        [--out DIR] [--plot] [--cameras NAME,... | --no-images]

An EPISODE is a name (looked up in $ROS_HOME/robopuppet/episodes/, ROS_HOME defaulting to
~/.ros) or the path of its .bag or .yaml. Each episode exports on its own: a bad one gets an
error line and the others still export; the exit code is 1 if any failed. The HDF5 gets the
images of every camera with frames in the bag, of the --cameras named (each must have frames),
or none (--no-images).
"""
import argparse
import os
import signal
import sys
import time

from robopuppet.episodes import export, export_files, export_images, export_run

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


def export_episode(episode, formats, rate_hz, out_dir, plot, say, cameras=None):
    """Export one episode; return the paths written. say(text) reports progress, and what
    could not be read and was skipped. cameras: the cameras whose images the HDF5 gets (None:
    all in the bag, []: none).

    Raises:
        export_files.EpisodeError, export.ExportError: the episode cannot be exported.
    """
    bag_path, yaml_path = export_files.episode_paths(resolve(episode))
    name = os.path.basename(bag_path)[:-len('.bag')]
    metadata = export_files.read_metadata(yaml_path)
    if not metadata:
        say('%s: no %s: taking sim as false' % (name, os.path.basename(yaml_path)))
    out_dir = out_dir or os.path.dirname(os.path.abspath(bag_path))
    say('%s: reading %s (%.1f MB)' % (name, bag_path, os.path.getsize(bag_path) / 1e6))
    for suffix in OUTPUT_SUFFIXES:
        remove_stale_parts(os.path.join(out_dir, name + suffix))
    outputs = {kind: _Output(os.path.join(out_dir, name + suffix)) for kind, suffix in
               (('aloha-hdf5', '.hdf5'), ('csv', '.csv'), ('plot', '.png'))
               if kind in formats or (kind == 'plot' and plot)}
    if 'aloha-hdf5' in formats:
        cameras = _cameras(bag_path, name, metadata, cameras, say)
    skipped = export_files.Skipped()
    try:
        export_run.write(bag_path, name, outputs, rate_hz, bool(metadata.get('sim')), cameras,
                         skipped, lambda text: say('%s: %s' % (name, text)),
                         _progress(name, say, time.monotonic()))
        for output in outputs.values():
            output.done()
    finally:
        for output in outputs.values():
            output.discard()
    for line in skipped.lines():
        say('%s: %s' % (name, line))
    for output in outputs.values():
        say('%s: wrote %s' % (name, output.path))
    return [output.path for output in outputs.values()], skipped


def parse_args(argv):
    """Return the parsed command line (formats: a set; aloha-hdf5 when neither --format nor
    --plot is given)."""
    parser = argparse.ArgumentParser(
        prog='export', description='Export recorded demonstration episodes.')
    parser.add_argument('episodes', nargs='+', metavar='EPISODE',
                        help='episode name (in %s) or its .bag/.yaml path'
                        % export_files.default_episodes_dir())
    parser.add_argument('--format', action='append', dest='formats',
                        choices=sorted(FORMATS) + ['all'],
                        help='aloha-hdf5 (one .hdf5 per episode), csv (Rethink joint_recorder) '
                             'or all; repeatable (default aloha-hdf5 unless only --plot)')
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
    args = parser.parse_args(argv)
    if not (args.rate > 0 and args.rate < float('inf')):
        parser.error('--rate must be a positive number of Hz')
    chosen = set(args.formats or ([] if args.plot else ['aloha-hdf5']))
    args.formats = set(FORMATS) if 'all' in chosen else chosen
    if args.cameras is not None and 'aloha-hdf5' not in args.formats:
        parser.error('--cameras and --no-images apply to --format aloha-hdf5')
    return args


def _names(text):
    """Return the names of a comma-separated list (argparse type)."""
    names = [name.strip() for name in text.split(',') if name.strip()]
    if not names:
        raise argparse.ArgumentTypeError('give one or more camera names')
    return names


def main(argv=None):
    """Run the command; exit 0 when every episode exported, 1 otherwise."""
    args = parse_args(sys.argv[1:] if argv is None else argv)
    if args.out:
        os.makedirs(args.out, exist_ok=True)
    signal.signal(signal.SIGTERM, _terminated)  # so that the .part files are removed
    failed, damaged = 0, 0
    for episode in args.episodes:
        try:
            _, skipped = export_episode(episode, args.formats, args.rate, args.out, args.plot,
                                        lambda text: print('export: ' + text, flush=True),
                                        args.cameras)
            damaged += bool(skipped.reasons)
        except (export_files.EpisodeError, export.ExportError, OSError) as error:
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
