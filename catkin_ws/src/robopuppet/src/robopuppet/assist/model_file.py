"""The assist's model file: one .npz of numpy arrays and a JSON header, written atomically.

Pure (numpy, no pickles). The header (the array `header`, a JSON string) holds `format`
(FORMAT), `format_version` (VERSION), and the learners.Predictor header: method, leader,
follower, task, feature and method settings, the confidence calibration, plus what train adds
(training episodes, held-out figures). The other arrays are the Predictor's. A file is written
to a temporary file beside it, flushed to disk and renamed over the name, so a reader sees the
old model or the new one, never half of one.
"""
import io
import json
import os
import zipfile

import numpy as np

from robopuppet import atomic_file
from robopuppet.assist import learners

FORMAT = 'robopuppet assist model'
VERSION = 1


class ModelError(Exception):
    """A model file cannot be used: missing, unreadable, not a model or of another version."""


def save(path, predictor, extra=None):
    """Write a learners.Predictor (its header updated with extra, a JSON-able dict) to path.

    Raises:
        OSError: the file cannot be written (nothing is left behind).
    """
    header = dict(predictor.header, **(extra or {}))
    header.update(format=FORMAT, format_version=VERSION)
    buffer = io.BytesIO()
    np.savez(buffer, header=np.array(json.dumps(header)), **predictor.arrays)
    atomic_file.write_atomic(path, buffer.getvalue())


def read_header(path):
    """Return a model file's header dict (checked as load() checks it).

    Raises:
        ModelError: see load().
    """
    return _read(path)[0]


def load(path):
    """Return the learners.Predictor a model file holds.

    Raises:
        ModelError: the file is missing, unreadable, truncated, not an assist model, of another
            format version, or its arrays do not make a model.
    """
    header, arrays = _read(path)
    try:
        return learners.Predictor(header, arrays)
    except (KeyError, ValueError, TypeError, IndexError, np.linalg.LinAlgError) as error:
        raise ModelError('%s: the model is damaged (%s: %s)'
                         % (path, type(error).__name__, error)) from error


def _read(path):
    if not os.path.exists(path):
        raise ModelError('%s: no such model file (train one: rosrun robopuppet train_assist)'
                         % path)
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in data.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as error:
        raise ModelError('%s: not an assist model file, or truncated (%s)' % (path, error)) \
            from error
    try:
        header = json.loads(str(arrays.pop('header')))
    except (KeyError, ValueError) as error:
        raise ModelError('%s: not an assist model file (no header)' % path) from error
    if not isinstance(header, dict) or header.get('format') != FORMAT:
        raise ModelError('%s: not an assist model file' % path)
    if header.get('format_version') != VERSION:
        raise ModelError('%s: model format version %r; this software reads version %d: train '
                         'the model again' % (path, header.get('format_version'), VERSION))
    return header, arrays
