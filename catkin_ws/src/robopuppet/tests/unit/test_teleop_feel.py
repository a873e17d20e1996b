"""Feel mode and the opmode others set: button 1's cycle, the feel setpoints (Baxter's pose of the
arm the puppet drives, mapped back, once per puppet sample), feel -> limp on a fault, without
Baxter or without a fresh Baxter pose, and the adoption of <ns>/opmode."""
import math

import pytest

from robopuppet.arm import baxter_upkeep
from robopuppet.arm.opmode import SetOpmode, SetSetpoints
from robopuppet.interface import (BUTTON_LEFT, BUTTON_OPMODE, BUTTON_RIGHT, FAULT, FEEL,
                                  FOLLOWING, HOLD, LIMP, NO_ROBOT, READY)
from test_teleop import NEUTRAL, STATE_TIMEOUT_S, Rig

LEFT = [0.2, -0.3, 0.4, 0.9, -0.5, 0.6, 0.7]      # Baxter's left arm (rad), within its limits
RIGHT = [-0.1, 0.2, -0.3, 1.1, 0.4, -0.5, 0.8]    # ... its right arm
POSE = {'left': LEFT, 'right': RIGHT}


def mirrored(angles):
    """Written out independently of joint_motion.mirror: joints 0, 2, 4, 6 negated."""
    return [-angles[0], angles[1], -angles[2], angles[3], -angles[4], angles[5], -angles[6]]


def run(rig, seconds, sample_every=10, pose=POSE, feed=True):
    """Step at 100 Hz with Baxter reporting `pose` every step and a puppet sample every
    sample_every steps (none when feed is False); return (all actions, samples fed)."""
    actions, samples = [], 0
    for k in range(int(round(seconds / 0.01))):
        rig.t += 0.01
        rig.robot(pose=pose)
        if feed and k % sample_every == 0:
            rig.feed()
            samples += 1
        actions += rig.tp.step(rig.t).actions
    return actions, samples


def feeling(side='R', follow=()):
    """Return a Rig of puppet `side` in feel, following with the buttons in `follow`."""
    rig = Rig(side)
    rig.robot(pose=POSE)
    rig.step()
    assert rig.tp.state == READY
    for button in follow:
        rig.press(button)
    rig.press(BUTTON_OPMODE)
    assert rig.tp.opmode == HOLD
    rig.robot(pose=POSE)
    rig.press(BUTTON_OPMODE)
    assert rig.tp.opmode == FEEL
    return rig


def setpoints(actions):
    return [a.angles for a in actions if isinstance(a, SetSetpoints)]


def test_entering_feel_sends_the_feel_pose_then_the_opmode():
    rig = Rig()
    rig.robot(pose=POSE)
    rig.step()
    assert rig.press(BUTTON_OPMODE).actions == [SetSetpoints(RIGHT), SetOpmode(HOLD)]
    rig.robot(pose={'left': LEFT, 'right': NEUTRAL['right']})   # Baxter moved meanwhile
    assert rig.press(BUTTON_OPMODE).actions == [SetSetpoints(NEUTRAL['right']), SetOpmode(FEEL)]
    assert rig.press(BUTTON_OPMODE).actions == [SetOpmode(LIMP)]
    assert rig.press(BUTTON_OPMODE).actions[-1] == SetOpmode(HOLD)   # round again


def test_feel_sends_one_setpoint_set_per_puppet_sample_not_per_step():
    rig = feeling()
    actions, samples = run(rig, 2.0, sample_every=10)   # 10 Hz samples, 100 Hz steps
    assert samples == 20
    assert setpoints(actions) == [RIGHT] * samples
    assert not [a for a in actions if isinstance(a, SetOpmode)]
    actions, samples = run(rig, 1.0, sample_every=4)    # 25 Hz
    assert len(setpoints(actions)) == samples == 25


def test_the_feel_pose_follows_baxter_as_it_moves():
    rig = feeling()
    moved = {'left': LEFT, 'right': [a + 0.05 for a in RIGHT]}
    actions, _ = run(rig, 0.3, pose=moved)
    assert setpoints(actions)[-1] == pytest.approx(moved['right'])


@pytest.mark.parametrize('side, follow, expected', [
    ('R', (BUTTON_RIGHT,), RIGHT),             # own side as is
    ('R', (BUTTON_LEFT,), mirrored(LEFT)),     # the other side mirrored back
    ('L', (BUTTON_RIGHT,), mirrored(RIGHT)),
    ('L', (BUTTON_LEFT,), LEFT),
    ('R', (), RIGHT),                          # neither follows: its own side
    ('L', (BUTTON_LEFT, BUTTON_RIGHT), LEFT),  # both follow: its own side
])
def test_feel_setpoints_are_the_driven_arms_pose_mapped_back(side, follow, expected):
    rig = feeling(side, follow)
    actions, _ = run(rig, 0.5)
    assert setpoints(actions) and all(s == pytest.approx(expected) for s in setpoints(actions))


def test_entering_feel_while_following_the_other_arm_sends_it_mirrored():
    rig = Rig('R')
    rig.robot(pose=POSE)
    rig.step()
    rig.press(BUTTON_LEFT)
    assert rig.tp.state == FOLLOWING
    rig.press(BUTTON_OPMODE)
    rig.robot(pose=POSE)
    assert rig.press(BUTTON_OPMODE).actions == [SetSetpoints(mirrored(LEFT)), SetOpmode(FEEL)]


def test_puppet_silence_in_feel_lets_the_puppet_go_limp_and_stops_the_setpoints():
    rig = feeling(follow=(BUTTON_RIGHT,))
    run(rig, 0.5)
    actions, _ = run(rig, STATE_TIMEOUT_S + 0.2, feed=False)
    assert rig.tp.state == FAULT and rig.tp.opmode == LIMP
    assert actions == [SetOpmode(LIMP)]
    assert 'no joint states from the puppet' in rig.tp.detail
    assert 'feel ended (fault): the puppet goes limp' in rig.tp.detail
    actions, _ = run(rig, 0.5, feed=False)
    assert actions == []


def test_baxter_absent_in_feel_lets_the_puppet_go_limp():
    rig = feeling()
    run(rig, 0.3)
    rig.robot(enabled=False)
    assert rig.step().actions == [SetOpmode(LIMP)]
    assert rig.tp.state == NO_ROBOT and rig.tp.opmode == LIMP
    assert 'feel ended (no_robot)' in rig.tp.detail


def test_a_stale_baxter_pose_in_feel_lets_the_puppet_go_limp():
    rig = feeling()
    # Baxter goes on reporting only its left arm: the right arm's pose ages.
    actions, _ = run(rig, baxter_upkeep.ROBOT_TIMEOUT_S + 0.2, pose={'left': LEFT})
    assert actions[-1] == SetOpmode(LIMP) and actions.count(SetOpmode(LIMP)) == 1
    assert all(s == RIGHT for s in setpoints(actions))
    assert rig.tp.state == READY and rig.tp.opmode == LIMP
    assert "feel ended, the puppet goes limp: Baxter's right arm pose is" in rig.tp.detail


def test_nan_in_baxters_pose_never_becomes_a_feel_setpoint():
    rig = feeling()
    bad = {'left': LEFT, 'right': RIGHT[:3] + [math.nan] + RIGHT[4:]}
    actions, _ = run(rig, 0.5, pose=bad)
    assert setpoints(actions) and all(s == RIGHT for s in setpoints(actions))  # the last good
    actions, _ = run(rig, baxter_upkeep.ROBOT_TIMEOUT_S, pose=bad)
    assert all(math.isfinite(a) for s in setpoints(actions) for a in s)
    assert rig.tp.opmode == LIMP   # no believable pose for the timeout: feel ends


def test_feel_set_by_others_is_adopted_and_streams_at_once():
    rig = Rig()
    rig.robot(pose=POSE)
    rig.step()
    assert rig.tp.on_opmode(FEEL) == ''
    assert rig.tp.opmode == FEEL
    assert rig.step(feed=False).actions == [SetSetpoints(RIGHT)]   # no opmode echoed back
    assert rig.tp.on_opmode(FEEL) == ''                     # a repeat: nothing new
    assert rig.step(feed=False).actions == []
    assert rig.press(BUTTON_OPMODE).actions == [SetOpmode(LIMP)]   # the cycle goes on from it


def test_limp_and_hold_set_by_others_are_adopted_and_the_cycle_goes_on_from_them():
    rig = feeling()
    assert rig.tp.on_opmode(LIMP) == ''    # serial_X's feel watchdog
    actions, _ = run(rig, 0.5)
    assert actions == []                          # no setpoints in limp
    rig.tp.on_opmode(HOLD)                 # the GUI's Hold
    assert rig.step().actions == []               # the GUI sent its own setpoints
    rig.robot(pose=POSE)
    # The first press makes that hold arm_X's where the puppet is (a playback into the puppet
    # stops on this press and holds there): nothing is sent; the next press goes on to feel.
    assert rig.press(BUTTON_OPMODE).actions == []
    assert rig.tp.opmode == HOLD and 'press 1 again for feel' in rig.tp.detail
    rig.robot(pose=POSE)
    assert rig.press(BUTTON_OPMODE).actions == [SetSetpoints(RIGHT), SetOpmode(FEEL)]


def test_a_hold_arm_x_set_itself_goes_on_to_feel_at_the_next_press():
    rig = Rig()
    rig.robot(pose=POSE)
    rig.step()
    assert rig.press(BUTTON_OPMODE).actions == [SetSetpoints(RIGHT), SetOpmode(HOLD)]
    rig.tp.on_opmode(HOLD)                 # a repeat of its own mode changes nothing
    rig.robot(pose=POSE)
    assert rig.press(BUTTON_OPMODE).actions == [SetSetpoints(RIGHT), SetOpmode(FEEL)]


def test_feel_set_by_others_without_baxter_goes_limp_and_says_why():
    rig = Rig()
    rig.robot(enabled=False, pose=POSE)
    rig.step()
    rig.tp.on_opmode(FEEL)
    assert rig.step().actions == [SetOpmode(LIMP)]
    assert 'feel ended (no_robot)' in rig.tp.detail


def test_an_unknown_opmode_is_refused_with_a_warning():
    rig = feeling()
    warning = rig.tp.on_opmode('Feel')
    assert warning == "opmode must be one of limp/hold/feel, got 'Feel'; ignored"
    assert rig.tp.opmode == FEEL
