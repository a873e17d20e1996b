"""The terminal command episodes: the episodes of a folder, one line each, oldest first.

    rosrun robopuppet episodes [DIR]
    rosrun robopuppet episodes set-task EPISODE... --task TEXT   (episode_task)

DIR defaults to $ROS_HOME/robopuppet/episodes/ (ROS_HOME defaulting to ~/.ros). Each line: the
name, start (local time), duration, puppet sides, cameras, the bag's size, how it ended, the
files exported beside it, the task (its first TASK_CHARS characters, '-' for none) and the
notes. How it ended: `clean` (stopped), `repaired` (the
recorder repaired it after a crash: ended_cleanly false), `recording` (a .bag.active: still
being recorded, or left by a crash that the recorder's next start repairs), `broken` (a
.bag.broken: beyond repair). Reads only the folder and the .yaml files (no bag is opened).
"""
import argparse
import collections
import datetime
import os
import sys

from robopuppet.episodes import export_files, recording
from robopuppet.episodes.metadata import metadata_or_empty
from robopuppet.interface import PUPPET_SIDES

EXPORTED = (('.hdf5', 'hdf5'), ('.csv', 'csv'), ('.png', 'png'))
BROKEN = '.bag.broken'
ENDINGS = ((recording.ACTIVE, 'recording'), (BROKEN, 'broken'), (recording.BAG, None))
HEADER = ('episode', 'start', 'duration', 'sides', 'cameras', 'size', 'ended', 'exported',
          'task', 'notes')
TASK_CHARS = 50   # of a task shown in the list (the .yaml holds it whole)

Entry = collections.namedtuple('Entry', 'name start duration_s sides cameras size_bytes ended '
                                        'exported task notes')
Entry.__doc__ = """One episode: name, start (datetime, local; None when unknown), duration_s
(None when unknown), sides ('R', 'LR'), cameras (count; None when unknown), size_bytes (its
bag), ended ('clean', 'repaired', 'recording', 'broken'), exported (['hdf5', 'csv', 'png'] of
the files beside it), task ('' for none), notes."""


def _start(metadata, name):
    """Return the start as a local datetime: the metadata's start_time (UTC), else the name's
    (local), else None."""
    text = metadata.get('start_time')
    if isinstance(text, str):
        try:
            utc = datetime.datetime.strptime(text.rstrip('Z')[:19], '%Y-%m-%dT%H:%M:%S')
            return utc.replace(tzinfo=datetime.timezone.utc).astimezone().replace(tzinfo=None)
        except ValueError:
            pass
    stamp = name[len(recording.NAME_PREFIX):len(recording.NAME_PREFIX) + 15]
    try:
        return datetime.datetime.strptime(stamp, '%Y%m%d-%H%M%S')
    except ValueError:
        return None


def entries(directory):
    """Return the Entry of every episode in directory (a .bag, .bag.active or .bag.broken),
    oldest first; [] when the folder is missing."""
    try:
        names = os.listdir(directory)
    except FileNotFoundError:
        return []
    found = []
    for file_name in names:
        suffix, ended = next(((s, e) for s, e in ENDINGS if file_name.endswith(s)),
                             (None, None))
        if suffix is None or not file_name.startswith(recording.NAME_PREFIX):
            continue
        name = file_name[:-len(suffix)]
        base = os.path.join(directory, name)
        meta = metadata_or_empty(base + recording.META)
        if ended is None:
            ended = 'repaired' if meta.get('ended_cleanly') is False else 'clean'
        duration = meta.get('duration_s')
        cameras = meta.get('cameras', [] if meta else None)
        found.append(Entry(
            name, _start(meta, name),
            float(duration) if isinstance(duration, (int, float)) and ended != 'recording'
            else None,
            ''.join(s for s in PUPPET_SIDES if s in (meta.get('sides') or ())),
            len(cameras) if isinstance(cameras, list) else None,
            os.path.getsize(os.path.join(directory, file_name)), ended,
            [kind for ext, kind in EXPORTED if os.path.exists(base + ext)],
            ' '.join(str(meta.get('task') or '').split()),
            ' '.join(str(meta.get('notes') or '').split())))
    return sorted(found, key=lambda e: (e.start or datetime.datetime.min, e.name))


def row(entry):
    """Return an entry's cells (text) in HEADER order."""
    return (entry.name,
            entry.start.strftime('%Y-%m-%d %H:%M:%S') if entry.start else '?',
            '?' if entry.duration_s is None else '%.1f s' % entry.duration_s,
            entry.sides or '-', '?' if entry.cameras is None else str(entry.cameras),
            '%.1f MB' % (entry.size_bytes / 1e6), entry.ended,
            ' '.join(entry.exported) or '-', _shortened(entry.task) or '-', entry.notes)


def _shortened(text):
    """Return text, cut to TASK_CHARS characters (the last three '...') when longer."""
    return text if len(text) <= TASK_CHARS else text[:TASK_CHARS - 3] + '...'


def table(found, directory):
    """Return the lines printed: a header, a line per entry (columns aligned), a total."""
    rows = [HEADER] + [row(entry) for entry in found]
    widths = [max(len(r[c]) for r in rows) for c in range(len(HEADER) - 1)]
    lines = ['  '.join(cell.ljust(w) for cell, w in zip(r, widths)) + '  ' + r[-1]
             for r in rows]
    total = sum(entry.size_bytes for entry in found)
    lines.append('%d episode%s, %.1f MB, in %s' % (len(found), '' if len(found) == 1 else 's',
                                                  total / 1e6, directory))
    return [line.rstrip() for line in lines]


def main(argv=None):
    """Print the episodes of the folder named on the command line (exit 0; 2 if no folder), or
    run `set-task` (episode_task.main)."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ['set-task']:
        from robopuppet.episodes import episode_task  # pylint: disable=import-outside-toplevel
        episode_task.main(argv[1:])  # (it imports the exporter: the list stays quick without)
    parser = argparse.ArgumentParser(
        prog='episodes', description='List recorded episodes.',
        epilog="`episodes set-task EPISODE... --task TEXT` sets episodes' task (see its --help)")
    parser.add_argument('directory', nargs='?', metavar='DIR',
                        default=export_files.default_episodes_dir(),
                        help='the episodes folder (default %(default)s)')
    args = parser.parse_args(argv)
    if not os.path.isdir(args.directory):
        print('episodes: no such folder: %s' % args.directory, file=sys.stderr)
        sys.exit(2)
    print('\n'.join(table(entries(args.directory), args.directory)))
    sys.exit(0)
