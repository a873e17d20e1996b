"""Teleop when config_X stores a change of what the puppet's angles mean (on_angle_settings):
every following arm stops where Baxter is, the detail names the change and the button, and only
a new press follows again, approaching slowly."""
import pytest

from robopuppet.interface import BUTTON_LEFT, BUTTON_RIGHT, FAULT, FOLLOWING, READY
from test_teleop import NEUTRAL, Rig, enter

MEASURED = {'left': NEUTRAL['left'], 'right': [a + 0.003 for a in NEUTRAL['right']]}


def test_a_change_stops_the_following_arm_where_baxter_is():
    rig = enter(FOLLOWING)
    rig.robot(pose=MEASURED)
    rig.tp.on_angle_settings("joint 0's home_angle")
    assert rig.tp.following['right']   # decided at the next step
    step = rig.step()
    assert step.commands == {'right': pytest.approx(MEASURED['right'])}   # stay there
    assert (rig.tp.state, rig.tp.following['right']) == (READY, False)
    assert rig.tp.detail == ("joint 0's home_angle changed: following stopped; press 3 to "
                             'follow again')
    rig.angles[0] -= 0.5   # the new meaning: the puppet reports joint 0 0.5 rad lower
    assert rig.step().commands == {}
    assert rig.step().commands == {}
    rig.press(BUTTON_RIGHT)   # following again only after a new press, slowly
    assert rig.tp.following['right'] and not rig.tp.tracking['right']
    shoulder = [rig.step().commands['right'][0] for _ in range(10)]
    assert MEASURED['right'][0] - shoulder[-1] == pytest.approx(0.05, abs=0.011)


def test_both_arms_stop_and_changes_before_a_step_are_named_together():
    rig = enter(FOLLOWING)
    rig.press(BUTTON_LEFT)
    assert rig.tp.following == {'left': True, 'right': True}
    rig.tp.on_angle_settings("joint 0's home_angle")
    rig.tp.on_angle_settings("joint 2's sign_angle")
    step = rig.step()
    assert set(step.commands) == {'left', 'right'}
    assert rig.tp.following == {'left': False, 'right': False}
    assert rig.tp.detail == ("joint 0's home_angle, joint 2's sign_angle changed: following "
                             'stopped; press 2 and 3 to follow again')


def test_a_press_in_the_same_step_does_not_outlive_the_change():
    rig = enter(READY)
    rig.tp.on_button(BUTTON_RIGHT)
    rig.tp.on_angle_settings("joint 1's angle_max")
    rig.step()
    assert not rig.tp.following['right']
    assert rig.tp.detail.startswith("joint 1's angle_max changed")


@pytest.mark.parametrize('state', [READY, FAULT])
def test_a_change_while_nothing_follows_changes_nothing(state):
    rig = enter(state)
    detail = rig.tp.detail
    rig.tp.on_angle_settings("joint 0's home_angle")
    assert rig.tp.step(rig.t + 0.01).commands == {}
    assert (rig.tp.state, rig.tp.detail) == (state, detail)
    rig.step()
    assert "home_angle" not in rig.tp.detail   # forgotten, not said at a later press
    rig.press(BUTTON_RIGHT)
    if state == READY:
        assert rig.tp.following['right']
