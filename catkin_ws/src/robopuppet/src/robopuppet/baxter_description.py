"""Baxter's joints, limits and forward kinematics, read from the package's urdf/baxter.urdf.

This module is the one place where Baxter's joint names and limits come from: the stand-in
(baxter_model) and the arm controller import them from here, and the URDF that RViz and
robot_state_publisher use is the same file. Pure: parses XML text, no ROS, no clock.
"""
import collections
import functools
import math
import os
import xml.etree.ElementTree as ET

import numpy as np

from robopuppet.interface import BAXTER_SIDES


def urdf_path(package_dir):
    """Return the path of baxter.urdf in a robopuppet package directory (source or installed).

    Nodes pass rospkg.RosPack().get_path('robopuppet'), which is right in every space.
    """
    return os.path.join(package_dir, 'urdf', 'baxter.urdf')


# The source tree's copy, next to this module: right for tests and tools run from the work tree
# (and the devel space), wrong after `catkin_make install`, where nodes must use urdf_path().
URDF_PATH = urdf_path(os.path.abspath(os.path.join(os.path.dirname(__file__), '..', '..')))

# Puppet joint J drives the J-th of these: shoulder s0 s1, elbow e0 e1, wrist w0 w1 w2.
ARM_JOINT_SUFFIXES = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
# The pose the Rethink SDK calls neutral (rad), the same for both arms.
# Baxter's default mode-1 speed ratio of the URDF velocity limits (Rethink's SDK 1.2.0 limb.py)
POSITION_SPEED_RATIO = 0.3
NEUTRAL_POSE = {'s0': 0.0, 's1': -0.55, 'e0': 0.0, 'e1': 0.75, 'w0': 0.0, 'w1': 1.26, 'w2': 0.0}
BASE_FRAME = 'base'
# Joints the real robot lists in /robot/joint_states although they do not move here.
HEAD_PAN = 'head_pan'
TORSO = 'torso_t0'

Joint = collections.namedtuple(
    'Joint', 'name type parent child origin axis lower upper velocity effort mimic')
Joint.__doc__ = """One URDF joint. origin: 4x4 parent-to-joint transform; axis: unit 3-vector;
lower/upper in rad or m, velocity in rad/s or m/s (None for fixed joints); mimic: (joint name,
multiplier, offset) or None."""

JointLimit = collections.namedtuple('JointLimit', 'name lower upper velocity')
JointLimit.__doc__ = """Limits of one joint: position lower/upper (rad or m), velocity (rad/s or
m/s)."""


class DescriptionError(ValueError):
    """The URDF text is not a robot description this module can use."""


def _check_side(side):
    if side not in BAXTER_SIDES:
        raise ValueError("Baxter side must be 'left' or 'right', got %r" % (side,))


def arm_joint_names(side):
    """Return the 7 arm joint names of a side in puppet order s0, s1, e0, e1, w0, w1, w2."""
    _check_side(side)
    return ['%s_%s' % (side, suffix) for suffix in ARM_JOINT_SUFFIXES]


def gripper_finger_joints(side):
    """Return (driven, mimic) finger joint names of a side's electric gripper."""
    _check_side(side)
    return ('%s_gripper_l_finger_joint' % side[0], '%s_gripper_r_finger_joint' % side[0])


def gripper_link(side):
    """Return the name of a side's gripper tool-point link (the endpoint_state frame)."""
    _check_side(side)
    return '%s_gripper' % side


def neutral_pose(side):
    """Return {joint name: angle rad} of the SDK's neutral pose for one arm."""
    return {'%s_%s' % (side, s): NEUTRAL_POSE[s] for s in ARM_JOINT_SUFFIXES}


def floats(text, default, count=None):
    """Return the numbers of a URDF attribute's text (default's when it is absent).

    Raises:
        ValueError: not numbers, or not `count` of them (when count is given).
    """
    values = [float(v) for v in (text or default).split()]
    if count is not None and len(values) != count:
        raise ValueError('expected %d numbers, got %r' % (count, text))
    return values


def rpy_matrix(roll, pitch, yaw):
    """Return the 3x3 rotation of URDF fixed-axis roll, pitch, yaw (Rz(yaw) Ry(pitch) Rx(roll))."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def _transform(rotation, xyz):
    t = np.eye(4)
    t[:3, :3] = rotation
    t[:3, 3] = xyz
    return t


def origin_matrix(element):
    """Return the 4x4 pose of a URDF element's <origin> in its frame (identity when absent)."""
    origin = element.find('origin')
    xyz = floats(origin.get('xyz') if origin is not None else None, '0 0 0', 3)
    rpy = floats(origin.get('rpy') if origin is not None else None, '0 0 0', 3)
    return _transform(rpy_matrix(*rpy), xyz)


def _parse_joint(element):
    name = element.get('name')
    kind = element.get('type')
    try:
        parent = element.find('parent').get('link')
        child = element.find('child').get('link')
        origin = origin_matrix(element)
        axis = element.find('axis')
        axis = np.array(floats(axis.get('xyz') if axis is not None else None, '1 0 0', 3))
        lower = upper = velocity = effort = None
        if kind in ('revolute', 'prismatic'):
            limit = element.find('limit')
            lower, upper = float(limit.get('lower', 0)), float(limit.get('upper', 0))
            velocity, effort = float(limit.get('velocity')), float(limit.get('effort'))
        mimic = element.find('mimic')
        if mimic is not None:
            mimic = (mimic.get('joint'), float(mimic.get('multiplier', 1)),
                     float(mimic.get('offset', 0)))
    except (AttributeError, TypeError, ValueError) as error:
        raise DescriptionError('joint %r: %s' % (name, error)) from error
    if kind not in ('revolute', 'prismatic', 'fixed', 'continuous'):
        raise DescriptionError('joint %r: unsupported type %r' % (name, kind))
    return Joint(name, kind, parent, child, origin,
                 axis / np.linalg.norm(axis), lower, upper, velocity, effort, mimic)


def parse_urdf(urdf_text, error=DescriptionError):
    """Return the root element of a URDF's XML text.

    Raises:
        error: the text is not XML ('robot description is not XML: ...').
    """
    try:
        return ET.fromstring(urdf_text)
    except ET.ParseError as reason:
        raise error('robot description is not XML: %s' % reason) from reason


def read_urdf(path=URDF_PATH):
    """Return the text of a URDF file (the source tree's baxter.urdf by default).

    Raises:
        DescriptionError: the file cannot be read.
    """
    try:
        with open(path) as urdf:
            return urdf.read()
    except OSError as error:
        raise DescriptionError('cannot read robot description %s: %s' % (path, error)) from error


class Description:
    """Joints of a robot description, with limits and forward kinematics.

    Args:
        urdf_text: the URDF XML (e.g. the robot_description parameter).

    Raises:
        DescriptionError: the text is not URDF, or lacks a Baxter arm joint.
    """

    def __init__(self, urdf_text):
        root = parse_urdf(urdf_text)
        self.joints = collections.OrderedDict()
        for element in root.findall('joint'):
            joint = _parse_joint(element)
            self.joints[joint.name] = joint
        self._by_child = {j.child: j for j in self.joints.values()}
        for side in BAXTER_SIDES:
            for name in arm_joint_names(side) + list(gripper_finger_joints(side)):
                if name not in self.joints or self.joints[name].type == 'fixed':
                    raise DescriptionError('robot description lacks movable joint %r' % name)

    def limit(self, name):
        """Return the JointLimit of a movable joint.

        Raises:
            KeyError: no movable joint of that name.
        """
        joint = self.joints.get(name)
        if joint is None or joint.velocity is None:
            raise KeyError('no movable joint %r in the robot description' % (name,))
        return JointLimit(name, joint.lower, joint.upper, joint.velocity)

    def arm_limits(self, side):
        """Return the 7 JointLimits of a side's arm in puppet order (rad, rad/s)."""
        return [self.limit(name) for name in arm_joint_names(side)]

    def chain(self, tip, base=BASE_FRAME):
        """Return the joints from base to tip link, in order.

        Raises:
            KeyError: tip is not below base in the tree.
        """
        joints = []
        link = tip
        while link != base:
            joint = self._by_child.get(link)
            if joint is None:
                raise KeyError('link %r is not below %r' % (tip, base))
            joints.append(joint)
            link = joint.parent
        return joints[::-1]

    def transform(self, positions, tip, base=BASE_FRAME):
        """Return the 4x4 pose of link tip in frame base.

        Args:
            positions: {joint name: position (rad or m)}; missing joints count as 0, mimic joints
                follow the joint they mimic.
        """
        pose = np.eye(4)
        for joint in self.chain(tip, base):
            pose = pose @ joint.origin
            if joint.type == 'fixed':
                continue
            if joint.mimic is not None:
                source, multiplier, offset = joint.mimic
                q = positions.get(source, 0.0) * multiplier + offset
            else:
                q = positions.get(joint.name, 0.0)
            if joint.type == 'prismatic':
                motion = _transform(np.eye(3), joint.axis * q)
            else:
                motion = _transform(axis_angle_matrix(joint.axis, q), (0.0, 0.0, 0.0))
            pose = pose @ motion
        return pose

    def pose(self, positions, tip, base=BASE_FRAME):
        """Return ((x, y, z) m, (qx, qy, qz, qw)) of link tip in frame base."""
        pose = self.transform(positions, tip, base)
        return tuple(pose[:3, 3]), matrix_quaternion(pose[:3, :3])


def axis_angle_matrix(axis, angle):
    """Return the 3x3 rotation by angle (rad) about a unit axis (Rodrigues)."""
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def matrix_quaternion(rotation):
    """Return the unit quaternion (x, y, z, w), w >= 0, of a 3x3 rotation matrix."""
    m = rotation
    trace = m[0, 0] + m[1, 1] + m[2, 2]
    if trace > 0.0:
        s = 2.0 * math.sqrt(trace + 1.0)
        q = ((m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s, 0.25 * s)
    elif m[0, 0] > m[1, 1] and m[0, 0] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[0, 0] - m[1, 1] - m[2, 2])
        q = (0.25 * s, (m[0, 1] + m[1, 0]) / s, (m[0, 2] + m[2, 0]) / s, (m[2, 1] - m[1, 2]) / s)
    elif m[1, 1] > m[2, 2]:
        s = 2.0 * math.sqrt(1.0 + m[1, 1] - m[0, 0] - m[2, 2])
        q = ((m[0, 1] + m[1, 0]) / s, 0.25 * s, (m[1, 2] + m[2, 1]) / s, (m[0, 2] - m[2, 0]) / s)
    else:
        s = 2.0 * math.sqrt(1.0 + m[2, 2] - m[0, 0] - m[1, 1])
        q = ((m[0, 2] + m[2, 0]) / s, (m[1, 2] + m[2, 1]) / s, 0.25 * s, (m[1, 0] - m[0, 1]) / s)
    q = np.array(q)
    q /= np.linalg.norm(q)
    return tuple(-q if q[3] < 0.0 else q)


@functools.lru_cache(maxsize=None)
def load(path=URDF_PATH):
    """Return the Description of a URDF file (the source tree's baxter.urdf by default), cached.

    Raises:
        DescriptionError: the file cannot be read or is not a usable description.
    """
    return Description(read_urdf(path))


def arm_limits(side, description=None):
    """Return the 7 JointLimits (rad, rad/s) of a side's arm in puppet order.

    Args:
        description: a Description; the source tree's baxter.urdf (see load) when None.
    """
    return (description or load()).arm_limits(side)
