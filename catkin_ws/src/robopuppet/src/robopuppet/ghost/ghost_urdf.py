"""The ghost's robot description: Baxter's URDF with every link and joint name prefixed, and
every material tinted in one colour.

Debian's robot_state_publisher has no tf_prefix, so a second robot in the same tf tree needs
names of its own: 'base' becomes 'ghost/base', 'right_s0' becomes 'ghost/right_s0', and so on.
RViz's RobotModel draws our URDF's boxes and cylinders in their material colours and has no
colour of its own per display, so the ghost (blue) and the calibration target (green) are told
from the real Baxter by a tint: each material becomes the tint, darker for Baxter's dark parts
(the assist's prediction, launch/assist.launch: orange).
Pure: XML text in, XML text out. Also the executable nodes/ghost_urdf, which prints the ghost
description for a launch file's <param command="...">.
"""
import sys
import xml.etree.ElementTree as ET

DEFAULT_PREFIX = 'ghost/'  # ghost frames: ghost/base, ghost/right_gripper, ...
# (element path, attribute) of every name a link or joint is referred to by in Baxter's URDF.
LINK_NAMES = (('link', 'name'), ('joint/parent', 'link'), ('joint/child', 'link'))
JOINT_NAMES = (('joint', 'name'), ('joint/mimic', 'joint'))
# Elements naming links or joints that this module does not rename: refused, not left stale.
UNSUPPORTED = ('gazebo', 'transmission')


# Tints by name (launch/ghost.launch gives the name): the puppet's ghost blue, the calibration
# target green, the assist's prediction orange; the real Baxter keeps its red and black.
TINTS = {'ghost': (0.15, 0.45, 1.0), 'target': (0.2, 0.85, 0.25), 'assist': (1.0, 0.55, 0.1)}
SHADE_FLOOR = 0.45                # a black part gets 45 % of the tint, a white one all of it


class PrefixError(ValueError):
    """The prefix or the URDF text cannot make a ghost description."""


def check_prefix(prefix):
    """Return prefix unchanged if it can start a tf frame name (non-empty, no '/' first, no
    blank); raise PrefixError otherwise."""
    if not isinstance(prefix, str) or not prefix or prefix.startswith('/') or \
            any(c.isspace() for c in prefix):
        raise PrefixError('ghost prefix must be a non-empty name without blanks or a leading '
                          "'/', got %r" % (prefix,))
    return prefix


def check_tint(tint):
    """Return tint as a tuple of 3 floats in 0..1; raise PrefixError otherwise."""
    try:
        rgb = tuple(float(c) for c in tint)
    except (TypeError, ValueError):
        rgb = ()
    if len(rgb) != 3 or not all(0.0 <= c <= 1.0 for c in rgb):
        raise PrefixError('a tint must be three numbers in 0..1 (R,G,B), got %r' % (tint,))
    return rgb


def tinted(rgba, tint):
    """Return the 'r g b a' text of a URDF colour in `tint`, shaded by its own lightness (its
    alpha kept)."""
    r, g, b, a = (float(c) for c in rgba.split())
    shade = SHADE_FLOOR + (1.0 - SHADE_FLOOR) * (0.299 * r + 0.587 * g + 0.114 * b)
    return ' '.join('%.4g' % c for c in [t * shade for t in tint] + [a])


def prefix_description(urdf_text, prefix=DEFAULT_PREFIX, tint=None):
    """Return urdf_text with prefix put before every link and joint name and every reference
    to one (joint parent, child and mimic), and every material colour in `tint` (R, G, B in
    0..1; None: colours unchanged). Materials keep their names: they are no frames.

    Raises:
        PrefixError: a bad prefix or tint, text that is not a URDF robot, or elements this
            function does not rename (gazebo, transmission).
    """
    if tint is not None:
        tint = check_tint(tint)
    check_prefix(prefix)
    try:
        root = ET.fromstring(urdf_text)
    except ET.ParseError as error:
        raise PrefixError('robot description is not XML: %s' % error) from error
    if root.tag != 'robot':
        raise PrefixError('robot description has root <%s>, not <robot>' % root.tag)
    unsupported = sorted({e.tag for e in root if e.tag in UNSUPPORTED})
    if unsupported:
        raise PrefixError('cannot prefix a description with %s elements' % unsupported)
    for path, attribute in LINK_NAMES + JOINT_NAMES:
        for element in root.findall(path):
            name = element.get(attribute)
            if not name:
                raise PrefixError('<%s> without %s' % (path, attribute))
            element.set(attribute, prefix + name)
    for colour in root.iter('color') if tint is not None else ():
        try:
            colour.set('rgba', tinted(colour.get('rgba', ''), tint))
        except ValueError:
            raise PrefixError('<color rgba=%r> is not four numbers' % colour.get('rgba')) from None
    return ET.tostring(root, encoding='unicode')


def main(argv=None):
    """Print the ghost description of a URDF file: ghost_urdf URDF_FILE [PREFIX [TINT]] (TINT a
    name of TINTS or R,G,B, e.g. 0.15,0.45,1); exit status 1 with a message on stderr when the
    file cannot be read or prefixed."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) not in (1, 2, 3):
        sys.stderr.write('usage: ghost_urdf URDF_FILE [PREFIX (default %s) [%s or R,G,B]]\n'
                         % (DEFAULT_PREFIX, ' or '.join(sorted(TINTS))))
        return 2
    try:
        tint = (TINTS.get(args[2]) or args[2].split(',')) if len(args) == 3 else None
        with open(args[0]) as urdf:
            text = prefix_description(urdf.read(), *args[1:2], tint=tint)
    except (OSError, PrefixError) as error:
        sys.stderr.write('ghost_urdf: %s\n' % error)
        return 1
    sys.stdout.write(text + '\n')
    return 0
