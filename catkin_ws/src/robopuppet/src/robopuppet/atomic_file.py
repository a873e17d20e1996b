"""Files replaced whole or not at all: the ini files, episodes' metadata, models, dataset files.

A write goes to a temporary file beside the target (.<name>.XXXX.tmp), is flushed to disk, takes
the old file's permissions and is renamed over it, and the folder is flushed too: a kill or a
power cut at any moment leaves the old file or the new one, never a torn one. A writer killed
mid-write leaves its temporary file; remove_stale_temporaries clears them.
"""
import glob
import os
import shutil
import tempfile


def _prefix(path):
    return '.%s.' % os.path.basename(path)


def remove_stale_temporaries(path):
    """Delete the temporary files a killed writer of path left beside it; return them."""
    pattern = os.path.join(os.path.dirname(path) or '.', glob.escape(_prefix(path)) + '*.tmp')
    stale = glob.glob(pattern)
    for tmp_path in stale:
        os.unlink(tmp_path)
    return stale


def write_atomic(path, data):
    """Replace the file at path with data (str or bytes), atomically and durably; make its
    folder when missing.

    Raises:
        OSError: the folder or file cannot be written; the old file is then unchanged and no
            temporary file is left.
    """
    directory = os.path.dirname(path) or '.'
    os.makedirs(directory, exist_ok=True)
    fd, tmp_path = tempfile.mkstemp(prefix=_prefix(path), suffix='.tmp', dir=directory)
    try:
        with os.fdopen(fd, 'wb' if isinstance(data, bytes) else 'w') as tmp:
            tmp.write(data)
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
