"""Unit tests of study.key_jog: each key's joint and direction, follow and grip keys."""
import pytest
from evdev import ecodes as e

from robopuppet.study import key_jog
from robopuppet.study.input_events import InputEvent

PLUS_L = 'KEY_1 KEY_2 KEY_3 KEY_4 KEY_5 KEY_6 KEY_7'.split()
MINUS_L = 'KEY_Q KEY_W KEY_E KEY_R KEY_T KEY_Y KEY_U'.split()
PLUS_R = 'KEY_A KEY_S KEY_D KEY_F KEY_G KEY_H KEY_J'.split()
MINUS_R = 'KEY_Z KEY_X KEY_C KEY_V KEY_B KEY_N KEY_M'.split()


def key(code, value):
    return InputEvent(0.0, e.EV_KEY, code, value)


@pytest.mark.parametrize('side, plus, minus', [('L', PLUS_L, MINUS_L), ('R', PLUS_R, MINUS_R)])
def test_each_key_jogs_its_joint_its_way_while_down(side, plus, minus):
    for joint in range(7):
        for name, sign in ((plus[joint], 1.0), (minus[joint], -1.0)):
            jog = key_jog.KeyJog(side, jog_speed=0.4)
            jog.on_event(key(getattr(e, name), 1))
            want = [0.0] * 7
            want[joint] = sign * 0.4
            assert jog.velocity() == want, name
            jog.on_event(key(getattr(e, name), 2))   # autorepeat: still down
            assert jog.velocity() == want, name
            jog.on_event(key(getattr(e, name), 0))
            assert jog.velocity() == [0.0] * 7, name


def test_the_other_sides_keys_and_other_event_types_do_nothing():
    jog = key_jog.KeyJog('R')
    for name in PLUS_L + MINUS_L:
        jog.on_event(key(getattr(e, name), 1))
    jog.on_event(InputEvent(0.0, e.EV_ABS, e.KEY_A, 1))   # code of KEY_A, but not a key
    jog.on_event(key(key_jog.FOLLOW_KEY['L'], 1))
    assert jog.velocity() == [0.0] * 7 and not jog.follow


def test_plus_and_minus_of_one_joint_cancel_and_two_joints_move_together():
    jog = key_jog.KeyJog('R', jog_speed=1.0)
    for name in ('KEY_A', 'KEY_Z', 'KEY_J'):
        jog.on_event(key(getattr(e, name), 1))
    assert jog.velocity() == [0.0] * 6 + [1.0]


@pytest.mark.parametrize('side', ['L', 'R'])
def test_the_follow_key_is_the_button_while_down_and_the_grip_key_toggles(side):
    jog = key_jog.KeyJog(side)
    jog.on_event(key(key_jog.FOLLOW_KEY[side], 1))
    assert jog.follow
    jog.on_event(key(key_jog.FOLLOW_KEY[side], 2))
    assert jog.follow
    jog.on_event(key(key_jog.FOLLOW_KEY[side], 0))
    assert not jog.follow
    states = []
    for value in (1, 2, 2, 0, 1, 0):   # two presses; autorepeat and release do not toggle
        jog.on_event(key(key_jog.GRIP_KEY[side], value))
        states.append(jog.closed)
    assert states == [True, True, True, True, False, False]


def test_a_speed_that_is_not_positive_is_refused():
    with pytest.raises(ValueError):
        key_jog.KeyJog('R', jog_speed=0.0)
    with pytest.raises(ValueError):
        key_jog.KeyJog('X')
