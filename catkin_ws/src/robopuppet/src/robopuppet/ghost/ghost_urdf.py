"""The ghost's robot description: Baxter's URDF with every link and joint name prefixed.

Debian's robot_state_publisher has no tf_prefix, so a second robot in the same tf tree needs
names of its own: 'base' becomes 'ghost/base', 'right_s0' becomes 'ghost/right_s0', and so on.
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


def prefix_description(urdf_text, prefix=DEFAULT_PREFIX):
    """Return urdf_text with prefix put before every link and joint name and every reference
    to one (joint parent, child and mimic). Materials keep their names: they are no frames.

    Raises:
        PrefixError: a bad prefix, text that is not a URDF robot, or elements this function
            does not rename (gazebo, transmission).
    """
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
    return ET.tostring(root, encoding='unicode')


def main(argv=None):
    """Print the ghost description of a URDF file: ghost_urdf URDF_FILE [PREFIX]; exit status
    1 with a message on stderr when the file cannot be read or prefixed."""
    args = sys.argv[1:] if argv is None else argv
    if len(args) not in (1, 2):
        sys.stderr.write('usage: ghost_urdf URDF_FILE [PREFIX (default %s)]\n' % DEFAULT_PREFIX)
        return 2
    try:
        with open(args[0]) as urdf:
            text = prefix_description(urdf.read(), *args[1:])
    except (OSError, PrefixError) as error:
        sys.stderr.write('ghost_urdf: %s\n' % error)
        return 1
    sys.stdout.write(text + '\n')
    return 0
