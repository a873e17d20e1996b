"""What the GUI's replay control needs, without Qt or ROS: the episodes in a directory (newest
first), the replay and export command lines, and the replay's state from its output.

The GUI (robopuppet.gui.replay_box) runs the real commands, `rosrun robopuppet replay` and
`rosrun robopuppet export`, as child processes and shows what they print.
"""
import collections
import glob
import os

from robopuppet.episodes import recording
from robopuppet.episodes.metadata import metadata_or_empty
from robopuppet.interface import PUPPET_SIDES

REPLAY_COMMAND = ('rosrun', 'robopuppet', 'replay')
EXPORT_COMMAND = ('rosrun', 'robopuppet', 'export')
ONTO_ROBOT, INTO_PUPPET = 'robot', 'puppet'   # replay --into
EXIT_WORDS = {0: 'finished', 1: 'stopped by a stop rule', 2: 'refused or failed'}
PREFIX = 'replay: '
ENDINGS = ('finished', 'stopped', 'refused', 'failed')  # the replay's last words start so
# What the replay command says -> the state shown (None: its own words).
STATES = (('reading ', 'reading the episode'),
          ('moving slowly to the start pose', 'approaching the start pose'),
          ('playing ', None), ('finished', None), ('stopped', None), ('refused', None),
          ('failed', None))

Episode = collections.namedtuple('Episode', 'name bag sides duration_s notes')
Episode.__doc__ = """A recorded episode: name, bag path, sides (puppet sides recorded, e.g.
('R',)), duration_s (None when unknown) and notes, from its metadata file."""


def list_episodes(directory):
    """Return the episodes (finished bags) in directory, newest first ([] when it is missing).

    Episode names hold their start time (episode_YYYYmmdd-HHMMSS, then _2, _3), so newest first
    is the names in reverse order. A bag still being written (.bag.active) is not listed.
    """
    episodes = []
    for bag in glob.glob(os.path.join(glob.escape(directory), '*' + recording.BAG)):
        name = os.path.basename(bag)[:-len(recording.BAG)]
        meta = metadata_or_empty(bag[:-len(recording.BAG)] + recording.META)
        sides = tuple(s for s in PUPPET_SIDES if s in (meta.get('sides') or ()))
        duration = meta.get('duration_s')
        episodes.append(Episode(name, bag, sides, float(duration) if isinstance(
            duration, (int, float)) else None, str(meta.get('notes') or '')))
    return sorted(episodes, key=lambda e: _name_key(e.name), reverse=True)


def _name_key(name):
    """Return a sort key: the start time, then the _N suffix as a number."""
    base, _, suffix = name.rpartition('_')
    return (base, int(suffix)) if suffix.isdigit() and base.startswith(
        recording.NAME_PREFIX) else (name, 1)


def label(episode):
    """Return the line the episode list shows, e.g. 'episode_20240101-120000  12.4 s, R: demo'."""
    parts = [] if episode.duration_s is None else ['%.1f s' % episode.duration_s]
    parts += [''.join(episode.sides)] if episode.sides else []
    text = '%s  %s' % (episode.name, ', '.join(parts))
    return (text + ': ' + episode.notes if episode.notes else text).rstrip()


def replay_arguments(episode, into, side, speed):
    """Return the replay command's arguments.

    Into the puppet: this window's puppet arm (side) plays its recorded angles. Onto the robot:
    button 1 of the episode's sides and of this window's side stops it.
    """
    if into == INTO_PUPPET:
        sides = side
    else:
        sides = ''.join(s for s in PUPPET_SIDES if s in episode.sides or s == side)
    return [episode.bag, '--into', into, '--side', sides, '--speed', '%g' % speed]


def export_arguments(episode):
    """Return the export command's arguments that write the episode's plot beside it."""
    return [episode.bag, '--plot']


def plot_path(episode):
    """Return where export --plot writes the episode's plot (a PNG beside the bag)."""
    return episode.bag[:-len(recording.BAG)] + '.png'


def state_from_line(line):
    """Return the state a line of the replay command's output shows, or None (no change)."""
    if not line.startswith(PREFIX):
        return None
    text = line[len(PREFIX):].strip()
    for start, state in STATES:
        if text.startswith(start):
            return state or text
    return None


def has_ended(state):
    """Return True when a state is the replay's own word on how it ended."""
    return bool(state) and state.split(':')[0] in ENDINGS


def exit_text(code, state):
    """Return what the GUI shows when the replay ended with exit code `code` (None: killed by
    a signal), its last state being `state`."""
    if code is None:
        return ('%s (then ended by a signal)' % state if has_ended(state)
                else 'ended by a signal (%s)' % (state or 'no output'))
    words = EXIT_WORDS.get(code, 'exit code %d' % code)
    return '%s (exit %d: %s)' % (state, code, words) if has_ended(state) else 'exit %d: %s' % (
        code, words)
