"""An ACT dataset folder (export --act-dir DIR): episode_0.hdf5, episode_1.hdf5 ..., the names
ACT's loader opens (episode_{i}.hdf5 for i in 0 .. num_episodes - 1), and INDEX_FILE, which maps
each index to the episode it holds.

A new episode takes the index after the highest already there; an episode exported into the
folder before keeps its index (its file is written again). One export at a time per folder:
export holds the folder's LOCK_FILE (flock) from choosing an index to recording it. Pure (files
only; no ROS).
"""
import contextlib
import fcntl
import os
import re

import yaml

from robopuppet import atomic_file

INDEX_FILE = 'episode_index.yaml'
LOCK_FILE = '.export.lock'
_FILE_RE = re.compile(r'^episode_(\d+)\.hdf5$')


def file_name(index):
    """Return the file name of an index: episode_<index>.hdf5."""
    return 'episode_%d.hdf5' % index


def indices(directory):
    """Return the indices of the episode_<i>.hdf5 files in directory, ascending."""
    found = [_FILE_RE.match(name) for name in os.listdir(directory)]
    return sorted(int(match.group(1)) for match in found if match)


def read_index(directory):
    """Return INDEX_FILE's mapping {index: episode name} ({} when missing or unreadable)."""
    try:
        with open(os.path.join(directory, INDEX_FILE)) as stream:
            data = yaml.safe_load(stream)
    except (OSError, yaml.YAMLError):
        return {}
    return {int(k): str(v) for k, v in data.items()
            if str(k).isdigit()} if isinstance(data, dict) else {}


def choose_index(directory, name):
    """Return (index, reused) for episode name: its index when the folder holds it already
    (INDEX_FILE names it and its file exists), else the one after the highest file there."""
    present = indices(directory)
    for index, held in sorted(read_index(directory).items()):
        if held == name and index in present:
            return index, True
    return (present[-1] + 1 if present else 0), False


def record(directory, index, name):
    """Write INDEX_FILE with index -> name, keeping the other entries whose files exist;
    whole or not at all (atomic_file)."""
    present = set(indices(directory)) | {index}
    mapping = {i: held for i, held in read_index(directory).items() if i in present}
    mapping[index] = name
    atomic_file.write_atomic(os.path.join(directory, INDEX_FILE), (
        '# ACT dataset index: episode_<index>.hdf5 holds the episode named\n'
        + yaml.safe_dump(dict(sorted(mapping.items())), default_flow_style=False)))


def gaps(directory):
    """Return the indices below the highest that have no file (ACT opens 0 .. N-1)."""
    present = indices(directory)
    return sorted(set(range(present[-1] + 1)) - set(present)) if present else []


def step_counts(directory):
    """Return {index: grid steps (rows of /action)} of the folder's episode files."""
    import h5py  # pylint: disable=import-outside-toplevel  (only this reads HDF5 files)
    counts = {}
    for index in indices(directory):
        try:
            with h5py.File(os.path.join(directory, file_name(index)), 'r') as root:
                counts[index] = root['/action'].shape[0]
        except (OSError, KeyError):
            continue
    return counts


@contextlib.contextmanager
def locked(directory, say):
    """Hold the folder's LOCK_FILE (flock) while the block runs; say(text) when another
    export holds it and this one waits."""
    with open(os.path.join(directory, LOCK_FILE), 'a') as stream:
        try:
            fcntl.flock(stream, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            say('waiting for another export into %s to finish' % directory)
            fcntl.flock(stream, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(stream, fcntl.LOCK_UN)
