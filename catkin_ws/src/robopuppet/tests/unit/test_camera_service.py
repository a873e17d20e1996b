"""Baxter's camera service as the stand-in answers it: two cameras with power, the third refused
(not another closed), Baxter's modes and rates only, close hands the power on, room cameras
outside the rule, and each camera's frames paced at its own rate."""
import errno
import math

import pytest

from robopuppet.cameras import camera_service as cs

ALL = ['room_camera', 'left_hand_camera', 'right_hand_camera', 'head_camera']
DEFAULT = ['room_camera', 'left_hand_camera', 'right_hand_camera']
START = cs.Mode(640, 480, 15.0)


def service(names=ALL):
    return cs.CameraService(names, START)


def test_the_hand_cameras_have_power_and_stream_at_start_and_the_head_camera_not():
    s = service()
    assert s.cameras() == ['left_hand_camera', 'right_hand_camera']
    assert s.streaming() == {'room_camera': START, 'left_hand_camera': START,
                             'right_hand_camera': START}


@pytest.mark.parametrize('width, height', cs.BAXTER_MODES)
def test_each_of_baxters_modes_opens_at_that_size(width, height):
    s = service()
    answer = s.open('right_hand_camera', width, height, 20.0)
    assert answer.err == cs.OK and 'right_hand_camera' in answer.line
    assert s.streaming()['right_hand_camera'] == cs.Mode(width, height, 20.0)


@pytest.mark.parametrize('width, height', [(640, 480), (800, 800), (1280, 720), (400, 640),
                                           (0, 0), (-640, -400)])
def test_a_size_baxter_has_not_is_refused_and_changes_nothing(width, height):
    s = service()
    answer = s.open('left_hand_camera', width, height, 20.0)
    assert answer.err == errno.EINVAL
    assert '%sx%s' % (width, height) in answer.line and '640x400' in answer.line
    assert s.streaming()['left_hand_camera'] == START


@pytest.mark.parametrize('fps', [0.0, -5.0, 30.5, 100.0, math.nan, math.inf])
def test_a_rate_out_of_range_is_refused(fps):
    s = service()
    answer = s.open('left_hand_camera', 640, 400, fps)
    assert answer.err == errno.EINVAL and 'frames/s' in answer.line
    assert s.streaming()['left_hand_camera'] == START


@pytest.mark.parametrize('fps', [0.5, 20, 25.0, cs.MAX_FPS])
def test_a_rate_in_range_is_taken(fps):
    s = service()
    assert s.open('left_hand_camera', 320, 200, fps).err == cs.OK
    assert s.streaming()['left_hand_camera'].fps == fps


def test_a_third_camera_is_refused_and_no_other_is_closed():
    s = service()
    answer = s.open('head_camera', 640, 400, 20.0)
    assert answer.err == errno.ENODEV
    assert 'no power' in answer.line and 'close one' in answer.line
    assert 'head_camera' not in s.streaming() and 'head_camera' not in s.cameras()
    assert set(s.streaming()) == set(DEFAULT)


def test_close_stops_a_camera_and_hands_its_power_to_the_third():
    s = service()
    answer = s.close('left_hand_camera')
    assert answer.err == cs.OK and 'head_camera' in answer.line
    assert 'left_hand_camera' not in s.streaming()
    assert s.cameras() == ['right_hand_camera', 'head_camera']
    assert s.open('head_camera', 1280, 800, 20.0).err == cs.OK
    # The closed camera lost its power: it comes back only once another is closed.
    assert s.open('left_hand_camera', 640, 400, 20.0).err == errno.ENODEV
    assert s.close('right_hand_camera').err == cs.OK
    assert s.cameras() == ['left_hand_camera', 'head_camera']
    assert s.open('left_hand_camera', 640, 400, 20.0).err == cs.OK
    assert set(s.streaming()) == {'room_camera', 'left_hand_camera', 'head_camera'}


def test_closing_a_camera_that_does_not_stream_answers_einval():
    s = service()
    assert s.close('head_camera').err == errno.EINVAL   # no power
    assert s.close('left_hand_camera').err == cs.OK
    assert s.close('left_hand_camera').err == errno.EINVAL   # closed already
    assert s.cameras() == ['right_hand_camera', 'head_camera']


def test_without_a_third_camera_a_closed_one_keeps_its_power_and_opens_again():
    s = service(DEFAULT)
    assert s.close('right_hand_camera').err == cs.OK
    assert s.cameras() == ['left_hand_camera', 'right_hand_camera']
    assert s.open('right_hand_camera', 480, 300, 10.0).err == cs.OK
    assert s.streaming()['right_hand_camera'] == cs.Mode(480, 300, 10.0)


def test_an_open_camera_opens_again_with_new_settings():
    s = service()
    assert s.open('left_hand_camera', 960, 600, 25.0).err == cs.OK
    answer = s.open('left_hand_camera', 384, 240, 10.0)
    assert answer.err == cs.OK and 'again' in answer.line
    assert s.streaming()['left_hand_camera'] == cs.Mode(384, 240, 10.0)


@pytest.mark.parametrize('name', ['room_camera', 'nose_camera', '', 'left_hand_camera/x'])
def test_a_camera_that_is_not_baxters_is_neither_listed_nor_opened_nor_closed(name):
    s = service()
    for answer in (s.open(name, 640, 400, 20.0), s.close(name)):
        assert answer.err == errno.ENODEV and repr(name)[1:-1] in answer.line
    assert name not in s.cameras()
    assert set(s.streaming()) == set(DEFAULT)


def test_a_room_camera_streams_beside_two_of_baxters_cameras():
    s = service()
    assert s.close('left_hand_camera').err == cs.OK
    assert s.open('head_camera', 640, 400, 20.0).err == cs.OK
    assert set(s.streaming()) == {'room_camera', 'right_hand_camera', 'head_camera'}
    assert 'room_camera' not in s.cameras()


def frames(s, name, rate_hz, duration_s, start_s=100.0):
    """Return how many frames of a camera are due over duration_s of ticks at rate_hz."""
    ticks = int(round(duration_s * rate_hz))
    return sum(s.due(name, start_s + i / rate_hz) for i in range(ticks))


@pytest.mark.parametrize('fps', [5.0, 10.0, 15.0, 20.0, 25.0, 30.0])
def test_frames_come_at_each_cameras_rate(fps):
    s = service()
    assert s.open('left_hand_camera', 640, 400, fps).err == cs.OK
    assert frames(s, 'left_hand_camera', cs.MAX_FPS, 10.0) == pytest.approx(10 * fps, abs=1)
    assert frames(s, 'room_camera', cs.MAX_FPS, 10.0) == pytest.approx(10 * START.fps, abs=1)


def test_a_closed_camera_is_never_due_and_a_late_one_is_not_made_up():
    s = service()
    assert s.due('left_hand_camera', 0.0)
    assert not s.due('left_hand_camera', 0.01)
    # Nobody asked for 5 s: one frame now, then the rate again, not a burst of 75.
    assert s.due('left_hand_camera', 5.0) and not s.due('left_hand_camera', 5.01)
    assert s.close('left_hand_camera').err == cs.OK
    assert not any(s.due('left_hand_camera', 6.0 + i / 30.0) for i in range(60))
    assert not s.due('head_camera', 10.0)


def test_a_garbage_name_makes_a_short_log_line():
    s = service()
    for answer in (s.open('x' * 100000, 640, 400, 20.0), s.close('\n' * 100000)):
        assert answer.err == errno.ENODEV and len(answer.line) < 200
