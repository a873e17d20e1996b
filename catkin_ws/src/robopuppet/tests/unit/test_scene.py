"""Shape files (config/world.yaml, later obstacles and zones): the format, its refusals, and the
robot's visual shapes posed like baxter_description's forward kinematics."""
import os

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.cameras import robot_shapes, scene
from robopuppet.world.shapes import ShapeFileError

WORLD_FILE = os.path.join(os.path.dirname(bd.URDF_PATH), '..', 'config', 'world.yaml')


def test_the_world_file_holds_a_bed_and_a_patient_in_front_of_baxter():
    world = scene.load_world(WORLD_FILE)
    shapes = {s.name: s for s in world.shapes}
    assert {'mattress', 'patient_head', 'patient_torso'} <= set(shapes)
    mattress = shapes['mattress']
    top_z = mattress.xyz[2] + mattress.size[2] / 2.0
    assert world.floor.z + 0.5 < top_z < world.floor.z + 0.8  # a hospital bed's height
    assert mattress.xyz[0] > 0.5 and 1.7 < mattress.size[1] < 2.2  # across Baxter's front
    head = shapes['patient_head']
    assert head.xyz[2] - head.radius > top_z - 0.01  # on the bed, not in it
    # The right gripper can reach above the patient: the bed is within an arm's length.
    shoulder = bd.load().transform({}, 'right_upper_shoulder')[:3, 3]
    assert np.linalg.norm(np.subtract(shapes['patient_torso'].xyz, shoulder)) < 1.1
    assert set(world.cameras) == {'room_camera'}


def test_shapes_follow_urdf_geometry():
    text = """
    frame: base
    shapes:
      - {name: b, type: box, size: [1, 2, 3], xyz: [0.5, 0, 0], colour: [1, 0, 0]}
      - {name: c, type: cylinder, radius: 0.1, length: 0.4, xyz: [0, 0, 1], rpy: [1.5708, 0, 0]}
      - {name: s, type: sphere, radius: 0.2, xyz: [0, 0, 0]}
    """
    b, c, s = scene.parse_world(text).shapes
    assert (b.size, b.colour, c.radius, c.length, s.radius, s.colour) == (
        (1.0, 2.0, 3.0), (1.0, 0.0, 0.0), 0.1, 0.4, 0.2, None)
    # The cylinder's axis (its own z) turned by roll 90 degrees lies along -y of the base.
    vertices = scene.shape_mesh(c).vertices
    assert np.ptp(vertices[:, 1]) == pytest.approx(0.4, abs=1e-6)
    assert np.ptp(vertices[:, 2]) == pytest.approx(0.2, abs=1e-3)
    box = scene.shape_mesh(b).vertices
    np.testing.assert_allclose(box.min(axis=0), (0.0, -1.0, -1.5), atol=1e-6)


@pytest.mark.parametrize('text, words', [
    ('shapes: [{name: a, type: cone, radius: 1, xyz: [0, 0, 0]}]', "type must be one of"),
    ('shapes: [{name: a, type: box, xyz: [0, 0, 0]}]', "'a' \\(box\\) needs size"),
    ('shapes: [{name: a, type: sphere, radius: -1, xyz: [0, 0, 0]}]', 'positive number'),
    ('shapes: [{name: a, type: sphere, radius: 1, xyz: [0, 0]}]', 'list of 3 numbers'),
    ('shapes: [{name: a, type: sphere, radius: 1, xyz: [0, 0, 0], colour: [2, 0, 0]}]',
     'in 0..1'),
    ('shapes: [{name: a, type: sphere, radius: 1, xyz: [0, 0, 0], height: 2}]',
     'unknown keys'),
    ('shapes: [{type: sphere, radius: 1, xyz: [0, 0, 0]}]', 'needs a name'),
    ('shapes: [{name: a, type: sphere, radius: 1, xyz: [0, 0, 0]},'
     ' {name: a, type: sphere, radius: 1, xyz: [1, 0, 0]}]', 'unique'),
    ('frame: world\nshapes: []', "in Baxter's 'base' frame"),
    ('shapes: {a: 1}', 'shapes must be a list'),
    ('cameras: {c: {xyz: [0, 0, 1], look_at: [0, 0, 0]}}', 'image upright'),
    ('cameras: {c: {xyz: [0, 0, 1], look_at: [1, 0, 0], hfov_deg: 190}}', 'below 180'),
    ('floor: {z: low}', 'floor: z must be a number'),
    ('shapes: [', 'not YAML'),
    ('- a list', 'must be a mapping'),
])
def test_a_malformed_file_is_refused_naming_what_is_wrong(text, words):
    with pytest.raises(ShapeFileError, match=words):
        scene.parse_world(text)


def test_a_missing_file_is_refused_naming_it(tmp_path):
    with pytest.raises(ShapeFileError, match='cannot read .*nothing.yaml'):
        scene.load_world(str(tmp_path / 'nothing.yaml'))


def test_an_optional_shape_file_may_be_missing_but_not_malformed(tmp_path):
    assert scene.optional_shapes(None) == ([], '')
    assert scene.optional_shapes(str(tmp_path / 'none.yaml')) == ([], '')
    bad = tmp_path / 'bad.yaml'
    bad.write_text('shapes: [')
    found, problem = scene.optional_shapes(str(bad))
    assert found == [] and 'not YAML' in problem
    good = tmp_path / 'good.yaml'
    good.write_text('shapes: [{name: a, type: sphere, radius: 1, xyz: [0, 0, 0]}]')
    assert [s.name for s in scene.optional_shapes(str(good))[0]] == ['a']


def test_look_at_gives_an_upright_optical_frame():
    pose = scene.look_at_pose((2.0, 0.0, 1.0), (0.0, 0.0, 1.0))  # looking back along -x
    np.testing.assert_allclose(pose[:3, 2], (-1, 0, 0), atol=1e-12)  # z forward
    np.testing.assert_allclose(pose[:3, 0], (0, 1, 0), atol=1e-12)   # x right: +y seen so
    np.testing.assert_allclose(pose[:3, 1], (0, 0, -1), atol=1e-12)  # y down


def test_robot_links_are_posed_like_baxter_description():
    with open(bd.URDF_PATH) as urdf:
        text = urdf.read()
    description = bd.Description(text)
    poser = robot_shapes.RobotPoser(description)
    rng = np.random.default_rng(3)
    positions = {name: rng.uniform(-1.0, 1.0) for name, joint in description.joints.items()
                 if joint.type != 'fixed'}
    poses = poser.link_poses(positions)
    for link in ('right_hand_camera', 'left_gripper', 'head_camera', 'r_gripper_r_finger'):
        np.testing.assert_allclose(poses[link], description.transform(positions, link),
                                   atol=1e-12)
    parts = robot_shapes.link_meshes(text)
    assert {'torso', 'right_upper_shoulder', 'r_gripper_l_finger', 'right_hand_camera'} <= \
        set(parts)
    assert 'base' not in parts and 'head_camera' not in parts  # no visuals


def test_the_posed_robot_mesh_moves_its_links_with_the_joints():
    with open(bd.URDF_PATH) as urdf:
        robot = robot_shapes.RobotMesh(urdf.read())
    still, _ = robot.posed({})
    moved, _ = robot.posed({'right_w2': 0.5})
    changed = np.any(still.vertices != moved.vertices, axis=1)
    assert 0 < changed.sum() < len(changed) / 4  # the wrist, hand, camera and fingers only


def test_a_visual_with_a_malformed_geometry_is_refused_naming_its_link():
    text = ('<robot name="r"><link name="l"><visual><geometry><box size="1 2"/></geometry>'
            '</visual></link></robot>')
    with pytest.raises(ShapeFileError, match="link 'l'"):
        robot_shapes.link_meshes(text)
