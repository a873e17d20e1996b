"""The simulated cameras' world file (config/world.yaml: floor, bed, patient, the room camera's
pose) and the meshes of its shapes.

Its shapes are in the shape-file format of robopuppet.world.shapes (the one keep-out zones and
obstacles use too); the world file adds a checkerboard `floor` and fixed room `cameras`.
docs/cameras.md describes it. Pure: YAML text in, checked tuples and meshes out.
"""
import collections
import os

import numpy as np

from robopuppet.cameras import meshes
from robopuppet.world import shapes
from robopuppet.world.shapes import ShapeFileError

Floor = collections.namedtuple('Floor', 'z size tile colours')
Floor.__doc__ = """A checkerboard floor: height z (m, base frame), square side size (m), tile
side (m) and the two tile colours."""
RoomCamera = collections.namedtuple('RoomCamera', 'xyz look_at hfov_deg')
RoomCamera.__doc__ = """A fixed camera: position and the point it looks at (m, base frame,
image up towards +z) and its horizontal field of view (degrees)."""
World = collections.namedtuple('World', 'shapes floor cameras')
World.__doc__ = """A world file: its Shapes, its Floor (or None) and {name: RoomCamera}."""

DEFAULT_COLOUR = (0.7, 0.7, 0.7)
DEFAULT_FLOOR_COLOURS = ((0.56, 0.55, 0.50), (0.46, 0.45, 0.41))


def _floor(value):
    if value is None:
        return None
    if not isinstance(value, dict) or set(value) - {'z', 'size', 'tile', 'colours'}:
        raise ShapeFileError('floor must be a mapping of z, size, tile, colours; got %r'
                             % (value,))
    colours = value.get('colours')
    if colours is not None:
        if not isinstance(colours, list) or len(colours) != 2:
            raise ShapeFileError('floor: colours must be two RGB colours, got %r' % (colours,))
        colours = tuple(shapes.colour('floor: colours', c) for c in colours)
    return Floor(shapes.number('floor: z', value.get('z')),
                 shapes.number('floor: size', value.get('size', 8.0), positive=True),
                 shapes.number('floor: tile', value.get('tile', 0.5), positive=True),
                 colours or DEFAULT_FLOOR_COLOURS)


def _cameras(value):
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise ShapeFileError('cameras must be a mapping of camera name to pose, got %r'
                             % (value,))
    cameras = {}
    for name, entry in value.items():
        if not isinstance(entry, dict) or set(entry) - {'xyz', 'look_at', 'hfov_deg'}:
            raise ShapeFileError('camera %r must have xyz, look_at and hfov_deg, got %r'
                                 % (name, entry))
        where = 'camera %r: ' % name
        hfov_deg = shapes.number(where + 'hfov_deg', entry.get('hfov_deg', 60.0), positive=True)
        if hfov_deg >= 180.0:
            raise ShapeFileError(where + 'hfov_deg must be below 180, got %r' % hfov_deg)
        camera = RoomCamera(shapes.vector(where + 'xyz', entry.get('xyz')),
                            shapes.vector(where + 'look_at', entry.get('look_at')), hfov_deg)
        look_at_pose(camera.xyz, camera.look_at)  # refuse a camera looking straight down now
        cameras[name] = camera
    return cameras


def parse_world(text, where='the world file'):
    """Return the World of a world file's YAML text.

    Raises:
        ShapeFileError: not YAML, or an entry not in the format (the message names it).
    """
    document = shapes.load_document(text, ('frame', 'shapes', 'floor', 'cameras'), where)
    return World(shapes.parse_shapes(document, where), _floor(document.get('floor')),
                 _cameras(document.get('cameras')))


def load_world(path):
    """Return the World of a file; raise ShapeFileError (unreadable or malformed, naming it)."""
    return parse_world(shapes.read_text(path), path)


def optional_shapes(path):
    """Return (Shapes, problem) of an optional obstacle or zone file: ([], '') when there is
    none or it does not exist, ([], why) when it cannot be used."""
    if path is None or not os.path.exists(path):
        return [], ''
    try:
        return load_world(path).shapes, ''
    except ShapeFileError as error:
        return [], str(error)


def look_at_pose(xyz, target, up=(0.0, 0.0, 1.0)):
    """Return the 4x4 pose of an optical frame (z forward, x right, y down in the image) at xyz
    looking at target, the image's up towards `up`.

    Raises:
        ShapeFileError: target is at xyz or straight along `up` from it.
    """
    eye, target, up = (np.asarray(v, np.float64) for v in (xyz, target, up))
    forward = target - eye
    right = np.cross(forward, up)
    if np.linalg.norm(forward) < 1e-9 or np.linalg.norm(right) < 1e-9 * np.linalg.norm(forward):
        raise ShapeFileError('a camera at %s cannot look at %s with the image upright'
                             % (tuple(eye), tuple(target)))
    forward /= np.linalg.norm(forward)
    right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = right, np.cross(forward, right), \
        forward, eye
    return pose


def shape_mesh(shape, default=DEFAULT_COLOUR):
    """Return a Shape's mesh in the base frame, in its colour or else in `default`."""
    colour = default if shape.colour is None else shape.colour
    if shape.type == 'box':
        mesh = meshes.box(shape.size, colour)
    elif shape.type == 'cylinder':
        mesh = meshes.cylinder(shape.radius, shape.length, colour)
    else:
        mesh = meshes.sphere(shape.radius, colour)
    return meshes.transformed(mesh, shapes.shape_pose(shape))


def world_mesh(world):
    """Return the still world (floor and shapes) as one mesh in the base frame."""
    parts = [shape_mesh(s) for s in world.shapes]
    if world.floor is not None:
        f = world.floor
        parts.append(meshes.checkerboard(f.size, f.tile, f.z, f.colours))
    return meshes.merged(parts)
