"""The ini file of one puppet arm on disk: where it lives, atomic writes, backups.

A write goes to a temporary file in the same directory, is flushed to disk and then renamed over
the old file, so a kill at any moment leaves either the old or the new file, never a torn one.
"""
import glob
import os
import shutil
import tempfile

from robopuppet import config_store


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


def _tmp_prefix(path):
    return '.%s.' % os.path.basename(path)


def remove_stale_temporaries(path):
    """Delete temporary files that a writer killed mid-write left beside path; return them."""
    pattern = os.path.join(os.path.dirname(path) or '.', glob.escape(_tmp_prefix(path)) + '*.tmp')
    stale = glob.glob(pattern)
    for tmp_path in stale:
        os.unlink(tmp_path)
    return stale


def write_atomic(path, text):
    """Replace the file at path with text, atomically and durably.

    Raises:
        OSError: the directory or file cannot be written; the old file is then unchanged.
    """
    directory = os.path.dirname(path) or '.'
    os.makedirs(directory, exist_ok=True)
    fd, tmp_path = tempfile.mkstemp(prefix=_tmp_prefix(path), suffix='.tmp', dir=directory)
    try:
        with os.fdopen(fd, 'w') as tmp:
            tmp.write(text)
            tmp.flush()
            os.fsync(tmp.fileno())
        if os.path.exists(path):
            shutil.copymode(path, tmp_path)
        os.replace(tmp_path, path)
    except BaseException:
        try:
            os.unlink(tmp_path)
        except OSError:
            pass
        raise
    dir_fd = os.open(directory, os.O_RDONLY)
    try:
        os.fsync(dir_fd)
    finally:
        os.close(dir_fd)


def backup(path, stamp):
    """Copy the file at path to '<path>.bak-<stamp>' and return the copy's path."""
    copy = '%s.bak-%s' % (path, stamp)
    shutil.copy2(path, copy)
    return copy


def load_or_create(path, seed_file, stamp):
    """Read the arm's ini file, creating or repairing it on disk as needed.

    A missing file is created from seed_file when that exists, else from the defaults. A file with
    problems is backed up (see backup) and rewritten with only the broken entries replaced.

    Args:
        path: the live ini file.
        seed_file: the shipped ini file to start from, or '' for none.
        stamp: text that makes a backup name unique, e.g. '20261122-101500'.
    Returns:
        (config, text, notes, problems): the settings, the file text now on disk, what was done
        (created, backed up), and one line per repaired entry naming file and entry.
    Raises:
        OSError: the file cannot be read or written.
    """
    notes = ['removed %s, left by an interrupted write' % tmp
             for tmp in remove_stale_temporaries(path)]
    if os.path.exists(path):
        source = path
        with open(path, errors='replace') as live:
            text = live.read()
    elif seed_file and os.path.exists(seed_file):
        source = seed_file
        with open(seed_file) as seed:
            text = seed.read()
        notes.append('created %s from %s' % (path, seed_file))
    else:
        source = 'defaults'
        text = config_store.default_text()
        notes.append('created %s with default settings' % path)
    config, problems = config_store.parse(text)
    problems = ['%s: %s' % (source, problem) for problem in problems]
    if problems and source == path:
        notes.append('%s had problems; original kept as %s' % (path, backup(path, stamp)))
    if problems or source != path:
        text = config_store.render(text, config)
        write_atomic(path, text)
    return config, text, notes, problems
