"""Unit tests of study.device_core: a device's controls and Baxter's pose -> puppet outputs."""
import math

import numpy as np
import pytest
from evdev import ecodes as e

from robopuppet import interface
from robopuppet.baxter_sim.baxter_ik import rotation_error
from robopuppet.study import device_core as dc
from robopuppet.study.cartesian import CartesianArm
from robopuppet.study.input_events import InputEvent
from robopuppet.study.key_jog import KeyJog
from robopuppet.study.pad_axes import FOLLOW, SPACE_FOLLOW, Gamepad, SpaceMouse

BENT = [0.3, -0.3, 0.0, 1.6, 0.0, 0.3, 0.0]
END = interface.END_PIECE_GRIPPER


@pytest.fixture(scope='module')
def arms():
    return {'R': CartesianArm('right'), 'L': CartesianArm('left')}


def key(code, value):
    return InputEvent(0.0, e.EV_KEY, code, value)


def run(core, t0, t1, rate_hz=50.0, follow=False):
    """Step core from t0 to t1 (follow: Baxter measured where the last step's target was);
    return the last Output."""
    output = None
    for t in np.arange(t0, t1 + 1e-9, 1.0 / rate_hz):
        output = core.step(float(t))
        if follow:
            core.on_robot(output.positions)
    return output


def test_nothing_is_published_before_baxters_pose_then_the_target_is_the_measured_pose(arms):
    core = dc.DeviceCore('R', KeyJog('R'), arms['R'])
    assert core.step(0.0).positions is None
    core.on_robot(BENT)
    core.on_events([key(e.KEY_A, 1)])   # a key held while not following moves nothing
    assert run(core, 0.02, 1.0).positions == pytest.approx(BENT)
    core.on_robot([0.1] * 7)
    assert core.step(1.02).positions == pytest.approx([0.1] * 7)


def test_while_following_a_key_jogs_the_target_from_the_pose_at_the_press(arms):
    core = dc.DeviceCore('R', KeyJog('R', jog_speed=0.4), arms['R'])
    core.on_robot(BENT)
    core.step(0.0)
    core.on_teleop(True)
    lagging = np.array(BENT) + [0.0, 0.0, 0.1, 0.0, 0.0, 0.0, -0.1]
    core.on_robot(lagging)         # Baxter lags: the target moves on from itself, not from here
    core.on_events([key(e.KEY_D, 1), key(e.KEY_M, 1)])   # joint 2 plus, joint 6 minus
    out = run(core, 0.02, 0.5)
    want = list(BENT)
    want[2] += 0.2
    want[6] -= 0.2
    assert out.positions == pytest.approx(want, abs=1e-6)
    core.on_events([key(e.KEY_D, 0), key(e.KEY_M, 0)])
    assert run(core, 0.52, 1.0).positions == pytest.approx(want, abs=1e-6)
    core.on_teleop(False)          # not following any more: back to Baxter's pose
    assert core.step(1.02).positions == pytest.approx(lagging)


def test_a_target_leads_a_held_arm_by_at_most_the_lead_and_turning_back_acts_at_once(arms):
    core = dc.DeviceCore('R', KeyJog('R', jog_speed=0.4), arms['R'])
    core.on_robot(BENT)
    core.step(0.0)
    core.on_teleop(True)
    core.on_events([key(e.KEY_D, 1)])        # joint 2 plus for 3 s: Baxter held, not moving
    out = run(core, 0.02, 3.0)
    assert out.positions[2] == pytest.approx(BENT[2] + dc.MAX_LEAD_RAD)
    core.on_events([key(e.KEY_D, 0), key(e.KEY_C, 1)])   # turn back: joint 2 minus
    out = run(core, 3.02, 3.5)
    assert out.positions[2] == pytest.approx(BENT[2] + dc.MAX_LEAD_RAD - 0.2, abs=1e-6)


def test_the_target_stays_within_the_joint_limits(arms):
    core = dc.DeviceCore('R', KeyJog('R', jog_speed=2.0), arms['R'])
    core.on_robot(BENT)
    core.on_teleop(True)
    core.on_events([key(e.KEY_A, 1), key(e.KEY_X, 1)])   # joint 0 up, joint 1 down
    out = run(core, 0.0, 5.0, follow=True)
    assert out.positions[0] == pytest.approx(arms['R'].upper[0])
    assert out.positions[1] == pytest.approx(arms['R'].lower[1])


def test_a_gamepad_moves_the_tip_forward_at_its_speed(arms):
    core = dc.DeviceCore('R', Gamepad('R', max_speed=0.1), arms['R'])
    core.on_robot(BENT)
    core.on_teleop(True)
    core.step(0.0)
    core.on_events([InputEvent(0.0, e.EV_ABS, e.ABS_RY, -32768)])   # stick up: +x
    out = run(core, 0.02, 0.5)
    moved = arms['R'].tip(out.positions)[0] - arms['R'].tip(BENT)[0]
    assert moved == pytest.approx([0.05, 0.0, 0.0], abs=0.003)


def test_a_gamepad_keeps_the_grippers_orientation_over_a_long_motion(arms):
    core = dc.DeviceCore('R', Gamepad('R', max_speed=0.1), arms['R'])
    core.on_robot(BENT)
    core.on_teleop(True)
    core.step(0.0)
    rotation = arms['R'].tip(BENT)[1]
    for t, (x, y) in ((0.0, (0, -32768)), (1.0, (32767, 0)), (2.0, (0, 32767))):
        core.on_events([InputEvent(t, e.EV_ABS, e.ABS_RX, x), InputEvent(t, e.EV_ABS, e.ABS_RY, y)])
        out = run(core, t + 0.02, t + 1.0, follow=True)   # Baxter follows
    assert np.linalg.norm(rotation_error(rotation, arms['R'].tip(out.positions)[1])) < 1e-3
    moved = arms['R'].tip(out.positions)[0] - arms['R'].tip(BENT)[0]
    assert moved == pytest.approx([0.0, -0.1, 0.0], abs=0.005)


def test_a_long_gap_between_steps_moves_no_further_than_max_step(arms):
    core = dc.DeviceCore('R', KeyJog('R', jog_speed=1.0), arms['R'])
    core.on_robot(BENT)
    core.on_teleop(True)
    core.step(0.0)
    core.on_events([key(e.KEY_A, 1)])
    assert core.step(10.0).positions[0] == pytest.approx(BENT[0] + dc.MAX_STEP_S)


def test_nan_is_never_published(arms):
    class Broken(KeyJog):
        def velocity(self):
            return [math.nan, math.inf] + [0.0] * 5
    core = dc.DeviceCore('R', Broken('R'), arms['R'])
    core.on_robot([math.nan] * 7)
    assert core.step(0.0).positions is None
    core.on_robot(BENT)
    core.on_robot([0.0, math.nan, 0, 0, 0, 0, 0])   # ignored: the last finite pose stays
    assert core.step(0.02).positions == pytest.approx(BENT)
    core.on_teleop(True)
    for t in (0.04, 0.06, 0.08):
        assert all(math.isfinite(p) for p in core.step(t).positions)
    assert not core.set_target([math.nan] * 7)
    assert all(math.isfinite(p) for p in core.step(0.1).positions)


@pytest.mark.parametrize('side, button', [('L', interface.BUTTON_LEFT),
                                          ('R', interface.BUTTON_RIGHT)])
def test_follow_control_is_the_sides_button_and_grip_the_end_piece(arms, side, button):
    jog = KeyJog(side)
    core = dc.DeviceCore(side, jog, arms[side])
    core.on_robot(BENT)
    out = core.step(0.0)
    assert out.button == 0 and out.grippers[END] == dc.RELEASED == 1.0
    assert out.grippers[:END] == (0.0,) * END
    core.on_events([key({'L': e.KEY_F2, 'R': e.KEY_F3}[side], 1),
                    key({'L': e.KEY_TAB, 'R': e.KEY_SPACE}[side], 1)])
    out = core.step(0.02)
    assert out.button == button and out.grippers[END] == dc.PRESSED == 0.0
    core.on_events([key({'L': e.KEY_F2, 'R': e.KEY_F3}[side], 0)])
    assert core.step(0.04).button == 0


def test_a_marker_press_holds_the_button_briefly_and_its_target_counts_only_while_following(
        arms):
    core = dc.DeviceCore('R', None, arms['R'])
    core.on_robot(BENT)
    core.press_follow(1.0)
    assert core.step(1.0).button == interface.BUTTON_RIGHT
    assert core.step(1.0 + dc.PRESS_S + 0.01).button == 0
    goal = [0.2, -0.2, 0.1, 1.5, 0.0, 0.4, 0.1]
    assert not core.set_target(goal)               # not following: refused
    assert core.step(1.3).positions == pytest.approx(BENT)
    core.on_teleop(True)
    assert core.set_target(goal)
    assert core.step(1.32).positions == pytest.approx(goal)
    core.set_closed(True)
    assert core.step(1.34).grippers[END] == dc.PRESSED


@pytest.mark.parametrize('mine, other, passed_on', [
    (False, False, True),    # nothing follows: the press starts both
    (True, True, True),      # both follow: it stops both
    (True, False, True),     # split: it stops the one that follows ...
    (False, True, False)])   # ... and is not passed on where the arm does not follow
def test_a_shared_follow_press_brings_both_arms_to_one_state(arms, mine, other, passed_on):
    core = dc.DeviceCore('L', SpaceMouse('L'), arms['L'])
    core.on_robot(BENT)
    core.on_teleop(mine)
    core.on_other_teleop(other)
    core.on_events([key(SPACE_FOLLOW, 1)])
    assert core.step(0.0).button == (interface.BUTTON_LEFT if passed_on else 0)
    core.on_other_teleop(not other)    # the other arm changes while the button is down
    assert core.step(0.02).button == (interface.BUTTON_LEFT if passed_on else 0)
    core.on_events([key(SPACE_FOLLOW, 0)])
    assert core.step(0.04).button == 0


def test_a_gamepad_follow_button_is_its_sides_own(arms):
    core = dc.DeviceCore('L', Gamepad('L'), arms['L'])
    core.on_robot(BENT)
    core.on_other_teleop(True)          # the other arm follows: this side's press still counts
    core.on_events([key(FOLLOW['L'], 1)])
    assert core.step(0.0).button == interface.BUTTON_LEFT
