"""Shape files: named boxes, cylinders and spheres in Baxter's base frame (config/*.yaml).

The one format for the simulated cameras' world (config/world.yaml: floor, bed, patient, the
room camera's pose) and, for issue 12, for obstacles and keep-out zones: a `shapes` list, each
shape with a name, a type and URDF's geometry fields (box `size` [x, y, z] m centred; cylinder
`radius`, `length` m along its own z; sphere `radius` m), its centre `xyz` (m) and `rpy` (rad,
URDF's fixed-axis roll, pitch, yaw) in the base frame, and an optional RGB `colour` (0..1).
docs/cameras.md describes it. Pure: YAML text in, checked tuples and meshes out.
"""
import collections
import math

import numpy as np
import yaml

from robopuppet import baxter_description as bd
from robopuppet.cameras import meshes

Shape = collections.namedtuple('Shape', 'name type size radius length xyz rpy colour')
Shape.__doc__ = """One checked shape: type 'box' (size), 'cylinder' (radius, length) or
'sphere' (radius); unused fields are None. Metres, radians, RGB 0..1 (None: not given)."""
Floor = collections.namedtuple('Floor', 'z size tile colours')
Floor.__doc__ = """A checkerboard floor: height z (m, base frame), square side size (m), tile
side (m) and the two tile colours."""
RoomCamera = collections.namedtuple('RoomCamera', 'xyz look_at hfov_deg')
RoomCamera.__doc__ = """A fixed camera: position and the point it looks at (m, base frame,
image up towards +z) and its horizontal field of view (degrees)."""
World = collections.namedtuple('World', 'shapes floor cameras')
World.__doc__ = """A world file: its Shapes, its Floor (or None) and {name: RoomCamera}."""

TYPES = {'box': ('size',), 'cylinder': ('radius', 'length'), 'sphere': ('radius',)}
DEFAULT_COLOUR = (0.7, 0.7, 0.7)
DEFAULT_FLOOR_COLOURS = ((0.56, 0.55, 0.50), (0.46, 0.45, 0.41))


class SceneError(ValueError):
    """A shape file is not in the format above; the message names the file's entry."""


def _number(where, value, positive=False):
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            not math.isfinite(value) or (positive and value <= 0.0):
        raise SceneError('%s must be a %snumber, got %r'
                         % (where, 'positive ' if positive else '', value))
    return float(value)


def _vector(where, value, count=3, positive=False, low=None, high=None):
    if not isinstance(value, (list, tuple)) or len(value) != count:
        raise SceneError('%s must be a list of %d numbers, got %r' % (where, count, value))
    numbers = tuple(_number(where, v, positive) for v in value)
    if low is not None and not all(low <= v <= high for v in numbers):
        raise SceneError('%s must be %d numbers in %g..%g, got %r'
                         % (where, count, low, high, value))
    return numbers


def _colour(where, value):
    return None if value is None else _vector(where, value, low=0.0, high=1.0)


def parse_shape(entry, index=0):
    """Return the Shape of one YAML entry (a dict); raise SceneError naming what is wrong."""
    if not isinstance(entry, dict):
        raise SceneError('shape %d must be a mapping, got %r' % (index, entry))
    name = entry.get('name')
    if not isinstance(name, str) or not name:
        raise SceneError('shape %d needs a name' % index)
    kind = entry.get('type')
    if kind not in TYPES:
        raise SceneError('shape %r: type must be one of %s, got %r'
                         % (name, ', '.join(sorted(TYPES)), kind))
    known = {'name', 'type', 'xyz', 'rpy', 'colour'} | set(TYPES[kind])
    unknown = sorted(set(entry) - known)
    if unknown:
        raise SceneError('shape %r (%s): unknown keys %s' % (name, kind, unknown))
    fields = {'size': None, 'radius': None, 'length': None}
    for key in TYPES[kind]:
        if key not in entry:
            raise SceneError('shape %r (%s) needs %s' % (name, kind, key))
        where = 'shape %r: %s' % (name, key)
        fields[key] = (_vector(where, entry[key], positive=True) if key == 'size'
                       else _number(where, entry[key], positive=True))
    xyz = _vector('shape %r: xyz' % name, entry.get('xyz'))
    rpy = _vector('shape %r: rpy' % name, entry.get('rpy', [0.0, 0.0, 0.0]))
    colour = _colour('shape %r: colour' % name, entry.get('colour'))
    return Shape(name, kind, fields['size'], fields['radius'], fields['length'], xyz, rpy,
                 colour)


def parse_shapes(document, where='the file'):
    """Return the Shapes of a loaded YAML document's `shapes` list (names must be unique)."""
    if document is None:
        return []
    if not isinstance(document, dict):
        raise SceneError('%s must be a mapping with a shapes list' % where)
    entries = document.get('shapes', [])
    if not isinstance(entries, list):
        raise SceneError('%s: shapes must be a list' % where)
    shapes = [parse_shape(entry, i) for i, entry in enumerate(entries)]
    names = [s.name for s in shapes]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise SceneError('%s: shape names must be unique, %s appear more than once'
                         % (where, twice))
    return shapes


def _floor(value):
    if value is None:
        return None
    if not isinstance(value, dict) or set(value) - {'z', 'size', 'tile', 'colours'}:
        raise SceneError('floor must be a mapping of z, size, tile, colours; got %r' % (value,))
    colours = value.get('colours')
    if colours is not None:
        if not isinstance(colours, list) or len(colours) != 2:
            raise SceneError('floor: colours must be two RGB colours, got %r' % (colours,))
        colours = tuple(_colour('floor: colours', c) for c in colours)
    return Floor(_number('floor: z', value.get('z')),
                 _number('floor: size', value.get('size', 8.0), positive=True),
                 _number('floor: tile', value.get('tile', 0.5), positive=True),
                 colours or DEFAULT_FLOOR_COLOURS)


def _cameras(value):
    if value is None:
        return {}
    if not isinstance(value, dict):
        raise SceneError('cameras must be a mapping of camera name to pose, got %r' % (value,))
    cameras = {}
    for name, entry in value.items():
        if not isinstance(entry, dict) or set(entry) - {'xyz', 'look_at', 'hfov_deg'}:
            raise SceneError('camera %r must have xyz, look_at and hfov_deg, got %r'
                             % (name, entry))
        where = 'camera %r: ' % name
        hfov_deg = _number(where + 'hfov_deg', entry.get('hfov_deg', 60.0), positive=True)
        if hfov_deg >= 180.0:
            raise SceneError(where + 'hfov_deg must be below 180, got %r' % hfov_deg)
        camera = RoomCamera(_vector(where + 'xyz', entry.get('xyz')),
                            _vector(where + 'look_at', entry.get('look_at')), hfov_deg)
        look_at_pose(camera.xyz, camera.look_at)  # refuse a camera looking straight down now
        cameras[name] = camera
    return cameras


def parse_world(text, where='the world file'):
    """Return the World of a world file's YAML text.

    Raises:
        SceneError: not YAML, or an entry not in the format (the message names it).
    """
    try:
        document = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise SceneError('%s is not YAML: %s' % (where, error)) from None
    if document is not None and not isinstance(document, dict):
        raise SceneError('%s must be a mapping (shapes, floor, cameras)' % where)
    document = document or {}
    unknown = sorted(set(document) - {'frame', 'shapes', 'floor', 'cameras'})
    if unknown:
        raise SceneError('%s: unknown keys %s' % (where, unknown))
    if document.get('frame', bd.BASE_FRAME) != bd.BASE_FRAME:
        raise SceneError("%s: shapes must be in Baxter's %r frame, got frame %r"
                         % (where, bd.BASE_FRAME, document['frame']))
    return World(parse_shapes(document, where), _floor(document.get('floor')),
                 _cameras(document.get('cameras')))


def load_world(path):
    """Return the World of a file; raise SceneError (unreadable or malformed, naming it)."""
    try:
        with open(path) as stream:
            text = stream.read()
    except OSError as error:
        raise SceneError('cannot read %s: %s' % (path, error)) from None
    return parse_world(text, path)


def look_at_pose(xyz, target, up=(0.0, 0.0, 1.0)):
    """Return the 4x4 pose of an optical frame (z forward, x right, y down in the image) at xyz
    looking at target, the image's up towards `up`.

    Raises:
        SceneError: target is at xyz or straight along `up` from it.
    """
    eye, target, up = (np.asarray(v, np.float64) for v in (xyz, target, up))
    forward = target - eye
    right = np.cross(forward, up)
    if np.linalg.norm(forward) < 1e-9 or np.linalg.norm(right) < 1e-9 * np.linalg.norm(forward):
        raise SceneError('a camera at %s cannot look at %s with the image upright'
                         % (tuple(eye), tuple(target)))
    forward /= np.linalg.norm(forward)
    right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = right, np.cross(forward, right), \
        forward, eye
    return pose


def shape_pose(shape):
    """Return the 4x4 pose of a Shape's centre in the base frame."""
    pose = np.eye(4)
    pose[:3, :3] = bd.rpy_matrix(*shape.rpy)
    pose[:3, 3] = shape.xyz
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
    return meshes.transformed(mesh, shape_pose(shape))


def world_mesh(world):
    """Return the still world (floor and shapes) as one mesh in the base frame."""
    parts = [shape_mesh(s) for s in world.shapes]
    if world.floor is not None:
        f = world.floor
        parts.append(meshes.checkerboard(f.size, f.tile, f.z, f.colours))
    return meshes.merged(parts)
