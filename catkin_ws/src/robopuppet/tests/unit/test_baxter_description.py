"""Tests of robopuppet.baxter_description: the URDF's joint table and forward kinematics."""
import math
import os

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.interface import BAXTER_SIDES

DESC = bd.load()

# Transcribed from baxter-kinematics.md (Rethink's baxter_description 1.2.0), independently of
# the URDF: (joint, origin xyz, origin rpy, lower, upper, velocity).
H = math.pi / 2
ARM_TABLE = [
    ('s0', (0.055695, 0, 0.011038), (0, 0, 0), -1.70167993878, 1.70167993878, 1.5),
    ('s1', (0.069, 0, 0.27035), (-H, 0, 0), -2.147, 1.047, 1.5),
    ('e0', (0.102, 0, 0), (H, 0, H), -3.05417993878, 3.05417993878, 1.5),
    ('e1', (0.069, 0, 0.26242), (-H, -H, 0), -0.05, 2.618, 1.5),
    ('w0', (0.10359, 0, 0), (H, 0, H), -3.059, 3.059, 4.0),
    ('w1', (0.01, 0, 0.2707), (-H, -H, 0), -1.57079632679, 2.094, 4.0),
    ('w2', (0.115975, 0, 0), (H, 0, H), -3.059, 3.059, 4.0),
]
MOUNT = {'left': ((0.024645, 0.219645, 0.118588), 0.7854),
         'right': ((0.024645, -0.219645, 0.118588), -0.7854)}
# wrist -> hand, hand -> gripper_base, gripper_base -> gripper: all straight along z.
TOOL_Z_M = 0.11355 + 0.025 + 0.1327


def rot(axis, angle):
    """Elementary rotation matrix about x, y or z, written out by hand."""
    c, s = math.cos(angle), math.sin(angle)
    return {'x': np.array([[1, 0, 0], [0, c, -s], [0, s, c]]),
            'y': np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]]),
            'z': np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])}[axis]


def frame(xyz, rotation):
    t = np.eye(4)
    t[:3, :3] = rotation
    t[:3, 3] = xyz
    return t


def reference_fk(side, angles):
    """Gripper pose in base from the table above: every joint turns about its local z."""
    xyz, yaw = MOUNT[side]
    pose = frame(xyz, rot('z', yaw))
    for (name, origin, (r, p, y), *_), q in zip(ARM_TABLE, angles):
        pose = pose @ frame(origin, rot('z', y) @ rot('y', p) @ rot('x', r)) @ frame(
            (0, 0, 0), rot('z', q))
    return pose @ frame((0, 0, TOOL_Z_M), np.eye(3))


def quaternion_matrix(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


@pytest.mark.parametrize('side', BAXTER_SIDES)
def test_arm_joint_names_in_puppet_order(side):
    assert bd.arm_joint_names(side) == [side + s for s in
                                        ('_s0', '_s1', '_e0', '_e1', '_w0', '_w1', '_w2')]


def test_unknown_side_is_refused():
    with pytest.raises(ValueError):
        bd.arm_joint_names('L')


@pytest.mark.parametrize('side', BAXTER_SIDES)
def test_arm_limits_are_rethinks(side):
    limits = bd.arm_limits(side)
    assert [lim.name for lim in limits] == bd.arm_joint_names(side)
    for lim, (_, _, _, lower, upper, velocity) in zip(limits, ARM_TABLE):
        assert (lim.lower, lim.upper, lim.velocity) == (lower, upper, velocity)


def test_head_and_fingers():
    assert bd.load().limit('head_pan')[1:3] == (-1.3963, 1.3963)
    driven, mimic = bd.gripper_finger_joints('left')
    assert DESC.limit(driven)[1:3] == (0.0, 0.020833)
    assert DESC.joints[mimic].mimic == (driven, -1.0, 0.0)
    assert DESC.joints['torso_t0'].type == 'fixed'


@pytest.mark.parametrize('side', BAXTER_SIDES)
@pytest.mark.parametrize('angles', [
    (0, 0, 0, 0, 0, 0, 0),
    (0, -0.55, 0, 0.75, 0, 1.26, 0),
    (0.4, -1.0, 1.2, 2.0, -2.5, 0.7, 3.0),
    (-1.7, 1.0, -3.0, -0.05, 3.0, -1.5, -3.0),
])
def test_forward_kinematics_matches_the_published_chain(side, angles):
    positions = dict(zip(bd.arm_joint_names(side), angles))
    expected = reference_fk(side, angles)
    xyz, quat = DESC.pose(positions, bd.gripper_link(side))
    assert np.allclose(xyz, expected[:3, 3], atol=1e-9)
    assert np.allclose(quaternion_matrix(quat), expected[:3, :3], atol=1e-9)
    assert quat[3] >= 0.0 and math.isclose(np.linalg.norm(quat), 1.0)


def test_mirrored_joint_angles_give_a_mirrored_endpoint():
    left = (0.3, -0.4, 0.5, 1.1, -0.6, 0.9, 0.7)
    mirror = [-q if i in (0, 2, 4, 6) else q for i, q in enumerate(left)]
    (lx, ly, lz), _ = DESC.pose(dict(zip(bd.arm_joint_names('left'), left)), 'left_gripper')
    (rx, ry, rz), _ = DESC.pose(dict(zip(bd.arm_joint_names('right'), mirror)), 'right_gripper')
    assert np.allclose((lx, -ly, lz), (rx, ry, rz), atol=1e-9)


def test_fingers_open_symmetrically_along_the_gripper_y_axis():
    closed = DESC.transform({}, 'l_gripper_r_finger', 'left_gripper_base')[:3, 3]
    opened = DESC.transform({'l_gripper_l_finger_joint': 0.02},
                            'l_gripper_r_finger', 'left_gripper_base')[:3, 3]
    assert np.allclose(opened - closed, (0, -0.02, 0))


def test_bad_descriptions_are_refused():
    with pytest.raises(bd.DescriptionError):
        bd.Description('<robot')
    with pytest.raises(bd.DescriptionError):
        bd.Description('<robot name="x"><link name="base"/></robot>')
    with pytest.raises(KeyError):
        DESC.chain('no_such_link')


def test_urdf_path_is_inside_the_package_dir(tmp_path):
    assert bd.urdf_path('/pkg') == '/pkg/urdf/baxter.urdf'
    assert bd.urdf_path(os.path.dirname(os.path.dirname(bd.URDF_PATH))) == bd.URDF_PATH
    with pytest.raises(bd.DescriptionError, match='cannot read'):
        bd.load(bd.urdf_path(str(tmp_path)))


def test_urdf_text_is_read_and_parsed_with_the_callers_error():
    assert bd.parse_urdf(bd.read_urdf()).tag == 'robot'
    with pytest.raises(ValueError, match='robot description is not XML') as raised:
        bd.parse_urdf('<robot', ValueError)
    assert type(raised.value) is ValueError
    with pytest.raises(bd.DescriptionError, match='cannot read robot description'):
        bd.read_urdf('/nonexistent/baxter.urdf')
