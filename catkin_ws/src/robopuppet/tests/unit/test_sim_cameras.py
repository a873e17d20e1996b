"""The simulated cameras' core: URDF points land on the right pixel, frames change only when the
joints move, the head camera comes out upright, zones are translucent, the JPEG is as advertised.

These tests render for real through EGL on Mesa (what the node does), headless.
"""
import math
import xml.etree.ElementTree as ET

import cv2
import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.cameras import gl_renderer, jpeg, meshes, scene, sim_cameras
from robopuppet.world import shapes

WIDTH, HEIGHT = 640, 480
with open(bd.URDF_PATH) as _urdf:
    URDF = _urdf.read()
WORLD = scene.load_world(bd.URDF_PATH.replace('urdf/baxter.urdf', 'config/world.yaml'))
DESCRIPTION = bd.load()
BACKGROUND_BGR = (219, 209, 199)  # gl_renderer's default background (0.78, 0.82, 0.86)


def neutral():
    positions = {}
    for side in ('left', 'right'):
        positions.update(bd.neutral_pose(side))
    return positions


def invisible_robot():
    """Return the URDF without its visuals: only the joints and frames remain."""
    root = ET.fromstring(URDF)
    for link in root.findall('link'):
        for visual in link.findall('visual'):
            link.remove(visual)
    return ET.tostring(root, encoding='unicode')


def marker_world(point, radius_m, cameras=None):
    """Return a world holding only a red sphere at point (and the given fixed cameras)."""
    marker = shapes.Shape('marker', 'sphere', None, radius_m, None, tuple(point), (0, 0, 0),
                         (1.0, 0.0, 0.0))
    return scene.World([marker], None, cameras or {})


def red_centroid(image):
    """Return the (u, v) centroid of the red marker's pixels, and how many there are."""
    b, g, r = (image[..., i].astype(int) for i in range(3))
    vs, us = np.nonzero((r > 80) & (g < 40) & (b < 40))
    assert len(us) > 0, 'the marker is not in the image'
    return (us.mean(), vs.mean()), len(us)


def pinhole(point, camera_pose, fx, fy, cx, cy):
    """Return the pixel (u, v) of a base-frame point for an optical frame pose (ROS pinhole)."""
    x, y, z = (np.linalg.inv(camera_pose) @ np.append(point, 1.0))[:3]
    assert z > 0, 'the point is behind the camera'
    return fx * x / z + cx, fy * y / z + cy


@pytest.fixture(scope='module')
def world_cameras():
    core = sim_cameras.SimCameras(URDF, WORLD, WIDTH, HEIGHT, ['room_camera',
                                                              'right_hand_camera',
                                                              'head_camera'])
    core.set_positions(neutral())
    yield core
    core.close()


def test_the_hand_camera_frames_are_rethinks():
    # RethinkRobotics/baxter_common baxter_description/urdf/baxter.urdf, joint <side>_hand_camera
    for side in ('left', 'right'):
        joint = DESCRIPTION.joints['%s_hand_camera' % side]
        assert (joint.type, joint.parent) == ('fixed', '%s_hand' % side)
        np.testing.assert_allclose(joint.origin[:3, 3], (0.03825, 0.012, 0.015355))
        np.testing.assert_allclose(joint.origin[:3, :3], bd.rpy_matrix(0, 0, -1.57079633))
    joint = DESCRIPTION.joints['head_camera']
    assert joint.parent == 'head'
    np.testing.assert_allclose(joint.origin[:3, 3], (0.12839, 0.0, 0.06368))


def test_the_right_gripper_tip_lands_on_its_pixel_in_the_room_camera():
    tip = DESCRIPTION.transform(neutral(), 'right_gripper')[:3, 3]
    room = WORLD.cameras['room_camera']
    core = sim_cameras.SimCameras(invisible_robot(), marker_world(tip, 0.01, WORLD.cameras),
                                  WIDTH, HEIGHT, ['room_camera'])
    core.set_positions(neutral())
    (u, v), count = red_centroid(core.render('room_camera')[0])
    core.close()
    # The room camera's pose worked out here from the world file: look-at with z up.
    forward = np.subtract(room.look_at, room.xyz) / np.linalg.norm(np.subtract(room.look_at,
                                                                                room.xyz))
    right = np.cross(forward, (0, 0, 1))
    right /= np.linalg.norm(right)
    pose = np.eye(4)
    pose[:3, 0], pose[:3, 1], pose[:3, 2], pose[:3, 3] = right, np.cross(forward, right), \
        forward, room.xyz
    f = (WIDTH / 2.0) / math.tan(math.radians(room.hfov_deg) / 2.0)
    expected = pinhole(tip, pose, f, f, (WIDTH - 1) / 2.0, (HEIGHT - 1) / 2.0)
    assert count >= 5
    assert abs(u - expected[0]) < 1.0 and abs(v - expected[1]) < 1.0, ((u, v), expected)


def test_a_point_beside_the_axis_lands_on_its_pixel_in_a_camera_placed_by_hand():
    tip = DESCRIPTION.transform(neutral(), 'right_gripper')[:3, 3]
    # Half a metre in front of the tip (+x), 10 cm to the robot's left, looking along -x: the
    # tip lies 0.1 m to the image's left of the axis at 0.5 m depth (and on the centre row).
    eye = tip + (0.5, 0.1, 0.0)
    cameras = {'test_camera': scene.RoomCamera(tuple(eye), tuple(eye - (1.0, 0.0, 0.0)), 90.0)}
    core = sim_cameras.SimCameras(invisible_robot(), marker_world(tip, 0.004, cameras),
                                  WIDTH, HEIGHT, ['test_camera'])
    core.set_positions(neutral())
    (u, v), _ = red_centroid(core.render('test_camera')[0])
    core.close()
    f = WIDTH / 2.0  # 90 degrees across
    assert abs(u - (319.5 - f * 0.1 / 0.5)) < 1.0 and abs(v - 239.5) < 1.0, (u, v)


def test_the_right_hand_camera_sees_from_its_urdf_frame():
    positions = dict(neutral(), right_s0=0.4, right_w1=0.9, right_w2=-0.6)
    camera = DESCRIPTION.transform(positions, 'right_hand_camera')
    point = (camera @ np.array([0.05, -0.03, 0.4, 1.0]))[:3]  # ahead, right and up a little
    core = sim_cameras.SimCameras(invisible_robot(), marker_world(point, 0.004), WIDTH, HEIGHT,
                                  ['right_hand_camera'])
    core.set_positions(positions)
    (u, v), _ = red_centroid(core.render('right_hand_camera')[0])
    core.close()
    f = 403.0  # sim_cameras.BAXTER_FOCAL_PX at 640 wide
    assert abs(u - (319.5 + f * 0.05 / 0.4)) < 1.0 and abs(v - (239.5 - f * 0.03 / 0.4)) < 1.0


def test_frames_change_when_a_joint_moves_and_not_otherwise(world_cameras):
    core = world_cameras
    core.set_positions(neutral())
    before = {n: core.render(n)[0].copy() for n in ('room_camera', 'right_hand_camera')}
    assert not core.set_positions(neutral())  # nothing moved
    for name, image in before.items():
        assert np.array_equal(core.render(name)[0], image)
    assert core.set_positions({'right_w1': bd.NEUTRAL_POSE['w1'] + 0.3})
    for name, image in before.items():
        moved = core.render(name)[0]
        changed = np.any(moved != image, axis=2).mean()
        assert changed > 0.002, (name, changed)  # the arm in the room, the view of the hand
    core.set_positions(neutral())


def test_the_same_positions_give_the_same_pixels_in_a_new_renderer(world_cameras):
    world_cameras.set_positions(neutral())
    image = world_cameras.render('right_hand_camera')[0]
    other = sim_cameras.SimCameras(URDF, WORLD, WIDTH, HEIGHT, ['right_hand_camera'])
    other.set_positions(neutral())
    again = other.render('right_hand_camera')[0]
    other.close()
    assert np.array_equal(image, again)
    # and the first renderer still draws into its own context after the second one's
    assert np.array_equal(world_cameras.render('right_hand_camera')[0], image)


def test_the_head_camera_image_is_upright(world_cameras):
    image = world_cameras.render('head_camera')[0]
    # Looking ahead and a little down: background (the room beyond the floor) at the top, the
    # floor and the bed at the bottom.
    assert np.all(np.abs(image[:20].astype(int) - BACKGROUND_BGR) <= 1)
    assert np.abs(image[-20:].astype(int) - BACKGROUND_BGR).max() > 20


def test_the_room_camera_sees_baxter_the_bed_and_the_patient(world_cameras):
    image = world_cameras.render('room_camera')[0]
    b, g, r = (image[..., i].astype(int) for i in range(3))
    assert ((r > 120) & (g < 40) & (b < 40)).sum() > 1000  # Baxter's red
    skin = (r > 150) & (r - b > 40) & (g > 90) & (g < r) & (b < g)
    assert skin.sum() > 100  # the patient's head and arms
    assert ((b > 200) & (g > 200) & (r > 200)).sum() > 2000  # sheets and pillow


def test_a_zone_tints_what_lies_behind_it_red_without_hiding_it():
    # A thin wall across the room camera's view (it looks along about yaw 2.4 rad), a metre
    # in front of it.
    zone = shapes.parse_shape({'name': 'wall', 'type': 'box', 'size': [0.05, 6.0, 6.0],
                              'xyz': [1.9, -1.25, 0.6], 'rpy': [0.0, 0.0, 2.4]})
    cameras = {}
    for zones in ([], [zone]):
        core = sim_cameras.SimCameras(URDF, WORLD, WIDTH, HEIGHT, ['room_camera'], zones=zones)
        core.set_positions(neutral())
        cameras[len(zones)] = core.render('room_camera')[0].astype(int)
        core.close()
    plain, tinted = cameras[0], cameras[1]
    redness = (tinted[..., 2] - tinted[..., 0]) - (plain[..., 2] - plain[..., 0])  # red - blue
    assert (redness > 10).mean() > 0.95  # the wall of the zone covers the whole view
    # ...and the scene shows through: the tinted image still has the plain one's structure.
    assert np.corrcoef(plain[..., 1].ravel(), tinted[..., 1].ravel())[0, 1] > 0.95


def test_the_jpeg_has_the_advertised_size_and_quality(world_cameras):
    settings = sim_cameras.read_settings(lambda name, default: {'quality': 65}.get(name,
                                                                                   default))
    image = world_cameras.render('room_camera')[0]
    data = jpeg.encode(image, settings.quality)
    decoded = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_COLOR)
    info = sim_cameras.camera_info_fields(world_cameras.cameras['room_camera'], settings.width,
                                          settings.height)
    assert decoded.shape == (info['height'], info['width'], 3) == (480, 640, 3)
    assert jpeg.quality_of(data) == 65


def test_camera_info_is_the_pinhole_that_renders():
    cameras = sim_cameras.make_cameras(['right_hand_camera', 'head_camera', 'room_camera'],
                                       WORLD, 320, 240)
    hand = sim_cameras.camera_info_fields(cameras['right_hand_camera'], 320, 240)
    assert hand['K'] == [201.5, 0.0, 159.5, 0.0, 201.5, 119.5, 0.0, 0.0, 1.0]  # half of 640
    assert hand['P'] == [201.5, 0.0, 159.5, 0.0, 0.0, 201.5, 119.5, 0.0, 0.0, 0.0, 1.0, 0.0]
    assert cameras['right_hand_camera'].frame_id == 'right_hand_camera'
    assert cameras['head_camera'].k[0][0] == -205.0  # a frame turned upside down
    room = cameras['room_camera']
    assert room.frame_id == 'room_camera_optical_frame' and room.link is None
    assert room.k[0][0] == pytest.approx(160.0 / math.tan(math.radians(30.0)))
    with pytest.raises(ValueError, match='unknown camera .kitchen_camera.'):
        sim_cameras.make_cameras(['kitchen_camera'], WORLD, 320, 240)


def test_settings_defaults_and_refusals():
    s = sim_cameras.read_settings(lambda name, default: default)
    assert (s.rate_hz, s.width, s.height, s.quality, s.nice) == (15.0, 640, 480, 80, 10)
    assert s.cameras == ['room_camera', 'left_hand_camera', 'right_hand_camera']
    for name, value, words in (('rate', 0, '~rate'), ('rate', 500, 'at most'),
                               ('width', 10, '~width'), ('height', True, '~height'),
                               ('quality', 0, '~quality'), ('cameras', [], '~cameras'),
                               ('cameras', ['a', 'a'], '~cameras'),
                               ('world_file', 3, '~world_file'), ('nice', -5, '~nice'),
                               ('nice', 2.5, '~nice')):
        with pytest.raises(ValueError, match=words):
            sim_cameras.read_settings(lambda n, d, name=name, value=value:
                                      value if n == name else d)


@pytest.mark.parametrize('names, positions, words', [
    (['a', 'b'], [0.0], '2 joint names but 1 positions'),
    (['a'], [float('nan')], 'not a finite number'),
    (['a'], ['x'], 'not a finite number'),
    ([3], [0.0], 'not a finite number'),
])
def test_garbage_joint_states_are_refused_by_name(names, positions, words):
    with pytest.raises(ValueError, match=words):
        sim_cameras.check_positions(names, positions)


def test_the_renderer_projection_puts_pixel_centres_where_ros_does():
    k = [[500.0, 0.0, 300.2], [0.0, 480.0, 210.7], [0.0, 0.0, 1.0]]
    projection = gl_renderer.projection(k, WIDTH, HEIGHT)
    for x, y, z in ((0.1, -0.2, 1.5), (-0.3, 0.25, 2.0), (0.0, 0.0, 0.7)):
        eye = gl_renderer.OPTICAL_TO_EYE @ np.array([x, y, z, 1.0])
        clip = projection @ eye
        ndc = clip[:3] / clip[3]
        column = (ndc[0] + 1.0) * WIDTH / 2.0 - 0.5          # window x to pixel centre
        row = HEIGHT - (ndc[1] + 1.0) * HEIGHT / 2.0 - 0.5    # rows read back top first
        assert column == pytest.approx(500.0 * x / z + 300.2)
        assert row == pytest.approx(480.0 * y / z + 210.7)
        assert -1.0 < ndc[2] < 1.0


@pytest.mark.parametrize('mesh, volume', [
    (meshes.box((0.2, 0.3, 0.4), (1, 1, 1)), 0.024),
    (meshes.cylinder(0.1, 0.5, (1, 1, 1)), math.pi * 0.01 * 0.5),
    (meshes.sphere(0.2, (1, 1, 1)), 4.0 / 3.0 * math.pi * 0.008),
])
def test_meshes_are_closed_and_wound_outwards(mesh, volume):
    triangles = mesh.vertices.reshape(-1, 3, 3).astype(np.float64)
    normals = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    outwards = np.einsum('ij,ij->i', normals, mesh.normals.reshape(-1, 3, 3)[:, 0])
    assert np.all(outwards > 0)  # counter-clockwise seen from outside: back faces cull inside
    enclosed = np.einsum('ij,ij->i', triangles[:, 0], np.cross(triangles[:, 1],
                                                                triangles[:, 2])).sum() / 6.0
    assert enclosed == pytest.approx(volume, rel=0.05)  # no face missing


def test_a_task_object_is_drawn_where_it_is_and_moves_with_set_objects():
    tip = DESCRIPTION.transform(neutral(), 'right_gripper')[:3, 3]
    core = sim_cameras.SimCameras(invisible_robot(), scene.World([], None, WORLD.cameras),
                                  WIDTH, HEIGHT, ['room_camera'])
    core.set_positions(neutral())
    empty = core.render('room_camera')[0].copy()
    ball = marker_world(tip, 0.02).shapes[0]
    core.set_objects([ball])
    (u, v), count = red_centroid(core.render('room_camera')[0])
    assert count >= 20
    core.set_objects([ball._replace(xyz=tuple(tip + (0.0, 0.0, 0.2)))])  # 20 cm up: higher
    (u_up, v_up), _ = red_centroid(core.render('room_camera')[0])
    assert v_up < v - 10, (v, v_up)
    core.set_objects([])
    assert np.array_equal(core.render('room_camera')[0], empty)
    core.close()


def test_objects_alone_are_no_pose_to_draw():
    core = sim_cameras.SimCameras(URDF, WORLD, WIDTH, HEIGHT, ['room_camera'])
    core.set_objects([marker_world((1.0, 0.0, 0.0), 0.05).shapes[0]])
    assert not core.posed   # the node draws nothing before Baxter's joints came
    core.set_positions(neutral())
    assert core.posed
    core.close()
