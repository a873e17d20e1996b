"""The ini file of one puppet arm on disk: where it lives, its repair, backups.

Every write replaces the file whole (atomic_file): a kill at any moment leaves either the old or
the new file, never a torn one.
"""
import collections
import itertools
import os
import shutil

from robopuppet.atomic_file import remove_stale_temporaries, write_atomic
from robopuppet.config import config_store


def resolve_path(file_name, ros_home):
    """Return the absolute path of the live ini file.

    Args:
        file_name: absolute path, or a path relative to <ros_home>/robopuppet/.
        ros_home: the ROS home directory (usually ~/.ros).
    """
    path = os.path.expanduser(file_name)
    if not os.path.isabs(path):
        path = os.path.join(ros_home, 'robopuppet', path)
    return path


def backup(path, stamp):
    """Copy the file at path to '<path>.bak-<stamp>' (or -2, -3 ... if taken); return the copy.

    The copy is flushed to disk before this returns, so the original may be replaced next.

    Raises:
        OSError: the copy cannot be made; no copy, not even a partial one, is left behind.
    """
    copy = base = '%s.bak-%s' % (path, stamp)
    for number in itertools.count(2):
        try:
            fd = os.open(copy, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
            break
        except FileExistsError:
            copy = '%s-%d' % (base, number)
    try:
        with os.fdopen(fd, 'wb') as out, open(path, 'rb') as original:
            shutil.copyfileobj(original, out)
            out.flush()
            os.fsync(out.fileno())
        shutil.copystat(path, copy)
    except BaseException:
        _remove_quietly(copy)
        raise
    return copy


def _remove_quietly(path):
    try:
        os.unlink(path)
    except OSError:
        pass


Loaded = collections.namedtuple('Loaded', 'config text notes problems unwritable')
Loaded.__doc__ = """What load_or_create found and did.

    config: the settings to run from, {joint: {name: float}}.
    text: the file text now on disk (what later edits start from).
    notes: what was done (created, backed up, temporaries removed).
    problems: one line per repaired entry, naming file and entry.
    unwritable: '' when the file on disk holds `text`; else why the file cannot be written
        (or read), and then nothing may be changed: a change would not persist.
"""


def load_or_create(path, seed_file, stamp):
    """Read the arm's ini file, creating or repairing it on disk as needed.

    A missing file is created from seed_file when that exists, else from the defaults. A file with
    problems is backed up (see backup) and rewritten once, clean: the broken entries replaced by
    defaults and every line that the reader ignores dropped, so that the next start finds nothing
    to repair. When the file cannot be read, or cannot be written although it must be, the
    settings come from what could be read (or the defaults), the file stays as it was, no backup
    or temporary is left behind, and `unwritable` says why.

    Args:
        path: the live ini file.
        seed_file: the shipped ini file to start from, or '' for none.
        stamp: text that makes a backup name unique, e.g. '20261122-101500'.
    Returns:
        Loaded(config, text, notes, problems, unwritable); never raises OSError.
    """
    notes = []
    try:
        for tmp in remove_stale_temporaries(path):
            notes.append('removed %s, left by an interrupted write' % tmp)
    except OSError as error:
        notes.append('could not remove temporaries beside %s: %s' % (path, error))
    try:
        exists = os.path.lexists(path)
        if exists:
            with open(path, errors='replace') as live:
                text = live.read()
    except OSError as error:
        return Loaded(config_store.defaults(), '', notes,
                      ['%s cannot be read (%s): using defaults' % (path, error)],
                      'cannot read %s: %s' % (path, error))
    if exists:
        source = path
    else:
        source, text = _seed_text(seed_file, notes)
    config, problems = config_store.parse(text)
    problems = ['%s: %s' % (source, problem) for problem in problems]
    if not problems and source == path:
        return Loaded(config, text, notes, problems, '')
    copy = None
    try:
        if problems and source == path:
            copy = backup(path, stamp)
        new_text = config_store.render(text, config)
        write_atomic(path, new_text)
    except OSError as error:
        if copy:
            _remove_quietly(copy)  # the original stays in place: the copy would only pile up
        what = 'repair' if source == path else 'create'
        return Loaded(config, text, notes, problems,
                      'cannot %s %s: %s' % (what, path, error))
    if copy:
        notes.append('%s had problems; original kept as %s' % (path, copy))
    if source != path:
        notes.append('created %s %s' % (path, 'with default settings' if source == 'defaults'
                                        else 'from %s' % source))
    return Loaded(config, new_text, notes, problems, '')


def _seed_text(seed_file, notes):
    """Return (source, text) to create the live file from: the seed file, else the defaults."""
    if seed_file and os.path.exists(seed_file):
        try:
            with open(seed_file, errors='replace') as seed:
                return seed_file, seed.read()
        except OSError as error:
            notes.append('cannot read seed file %s (%s): using defaults' % (seed_file, error))
    return 'defaults', config_store.default_text()
