"""An episode's files by name and its metadata file (<name>.yaml): find, read, write.

Pure: no ROS; the format is fixed in docs/demonstrations.md ("The episode format").
"""
import os

import yaml

from robopuppet import atomic_file
from robopuppet.episodes.recording import ACTIVE, BAG, META


class EpisodeError(Exception):
    """An episode's files cannot be read (missing, still being recorded, or not a bag)."""


def episode_paths(episode):
    """Return (bag path, yaml path) of an episode given as its name, .bag or .yaml path.

    Raises:
        EpisodeError: only a .bag.active exists (a recording that is running or crashed), or
            the bag is missing.
    """
    base = episode
    for suffix in (ACTIVE, BAG, META):
        if base.endswith(suffix):
            base = base[:-len(suffix)]
            break
    bag_path, yaml_path = base + BAG, base + META
    if not os.path.exists(bag_path):
        if os.path.exists(base + ACTIVE):
            raise EpisodeError(
                '%s is still being recorded or its recording crashed: stop the recording, '
                'or start the recorder (it repairs leftover .active bags) or run '
                '`rosbag reindex` on it and rename it to .bag' % (base + ACTIVE))
        raise EpisodeError('%s: no such bag' % bag_path)
    return bag_path, yaml_path


def read_metadata(yaml_path):
    """Return the episode's metadata dict ({} when the .yaml is missing).

    Raises:
        EpisodeError: the file holds no metadata dict.
        OSError, yaml.YAMLError: the file cannot be read.
    """
    if not os.path.exists(yaml_path):
        return {}
    with open(yaml_path) as stream:
        metadata = yaml.safe_load(stream)
    if not isinstance(metadata, dict):
        raise EpisodeError('%s: not an episode metadata file' % yaml_path)
    return metadata


def metadata_or_empty(yaml_path):
    """Return the episode's metadata dict, or {} when it is missing or unreadable."""
    try:
        return read_metadata(yaml_path)
    except (OSError, yaml.YAMLError, EpisodeError):
        return {}


def write_metadata(path, data):
    """Write a metadata dict as YAML, whole or not at all (atomic_file); OSError on failure."""
    atomic_file.write_atomic(path, yaml.safe_dump(data, default_flow_style=False,
                                                  sort_keys=False))
