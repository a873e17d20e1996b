"""robopuppet.cameras.webcam: the camera node's parameters, devices, retries and CameraInfo."""
import math

import cv2
import pytest

from robopuppet import interface
from robopuppet.cameras import webcam


def settings(**given):
    return webcam.read_settings(lambda name, default: given.get(name, default))


def test_the_defaults_make_a_640x480_room_camera_on_video0():
    s = settings()
    assert s == webcam.Settings(interface.ROOM_CAMERA, '/dev/video0', 640, 480, 15.0, 80, 60.0,
                                'room_camera_optical_frame')


def test_given_parameters_are_used():
    s = settings(name='left_webcam', device='2', width=320, height=240.0, rate=30, quality=95,
                 hfov_deg=90, frame_id='webcam')
    assert s == webcam.Settings('left_webcam', 2, 320, 240, 30.0, 95, 90.0, 'webcam')


@pytest.mark.parametrize('name, value', [
    ('name', 'room camera'), ('name', '/cameras/x'), ('name', ''), ('name', 3),
    ('device', ''), ('device', None), ('device', True), ('device', 1.5),
    ('width', 0), ('width', 8), ('width', 5000), ('width', 640.5), ('width', '640'),
    ('height', True), ('rate', 0), ('rate', -1), ('rate', 500), ('rate', 'fast'),
    ('quality', 0), ('quality', 101), ('hfov_deg', 180), ('hfov_deg', 0), ('frame_id', 5),
])
def test_a_bad_parameter_is_refused_with_its_name(name, value):
    with pytest.raises(ValueError, match='~' + name):
        settings(**{name: value})


@pytest.mark.parametrize('value, expected', [
    (0, 0), ('1', 1), (' 3 ', 3), ('/dev/video2', '/dev/video2'),
    ('/tmp/demo.avi', '/tmp/demo.avi'), ('demo.mp4', 'demo.mp4')])
def test_a_device_is_an_index_or_a_path(value, expected):
    assert webcam.parse_device(value) == expected


def test_devices_and_files_go_through_their_opencv_backends():
    assert webcam.source(0) == (0, cv2.CAP_V4L2)
    assert webcam.source('/dev/video1') == ('/dev/video1', cv2.CAP_V4L2)
    assert webcam.source('/tmp/demo.avi') == ('/tmp/demo.avi', cv2.CAP_FFMPEG)
    assert webcam.is_file('/tmp/demo.avi') and not webcam.is_file('/dev/video0')
    assert not webcam.is_file(0)


def test_missing_names_the_kind_of_thing_that_is_missing():
    present = {'/dev/video0', '/tmp/demo.avi'}.__contains__
    assert webcam.missing(0, present) == ''
    assert webcam.missing('/tmp/demo.avi', present) == ''
    assert webcam.missing(1, present) == 'no such device'
    assert webcam.missing('/dev/video1', present) == 'no such device'
    assert webcam.missing('/tmp/other.avi', present) == 'no such file'


def test_describe_names_the_device_path_of_an_index():
    assert webcam.describe(2) == 'V4L2 device 2 (/dev/video2)'
    assert webcam.describe('/dev/video0') == '/dev/video0'


def test_retries_back_off_to_the_maximum_and_reset_on_success():
    retry = webcam.Retry(first_s=0.5, max_s=4.0)
    assert retry.due(0.0)
    delays = []
    now = 0.0
    for _ in range(6):
        retry.failed(now, 'no such device')
        delays.append(retry.delay_s)
        assert not retry.due(now + retry.delay_s - 0.01)
        now += retry.delay_s
        assert retry.due(now)
    assert delays == [0.5, 1.0, 2.0, 4.0, 4.0, 4.0]
    assert retry.succeeded() == 6
    assert retry.failures == 0 and retry.reason == '' and retry.due(now)
    retry.failed(now, 'no such device')
    assert retry.delay_s == 0.5


def test_a_failure_is_logged_first_on_a_new_reason_and_then_every_so_often():
    retry = webcam.Retry(first_s=0.5, max_s=2.0, log_every_s=30.0)
    lines = [(t, retry.failed(t, 'no such device')) for t in (0.0, 0.5, 1.5, 3.5, 20.0)]
    assert lines[0][1] == 'no such device; retrying (attempt 1, next in 0.5 s)'
    assert [line for _, line in lines[1:]] == [None] * 4
    assert retry.failed(30.0, 'no such device') is not None  # 30 s after the last line
    assert retry.failed(31.0, 'no such device') is None
    assert 'delivers no frames' in retry.failed(32.0, 'the device delivers no frames')
    retry.succeeded()
    assert retry.failed(33.0, 'the device delivers no frames') is not None  # lost again


def test_retry_refuses_an_impossible_backoff():
    with pytest.raises(ValueError):
        webcam.Retry(first_s=2.0, max_s=1.0)


def test_the_camera_model_projects_the_field_of_view_edges_to_the_image_edges():
    model = webcam.camera_model(640, 480, 90.0)
    fx, cx, fy, cy = model.K[0], model.K[2], model.K[4], model.K[5]
    assert (fx, fy, cx, cy) == pytest.approx((320.0, 320.0, 320.0, 240.0))
    edge = math.tan(math.radians(45.0))  # a ray at half the field of view
    assert fx * edge + cx == pytest.approx(640.0)
    assert model.P == [fx, 0.0, cx, 0.0, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0]
    assert model.R == [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    assert model.D == [0.0] * 5 and (model.width, model.height) == (640, 480)


def test_a_narrower_lens_has_a_longer_focal_length():
    assert webcam.camera_model(640, 480, 40.0).K[0] > webcam.camera_model(640, 480, 60.0).K[0]
    with pytest.raises(ValueError):
        webcam.camera_model(640, 480, 180.0)
