"""Unit tests of study.pad_axes: the gamepad's and the SpaceMouse's axes as a twist."""
import pytest
from evdev import ecodes as e

from robopuppet.study import input_events, pad_axes as pa
from robopuppet.study.input_events import InputEvent


def ev(kind, code, value):
    return InputEvent(0.0, kind, code, value)


def twist_after(device, *events):
    for event in events:
        device.on_event(ev(*event))
    return device.velocity()


@pytest.mark.parametrize('side', ['L', 'R'])
def test_gamepad_stick_up_is_plus_x_and_right_is_minus_y_at_full_speed(side):
    x, y = pa.STICK[side]
    assert twist_after(pa.Gamepad(side, 0.15), (e.EV_ABS, y, -32768)) == pytest.approx(
        [0.15, 0, 0, 0, 0, 0])
    assert twist_after(pa.Gamepad(side, 0.15), (e.EV_ABS, x, 32767)) == pytest.approx(
        [0, -0.15, 0, 0, 0, 0])
    assert twist_after(pa.Gamepad(side, 0.15), (e.EV_ABS, y, 32767)) == pytest.approx(
        [-0.15, 0, 0, 0, 0, 0])


def test_gamepad_dead_zone_of_ten_percent_and_speed_growing_beyond_it():
    pad = pa.Gamepad('R', 0.1)
    assert twist_after(pad, (e.EV_ABS, e.ABS_RY, int(-0.09 * 32768))) == [0.0] * 6
    half = twist_after(pad, (e.EV_ABS, e.ABS_RY, int(-0.55 * 32768)))[0]
    assert half == pytest.approx(0.05, abs=2e-3)
    assert twist_after(pad, (e.EV_ABS, e.ABS_RY, 0))[0] == 0.0   # back in the middle: stops


def test_gamepad_shoulder_button_raises_and_trigger_lowers_in_proportion():
    pad = pa.Gamepad('R', 0.2)
    assert twist_after(pad, (e.EV_KEY, e.BTN_TR, 1))[2] == pytest.approx(0.2)
    assert twist_after(pad, (e.EV_KEY, e.BTN_TR, 0))[2] == 0.0
    assert twist_after(pad, (e.EV_ABS, e.ABS_RZ, 255))[2] == pytest.approx(-0.2)
    assert twist_after(pad, (e.EV_ABS, e.ABS_RZ, 10))[2] == 0.0   # within the dead zone
    # the left side's trigger and button do not move the right arm
    assert twist_after(pad, (e.EV_ABS, e.ABS_Z, 255), (e.EV_KEY, e.BTN_TL, 1)) == [0.0] * 6


def test_gamepad_uses_the_devices_axis_ranges():
    pad = pa.Gamepad('L', 0.1, ranges={e.ABS_X: (0, 255), e.ABS_Y: (0, 255), e.ABS_Z: (0, 1023)})
    assert twist_after(pad, (e.EV_ABS, e.ABS_Y, 0))[0] == pytest.approx(0.1)
    assert twist_after(pad, (e.EV_ABS, e.ABS_Y, 128)) == [0.0] * 6
    assert twist_after(pad, (e.EV_ABS, e.ABS_Z, 1023))[2] == pytest.approx(-0.1)


@pytest.mark.parametrize('side', ['L', 'R'])
def test_gamepad_follow_button_while_down_and_grip_toggles(side):
    pad = pa.Gamepad(side)
    pad.on_event(ev(e.EV_KEY, pa.FOLLOW[side], 1))
    assert pad.follow
    pad.on_event(ev(e.EV_KEY, pa.FOLLOW[side], 0))
    assert not pad.follow
    pad.on_event(ev(e.EV_KEY, pa.GRIP[side], 1))
    pad.on_event(ev(e.EV_KEY, pa.GRIP[side], 0))
    assert pad.closed
    pad.on_event(ev(e.EV_KEY, pa.GRIP[side], 1))
    assert not pad.closed


# device axis (x right, y toward the user, z down; turns right-handed) -> the twist a full
# positive deflection gives for side R (Baxter: x forward, y left, z up)
SPACE_R = {e.REL_X: [0, -1, 0, 0, 0, 0], e.REL_Y: [-1, 0, 0, 0, 0, 0],
           e.REL_Z: [0, 0, -1, 0, 0, 0], e.REL_RX: [0, 0, 0, 0, -1, 0],
           e.REL_RY: [0, 0, 0, -1, 0, 0], e.REL_RZ: [0, 0, 0, 0, 0, -1]}


@pytest.mark.parametrize('kind', [e.EV_REL, e.EV_ABS])
@pytest.mark.parametrize('axis', sorted(SPACE_R))
def test_spacemouse_each_axis_full_deflection(axis, kind):
    mouse = pa.SpaceMouse('R', max_speed=0.15, max_turn=0.6)
    want = [v * s for v, s in zip(SPACE_R[axis], [0.15] * 3 + [0.6] * 3)]
    assert twist_after(mouse, (kind, axis, 350)) == pytest.approx(want)
    assert twist_after(mouse, (kind, axis, 20)) == [0.0] * 6   # dead zone (35)


@pytest.mark.parametrize('axis', sorted(SPACE_R))
def test_spacemouse_side_l_is_mirrored_in_y_roll_and_yaw(axis):
    right = twist_after(pa.SpaceMouse('R'), (e.EV_REL, axis, -300))
    left = twist_after(pa.SpaceMouse('L'), (e.EV_REL, axis, -300))
    assert left == pytest.approx([r * m for r, m in zip(right, (1, -1, 1, -1, 1, -1))])
    assert any(left)


def test_spacemouse_buttons_follow_and_grip():
    mouse = pa.SpaceMouse('R')
    mouse.on_event(ev(e.EV_KEY, e.BTN_0, 1))
    mouse.on_event(ev(e.EV_KEY, e.BTN_1, 1))
    assert mouse.follow and mouse.closed
    mouse.on_event(ev(e.EV_KEY, e.BTN_0, 0))
    assert not mouse.follow and mouse.closed


def test_dead_zone_is_continuous_and_bounded():
    assert pa.dead_zone(0.1) == 0.0 and pa.dead_zone(0.1001) == pytest.approx(0.0, abs=1e-3)
    assert pa.dead_zone(1.5) == 1.0 and pa.dead_zone(-1.0) == -1.0


@pytest.mark.parametrize('spacenavd, want', [
    ((0, 0, 0, 350), [0.15, 0, 0, 0, 0, 0]),    # the cap pushed away: forward
    ((0, 0, 350, 0), [0, 0, 0.15, 0, 0, 0]),    # lifted: up
    ((0, 350, 0, 0), [0, -0.15, 0, 0, 0, 0]),   # pushed right: to Baxter's right
    ((0, 0, 0, 0, 0, 350), [0, 0, 0, 0, 0, 0.6])])   # turned left (spacenavd's ry): yaw left
def test_spacenavd_events_move_the_gripper_the_way_the_cap_moves(spacenavd, want):
    data = input_events.SPACENAV.pack(*(list(spacenavd) + [0] * (8 - len(spacenavd))))
    mouse = pa.SpaceMouse('R')
    for event in input_events.decode_spacenav(data, 0.0)[0]:
        mouse.on_event(event)
    assert mouse.velocity() == pytest.approx(want)
