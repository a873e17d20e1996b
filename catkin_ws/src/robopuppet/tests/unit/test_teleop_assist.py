"""Teleop with the assist: puppet R drives Baxter's right arm, the assist's targets drive the left
arm through button 2 by the same rules as following (approach, speed, limits, zones), holding,
every stop, the other puppet's take-over, the gripper; fed with a fake clock."""
import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.arm import assist_follow, teleop
from robopuppet.interface import (BUTTON_LEFT, BUTTON_RIGHT, FAULT, FOLLOWING, READY,
                                  UNCALIBRATED, WORKING)
from robopuppet.world import arm_capsules, shapes, zones
from test_teleop import LIMITS, NEUTRAL, Rig

TARGET = [0.3, -0.4, -0.2, 0.9, 0.1, 1.0, -0.2]   # the left arm, within its limits
UNFAMILIAR = 'assist holding: unfamiliar motion'


class AssistRig(Rig):
    """A Rig whose assist node sends a target for Baxter's left arm at every step."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.target = list(TARGET)
        self.closed = False
        self.hold = False
        self.sending = True

    def feed(self, statuses=None, angles=None, heartbeat=True):
        super().feed(statuses, angles, heartbeat)
        if self.sending:
            assert self.tp.on_assist_target(self.t, 'left', self.target, self.closed, self.hold,
                                            UNFAMILIAR if self.hold else '') == ''


def assisted():
    """Return an AssistRig of a ready puppet R with the assist engaged on the left arm."""
    rig = AssistRig()
    rig.robot()
    rig.step()
    assert rig.tp.state == READY
    step = rig.press(BUTTON_LEFT)
    assert rig.tp.assist.assisted['left'] and not rig.tp.following['left']
    assert set(step.commands) == {'left'}
    return rig


def steps_until_tracking(rig, limit=2000):
    for n in range(limit):
        rig.step()
        if rig.tp.tracking['left']:
            return n
    raise AssertionError('the assisted arm never reached its target')


def test_button_2_engages_the_assist_when_a_fresh_target_is_there():
    rig = assisted()
    assert rig.tp.state == FOLLOWING
    assert rig.tp.detail == "the assist drives Baxter's left arm"
    rig.press(BUTTON_RIGHT)
    assert rig.tp.detail == 'Baxter follows with its right arm; the assist drives its left arm'


@pytest.mark.parametrize('why', ['none', 'old', 'own arm'])
def test_without_a_fresh_target_button_2_mirrors_the_puppet_as_before(why):
    rig = AssistRig()
    rig.sending = why != 'none'
    rig.hold = why == 'hold'
    rig.robot()
    rig.step()
    if why == 'old':
        rig.sending = False
        rig.step(assist_follow.ASSIST_TIMEOUT_S + 0.01)
    if why == 'own arm':   # refused: puppet R drives Baxter's right arm itself
        assert 'drives that arm itself' in rig.tp.on_assist_target(
            rig.t, 'right', TARGET, False, False, '')
        rig.press(BUTTON_RIGHT)
        assert rig.tp.following['right'] and not rig.tp.assist.assisted['right']
        return
    rig.press(BUTTON_LEFT)
    assert rig.tp.following['left'] and not rig.tp.assist.assisted['left']


def test_button_2_on_a_holding_assist_engages_it_holding_never_mirroring():
    rig = AssistRig()
    rig.sending, rig.hold = True, True
    rig.robot()
    rig.step()
    step = rig.press(BUTTON_LEFT)
    assert rig.tp.assist.assisted['left'] and not rig.tp.following['left']
    assert step.commands['left'] == pytest.approx(NEUTRAL['left']), 'held where Baxter is'
    assert 'assist holding' in rig.tp.detail


def test_the_assisted_arm_approaches_slowly_then_tracks_at_most_at_the_velocity_limit():
    rig = AssistRig()
    rig.robot()
    rig.step()
    previous = rig.press(BUTTON_LEFT).commands['left']
    assert max(abs(p - n) for p, n in zip(previous, NEUTRAL['left'])) <= 0.5 * 0.01 + 1e-12, \
        'the assist starts where Baxter is'
    steps = 1
    while not rig.tp.tracking['left']:
        command = rig.step().commands['left']
        assert max(abs(c - p) for c, p in zip(command, previous)) <= 0.5 * 0.01 + 1e-12
        previous, steps = command, steps + 1
    far = max(abs(t - n) for t, n in zip(TARGET, NEUTRAL['left']))
    # tracking begins within track_tolerance_rad (0.02) of the target
    assert steps == pytest.approx((far - 0.02) / (0.5 * 0.01), abs=1)
    rig.target = [a + 0.3 for a in TARGET]   # a quick move of the prediction
    command = rig.step().commands['left']
    speeds = [abs(c - p) / 0.01 for c, p in zip(command, previous)]
    assert max(speeds) > 0.5, 'tracking is faster than the approach'
    for speed, limit in zip(speeds, LIMITS['left']):
        assert speed <= limit.velocity + 1e-9


def test_a_target_beyond_the_joint_limits_is_clamped():
    rig = assisted()
    rig.target = [5.0] * 7
    for _ in range(2000):
        command = rig.step().commands['left']
        for angle, limit in zip(command, LIMITS['left']):
            assert limit.lower <= angle <= limit.upper
    assert command == pytest.approx([lim.upper for lim in LIMITS['left']])


@pytest.mark.parametrize('why, detail', [
    ('hold', UNFAMILIAR), ('silent assist', 'assist holding: no prediction for 0.2 s')])
def test_a_hold_or_missing_target_holds_where_baxter_is_then_approaches_again(why, detail):
    rig = assisted()
    for _ in range(10):   # on the way
        rig.step()
    where = [a + 0.01 for a in rig.tp.drive._motion['left'].command]   # Baxter lags a little
    rig.robot(pose={'left': where, 'right': NEUTRAL['right']})
    rig.hold, rig.sending = why == 'hold', why == 'hold'
    step = rig.step(assist_follow.ASSIST_TIMEOUT_S + 0.01 if why != 'hold' else 0.01)
    assert step.commands['left'] == pytest.approx(where)
    assert rig.tp.detail == detail and rig.tp.state == FOLLOWING
    rig.robot(pose={'left': NEUTRAL['left'], 'right': NEUTRAL['right']})   # measured again
    for _ in range(20):   # held at that pose, not where Baxter is measured next
        assert rig.step().commands['left'] == pytest.approx(where)
    rig.hold, rig.sending = False, True
    previous, steps = where, 0
    while not rig.tp.tracking['left']:   # moving again: slowly, from the held pose
        command = rig.step().commands['left']
        assert max(abs(c - p) for c, p in zip(command, previous)) <= 0.5 * 0.01 + 1e-12
        previous, steps = command, steps + 1
    assert steps >= 20 and command != pytest.approx(where)
    assert rig.tp.detail == "the assist drives Baxter's left arm"


def stop_by(rig, how):
    if how == 'press':
        return rig.press(BUTTON_LEFT)
    if how == 'silent puppet':
        return rig.step(1.0, feed=False)
    if how == 'uncalibrated':
        rig.statuses = [WORKING] * 2 + [UNCALIBRATED] + [WORKING] * 4
        return rig.step()
    if how == 'angle settings':
        rig.tp.on_angle_settings("joint 0's home_angle")
        return rig.step()
    if how == 'controller failed':
        rig.tp.on_controller_failed('OverflowError: too big')
        return rig.step()
    raise ValueError(how)


@pytest.mark.parametrize('how', ['press', 'silent puppet', 'uncalibrated', 'angle settings',
                                 'controller failed'])
def test_every_stop_stops_the_assisted_arm_where_baxter_is_and_needs_a_new_press(how):
    rig = assisted()
    for _ in range(30):
        rig.step()
    where = [a - 0.01 for a in rig.tp.drive._motion['left'].command]
    rig.robot(pose={'left': where, 'right': NEUTRAL['right']})
    step = stop_by(rig, how)
    assert step.commands == {'left': pytest.approx(where)}
    assert not rig.tp.assist.assisted['left'] and not rig.tp.following['left']
    if how == 'angle settings':
        assert 'press 2 to follow again' in rig.tp.detail
    rig.statuses = [WORKING] * 7
    for _ in range(3):   # fresh data and targets: nothing moves without a new press
        rig.t += 0.1
        rig.feed()
        assert rig.tp.step(rig.t).commands == {}
    assert rig.tp.state in (READY, FAULT)
    if rig.tp.state == READY:
        assert rig.press(BUTTON_LEFT).commands and rig.tp.assist.assisted['left']


def test_the_other_puppet_takes_the_assisted_arm_over_without_both_letting_go():
    rig = assisted()
    rig.press(BUTTON_RIGHT)
    for _ in range(10):
        rig.step()
    rig.tp.on_other_puppet(rig.t, True, False)   # puppet L pressed its button 2
    step = rig.step()
    assert step.commands['left'] == pytest.approx(NEUTRAL['left'])   # stay, once
    assert 'right' in step.commands and rig.tp.following['right']   # its own arm goes on
    assert not rig.tp.assist.assisted['left']
    assert rig.tp.detail == ("puppet L took Baxter's left arm over from the assist; "
                             'Baxter follows with its right arm')
    assert 'both let go' not in rig.tp.detail
    assert 'left' not in rig.step().commands
    rig.press(BUTTON_LEFT)   # the other puppet drives it now
    assert not rig.tp.assist.assisted['left'] and not rig.tp.following['left']


def test_the_gripper_follows_the_target_on_engaging_and_on_changes_but_not_while_holding():
    rig = AssistRig()
    rig.closed = True
    rig.robot()
    rig.step()
    assert teleop.Grip('left', True) in rig.press(BUTTON_LEFT).actions
    assert not [a for a in rig.step().actions if isinstance(a, teleop.Grip)]
    rig.closed = False
    assert [a for a in rig.step().actions if isinstance(a, teleop.Grip)] == [
        teleop.Grip('left', False)]
    rig.closed, rig.hold = True, True   # an unsure prediction does not drop the tray
    assert not [a for a in rig.step().actions if isinstance(a, teleop.Grip)]
    rig.hold = False
    assert teleop.Grip('left', True) in rig.step().actions
    rig.tp.on_end_piece(0.0)   # the end piece grips the puppet's arms, not the assisted one
    assert teleop.Grip('left', True) not in rig.step().actions


def test_the_assisted_arm_is_cut_at_a_keep_out_zone():
    model = bd.load()
    tip = model.pose(dict(zip(bd.arm_joint_names('left'), TARGET)), 'left_gripper')[0]
    ball = shapes.parse_shape({'name': 'ball', 'type': 'sphere', 'radius': 0.08,
                               'xyz': list(np.asarray(tip))})
    with open(bd.URDF_PATH) as urdf:
        capsules = arm_capsules.ArmCapsules(model, urdf.read(), 'left')
    guard = zones.ZoneGuard(capsules, [ball])
    rig = AssistRig(zone_guards={'left': guard})
    rig.robot()
    rig.step()
    rig.press(BUTTON_LEFT)
    for _ in range(1500):
        command = rig.step().commands['left']
        rig.robot(pose={'left': command, 'right': NEUTRAL['right']})   # Baxter where commanded
        assert guard.clearance(command).min() > 0.0
    assert rig.tp.zones.zone('left') == 'ball'
    assert "keep-out zone 'ball'" in rig.tp.detail


def test_the_teleop_state_fields_name_the_assisted_arm_apart_from_the_following_ones():
    rig = assisted()
    assert rig.tp.driven() == {'left': True, 'right': False}
    assert rig.tp.following == {'left': False, 'right': False}
    rig.step(1.0, feed=False)
    assert rig.tp.state == FAULT and rig.tp.driven() == {'left': False, 'right': False}
