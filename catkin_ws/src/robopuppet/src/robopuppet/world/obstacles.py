"""Obstacle files: the shapes that physically block the Baxter stand-in's arms (and that the
simulated cameras draw), in the shape-file format of world.shapes (`frame: base`, `shapes`).

The one place for the default file: the package's config/obstacles.yaml, used when it exists and
no other file is chosen. Pure: paths and YAML in, checked shapes out; no ROS.
"""
import os

from robopuppet.world import shapes, zones

DEFAULT_FILE = ('config', 'obstacles.yaml')   # inside the robopuppet package


class ObstacleFileError(zones.ZoneFileError):
    """An obstacle file cannot be read or is not a shape file; the message names file and entry."""


def default_path(package_dir):
    """Return the path of the default obstacle file of the package at package_dir."""
    return os.path.join(package_dir, *DEFAULT_FILE)


def chosen_path(value, package_dir):
    """Return the obstacle file an ~obstacles_file parameter selects, or None for none.

    Args:
        value: None (parameter unset): the default file when it exists, else none; '' none;
            anything else a path (which must then be readable).
        package_dir: the robopuppet package's directory.
    """
    if value is None:
        path = default_path(package_dir)
        return path if os.path.exists(path) else None
    return value or None


def load_obstacles(path):
    """Return the Shapes of an obstacle file (an empty file: none).

    Raises:
        ObstacleFileError: unreadable, not YAML, or an entry not in the format (named).
    """
    text = shapes.read_text(path, ObstacleFileError, 'obstacle file')
    try:
        return zones.parse_zones(text, path)
    except zones.ZoneFileError as error:
        raise ObstacleFileError(str(error)) from None
