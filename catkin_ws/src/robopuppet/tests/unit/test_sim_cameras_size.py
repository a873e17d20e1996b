"""The simulated cameras at a size set per camera (what /cameras/open does): the image and
camera_info take the new size, the view stays the same (focal length scaled with the width),
other cameras keep theirs, and every size's renderer shows the newest pose.

These tests render for real through EGL on Mesa (what the node does), headless.
"""
import cv2
import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.cameras import scene, sim_cameras

WIDTH, HEIGHT = 640, 480
with open(bd.URDF_PATH) as _urdf:
    URDF = _urdf.read()
WORLD = scene.load_world(bd.URDF_PATH.replace('urdf/baxter.urdf', 'config/world.yaml'))
CAMERAS = ['room_camera', 'right_hand_camera']
REACH = {'right_s0': 0.3, 'right_s1': -0.2, 'right_e1': 1.0, 'right_w1': 0.8}


def neutral():
    positions = {}
    for side in ('left', 'right'):
        positions.update(bd.neutral_pose(side))
    return positions


@pytest.fixture
def core():
    cameras = sim_cameras.SimCameras(URDF, WORLD, WIDTH, HEIGHT, CAMERAS)
    cameras.set_positions(neutral())
    yield cameras
    cameras.close()


def test_a_new_size_gives_images_and_camera_info_of_that_size(core):
    core.set_size('right_hand_camera', 320, 200)
    image, _ = core.render('right_hand_camera')
    assert image.shape == (200, 320, 3)
    info = sim_cameras.camera_info_fields(core.cameras['right_hand_camera'],
                                          *core.sizes['right_hand_camera'])
    assert (info['width'], info['height']) == (320, 200)
    fx, cx, fy, cy = info['K'][0], info['K'][2], info['K'][4], info['K'][5]
    assert (fx, fy) == (pytest.approx(201.5), pytest.approx(201.5))
    assert (cx, cy) == (159.5, 99.5)
    raw, packed, _ = core.encode('right_hand_camera', True, True, 80)
    assert len(raw) == 320 * 200 * 3
    assert cv2.imdecode(np.frombuffer(packed, np.uint8), cv2.IMREAD_COLOR).shape == (200, 320, 3)
    # the other camera keeps the node's size
    assert core.render('room_camera')[0].shape == (HEIGHT, WIDTH, 3)


def test_the_view_is_the_same_at_every_size(core):
    core.set_size('room_camera', 1280, 800)
    large = core.render('room_camera')[0]
    core.set_size('room_camera', 640, 400)
    small = core.render('room_camera')[0]
    halved = cv2.resize(large, (640, 400), interpolation=cv2.INTER_AREA)
    # The same scene, pixel for pixel within the edges' antialiasing of the halving.
    differs = np.abs(halved.astype(int) - small.astype(int)).max(axis=2) > 40
    assert differs.mean() < 0.02, differs.mean()


def test_each_sizes_renderer_shows_the_newest_pose(core):
    core.set_size('right_hand_camera', 640, 400)
    core.render('right_hand_camera')
    core.set_size('right_hand_camera', 960, 600)
    core.render('right_hand_camera')
    moved = dict(neutral(), **REACH)
    core.set_positions(moved)
    core.set_size('right_hand_camera', 640, 400)  # back to the first size's renderer
    image = core.render('right_hand_camera')[0]
    fresh = sim_cameras.SimCameras(URDF, WORLD, 640, 400, ['right_hand_camera'])
    fresh.set_positions(moved)
    expected = fresh.render('right_hand_camera')[0]
    fresh.close()
    assert np.array_equal(image, expected)
    room = core.render('room_camera')[0]   # 640x480: its renderer gets the pose too
    other = sim_cameras.SimCameras(URDF, WORLD, WIDTH, HEIGHT, ['room_camera'])
    other.set_positions(moved)
    assert np.array_equal(room, other.render('room_camera')[0])
    other.close()
