"""Shape files: named boxes, cylinders and spheres in Baxter's base frame (config/*.yaml).

The one format for the simulated cameras' world (config/world.yaml: floor, bed, patient, the
room camera's pose, read by cameras.scene), the keep-out zones (config/zones.yaml, world.zones)
and the stand-in's obstacles: a `shapes` list, each shape with a name, a type and URDF's geometry
fields (box `size` [x, y, z] m centred; cylinder `radius`, `length` m along its own z; sphere
`radius` m), its centre `xyz` (m) and `rpy` (rad, URDF's fixed-axis roll, pitch, yaw) in the base
frame, and an optional RGB `colour` (0..1). docs/cameras.md describes it. The primitive shapes of
a URDF's links are read into the same Shapes (link_shapes): the cameras draw them, the arm's
capsules hold them. Pure: YAML and URDF text in, checked tuples out.
"""
import collections
import math

import numpy as np
import yaml

from robopuppet import baxter_description as bd

Shape = collections.namedtuple('Shape', 'name type size radius length xyz rpy colour')
Shape.__doc__ = """One checked shape: type 'box' (size), 'cylinder' (radius, length) or
'sphere' (radius); unused fields are None. Metres, radians, RGB 0..1 (None: not given)."""

TYPES = {'box': ('size',), 'cylinder': ('radius', 'length'), 'sphere': ('radius',)}


class ShapeFileError(ValueError):
    """A shape file is not in the format above; the message names the file's entry."""


def number(where, value, positive=False):
    """Return value as a float; raise ShapeFileError naming `where` unless a finite number
    (above 0 when positive)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            not math.isfinite(value) or (positive and value <= 0.0):
        raise ShapeFileError('%s must be a %snumber, got %r'
                             % (where, 'positive ' if positive else '', value))
    return float(value)


def vector(where, value, count=3, positive=False, low=None, high=None):
    """Return a list of `count` numbers (in low..high when given) as a tuple of floats."""
    if not isinstance(value, (list, tuple)) or len(value) != count:
        raise ShapeFileError('%s must be a list of %d numbers, got %r' % (where, count, value))
    numbers = tuple(number(where, v, positive) for v in value)
    if low is not None and not all(low <= v <= high for v in numbers):
        raise ShapeFileError('%s must be %d numbers in %g..%g, got %r'
                             % (where, count, low, high, value))
    return numbers


def colour(where, value):
    """Return an RGB colour (0..1) as a tuple, or None when not given."""
    return None if value is None else vector(where, value, low=0.0, high=1.0)


def parse_shape(entry, index=0):
    """Return the Shape of one YAML entry (a dict); raise ShapeFileError naming what is wrong."""
    if not isinstance(entry, dict):
        raise ShapeFileError('shape %d must be a mapping, got %r' % (index, entry))
    name = entry.get('name')
    if not isinstance(name, str) or not name:
        raise ShapeFileError('shape %d needs a name' % index)
    kind = entry.get('type')
    if kind not in TYPES:
        raise ShapeFileError('shape %r: type must be one of %s, got %r'
                             % (name, ', '.join(sorted(TYPES)), kind))
    known = {'name', 'type', 'xyz', 'rpy', 'colour'} | set(TYPES[kind])
    unknown = sorted(set(entry) - known)
    if unknown:
        raise ShapeFileError('shape %r (%s): unknown keys %s' % (name, kind, unknown))
    fields = {'size': None, 'radius': None, 'length': None}
    for key in TYPES[kind]:
        if key not in entry:
            raise ShapeFileError('shape %r (%s) needs %s' % (name, kind, key))
        where = 'shape %r: %s' % (name, key)
        fields[key] = (vector(where, entry[key], positive=True) if key == 'size'
                       else number(where, entry[key], positive=True))
    xyz = vector('shape %r: xyz' % name, entry.get('xyz'))
    rpy = vector('shape %r: rpy' % name, entry.get('rpy', [0.0, 0.0, 0.0]))
    rgb = colour('shape %r: colour' % name, entry.get('colour'))
    return Shape(name, kind, fields['size'], fields['radius'], fields['length'], xyz, rpy, rgb)


def parse_shapes(document, where='the file'):
    """Return the Shapes of a load_document mapping's `shapes` list (names must be unique);
    raise ShapeFileError naming `where` and the entry."""
    entries = document.get('shapes', [])
    if not isinstance(entries, list):
        raise ShapeFileError('%s: shapes must be a list' % where)
    try:
        shapes = [parse_shape(entry, i) for i, entry in enumerate(entries)]
    except ShapeFileError as error:
        raise ShapeFileError('%s: %s' % (where, error)) from None
    names = [s.name for s in shapes]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ShapeFileError('%s: shape names must be unique, %s appear more than once'
                             % (where, twice))
    return shapes


def load_document(text, keys, where):
    """Return the mapping of a shape file's YAML text ({} for an empty file) with only the
    top-level `keys` and, if it names one, Baxter's base frame.

    Raises:
        ShapeFileError: not YAML, not a mapping, an unknown key or another frame (naming where).
    """
    try:
        document = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise ShapeFileError('%s is not YAML: %s' % (where, error)) from None
    if document is None:
        return {}
    if not isinstance(document, dict):
        raise ShapeFileError('%s must be a mapping (%s)' % (where, ', '.join(keys)))
    unknown = sorted(set(document) - set(keys))
    if unknown:
        raise ShapeFileError('%s: unknown keys %s' % (where, unknown))
    check_frame(document, where)
    return document


def read_text(path, error=ShapeFileError, kind=''):
    """Return the text of a shape file.

    Raises:
        error: the file cannot be read ('cannot read <kind> <path>: why').
    """
    try:
        with open(path) as stream:
            return stream.read()
    except OSError as reason:
        raise error('cannot read %s%s: %s' % (kind + ' ' if kind else '', path, reason)) from None


def check_frame(document, where):
    """Raise ShapeFileError unless a document's `frame` (default base) is Baxter's base."""
    if document.get('frame', bd.BASE_FRAME) != bd.BASE_FRAME:
        raise ShapeFileError("%s: shapes must be in Baxter's %r frame, got frame %r"
                             % (where, bd.BASE_FRAME, document['frame']))


def shape_pose(shape):
    """Return the 4x4 pose of a Shape's centre in the base frame."""
    pose = np.eye(4)
    pose[:3, :3] = bd.rpy_matrix(*shape.rpy)
    pose[:3, 3] = shape.xyz
    return pose


def link_shapes(urdf_text, tags):
    """Return {link: [Shape in the link's frame]} of a URDF's boxes, cylinders and spheres.

    Each link's shapes are those of the first of `tags` ('collision', 'visual') under which it has
    any; mesh files are left out. A Shape is named after its link and has its material's colour
    (None without one).

    Raises:
        ShapeFileError: the text is not XML, or a shape is malformed (naming its link).
    """
    root = bd.parse_urdf(urdf_text, ShapeFileError)
    named = {}
    try:
        for material in root.findall('material'):
            if material.find('color') is not None:
                named[material.get('name')] = _rgb(material)
    except (TypeError, ValueError) as error:
        raise ShapeFileError('material %r: %s' % (material.get('name'), error)) from None
    result = {}
    for link in root.findall('link'):
        name = link.get('name')
        try:
            for tag in tags:
                found = [_urdf_shape(name, e, named) for e in link.findall(tag)]
                found = [shape for shape in found if shape is not None]
                if found:
                    result[name] = found
                    break
        except (TypeError, ValueError) as error:
            raise ShapeFileError('link %r: %s' % (name, error)) from None
    return result


def _rgb(material):
    return tuple(bd.floats(material.find('color').get('rgba'), '', 4)[:3])


def _urdf_shape(link, element, named):
    """Return the Shape of a URDF <visual> or <collision>, or None for a mesh file."""
    geometry = element.find('geometry')
    if geometry is None:
        raise ValueError('<%s> without <geometry>' % element.tag)
    if not len(geometry):
        raise ValueError('empty <geometry>')
    kind = geometry[0].tag
    if kind == 'mesh':
        return None
    if kind not in TYPES:
        raise ValueError('unknown geometry <%s>' % kind)
    fields = {'size': None, 'radius': None, 'length': None}
    for key in TYPES[kind]:
        text = geometry[0].get(key)
        fields[key] = tuple(bd.floats(text, '', 3)) if key == 'size' else float(text)
    origin = element.find('origin')
    xyz, rpy = (tuple(bd.floats(None if origin is None else origin.get(key), '0 0 0', 3))
                for key in ('xyz', 'rpy'))
    material = element.find('material')
    colour = None
    if material is not None:
        colour = _rgb(material) if material.find('color') is not None else \
            named.get(material.get('name'))
    return Shape(link, kind, fields['size'], fields['radius'], fields['length'], xyz, rpy, colour)
