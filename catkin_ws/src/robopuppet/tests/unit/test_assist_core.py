"""Tests of robopuppet.assist.assist_core: the assist's hold rules, its hysteresis, stop and
start, refused leader poses, the state texts and when the state and the ghost go out."""
import collections
import math

import pytest

from robopuppet.assist import assist_core
from robopuppet.assist.assist_core import AssistCore

Prediction = collections.namedtuple('Prediction', 'positions gripper_closed confidence familiar')
DT = 0.01  # 100 Hz


class Predictor:
    """A stand-in of model_file's Predictor: the follower mirrors the leader; the motion is
    familiar while the leader's first joint stays below 1 rad."""
    leader, follower, task, method = 'right', 'left', 'carry the tray', 'gmr'

    def __init__(self):
        self.steps, self.resets, self.fail = [], 0, None

    def reset(self):
        self.resets += 1

    def step(self, t, leader_positions):
        self.steps.append((t, list(leader_positions)))
        if self.fail:
            return self.fail()
        familiar = leader_positions[0] < 1.0
        return Prediction([-a for a in leader_positions], leader_positions[1] > 0.5,
                          0.9 if familiar else 0.1, familiar)


def pose(a=0.1, b=0.0):
    return [a, b, 0.2, 0.3, 0.4, 0.5, 0.6]


@pytest.fixture(name='core')
def fixture_core():
    return AssistCore(Predictor(), rate_hz=100.0, leader_timeout_s=0.1, resume_after_s=0.3)


def run(core, t0, t1, leader=None):
    """Feed a leader pose (default pose()) and step every 10 ms from t0 to before t1; return
    the steps."""
    steps, n = [], int(round((t1 - t0) / DT))
    for i in range(n):
        t = t0 + i * DT
        assert core.on_leader_pose(t, leader or pose()) == ''
        steps.append(core.step(t))
    return steps


def test_it_is_ready_after_familiar_motion_and_says_which_button_engages_it(core):
    steps = run(core, 0.0, 0.5)
    first, last = steps[0], steps[-1]
    assert first.target.hold and first.state.state == assist_core.HOLDING  # watching first
    assert last.state.state == assist_core.READY and not last.target.hold
    assert last.state.detail == (
        "ready: press 2 on puppet R to let the assist drive Baxter's left arm")
    assert last.target.side == 'left' and last.target.positions == [-a for a in pose()]
    assert last.state[1:5] == ('right', 'left', 'carry the tray', 'gmr')
    assert last.state.confidence == pytest.approx(0.9)
    resumed = next(i for i, s in enumerate(steps) if not s.target.hold)
    assert resumed * DT == pytest.approx(0.3)


def test_the_leaders_controller_driving_it_makes_it_assisting_with_the_take_over_hint(core):
    run(core, 0.0, 0.5)
    core.on_teleop_state(0.5, True)
    step = run(core, 0.5, 0.52)[-1]
    assert step.state.state == assist_core.ASSISTING and not step.target.hold
    assert 'take over: press 2 on puppet L' in step.state.detail
    core.on_teleop_state(0.6, False)  # the left puppet took it over
    assert run(core, 0.6, 0.62)[-1].state.state == assist_core.READY


def test_unfamiliar_motion_holds_at_once_and_resumes_after_familiar_for_0_3_s(core):
    run(core, 0.0, 0.5)
    core.on_teleop_state(0.5, True)
    step = run(core, 0.5, 0.51, pose(a=1.5))[-1]
    assert step.target.hold and step.state.state == assist_core.HOLDING
    assert step.state.detail == step.target.detail == 'assist holding: unfamiliar motion'
    assert step.state.confidence == pytest.approx(0.1)
    # Flickering back to familiar for less than 0.3 s does not resume.
    steps = run(core, 0.51, 0.71) + run(core, 0.71, 0.72, pose(a=1.5)) + run(core, 0.72, 1.2)
    holds = [s.target.hold for s in steps]
    assert all(holds[:21]) and all(s.target.detail == assist_core.UNFAMILIAR
                                   for s in steps if s.target.hold)
    resumed = next(i for i, h in enumerate(holds) if not h)
    assert 0.72 + (resumed - 21) * DT == pytest.approx(1.02)
    assert steps[-1].state.state == assist_core.ASSISTING


def test_a_hold_target_still_carries_the_newest_predictions_pose(core):
    run(core, 0.0, 0.5)
    step = run(core, 0.5, 0.51, pose(a=1.5, b=0.7))[-1]
    assert step.target.hold
    assert step.target.positions == [-a for a in pose(a=1.5, b=0.7)]
    assert step.target.gripper_closed


def test_a_leader_pose_older_than_the_timeout_holds_and_the_predictor_restarts(core):
    run(core, 0.0, 0.5)
    predictor = core.predictor
    resets, stepped = predictor.resets, len(predictor.steps)
    assert not core.step(0.59).target.hold  # 0.1 s after the last pose at 0.49
    step = core.step(0.6)
    assert step.target.hold and step.state.state == assist_core.HOLDING
    assert step.target.detail == "assist holding: Baxter's right arm's pose is not current"
    assert step.target.positions == [-a for a in pose()]  # the last prediction's pose
    assert predictor.resets == resets + 1 and len(predictor.steps) == stepped
    steps = run(core, 1.0, 1.5)  # back: familiar for 0.3 s before it resumes
    assert steps[0].target.hold and steps[29].target.hold and not steps[30].target.hold


def test_no_leader_pose_yet_holds_and_sends_no_target(core):
    step = core.step(0.0)
    assert step.target is None and step.ghost is None
    assert step.state.state == assist_core.HOLDING
    assert step.state.detail == "assist holding: Baxter's right arm's pose is not known yet"


@pytest.mark.parametrize('bad', [
    [math.nan] + pose()[1:], pose()[:6], pose() + [0.0], [math.inf] * 7, ['x'] * 7, None])
def test_a_leader_pose_that_is_not_7_finite_angles_is_refused_and_said(core, bad):
    run(core, 0.0, 0.5)
    stepped = len(core.predictor.steps)
    warning = core.on_leader_pose(0.5, bad)
    assert warning.startswith('leader pose refused')
    core.step(0.5)
    assert len(core.predictor.steps) == stepped  # never reached the model
    assert core.step(0.6).target.hold            # the pose it had ages


def test_stop_holds_until_start(core):
    run(core, 0.0, 0.5)
    core.on_teleop_state(0.5, True)
    assert core.on_command(0.5, 'stop') == ''
    step = run(core, 0.5, 0.52)[-1]
    assert step.target.hold and step.state.state == assist_core.STOPPED
    assert step.state.detail == step.target.detail == assist_core.STOPPED_TEXT
    assert step.ghost is None or step.ghost == [-a for a in pose()]  # still predicting
    step = run(core, 0.52, 2.0)[-1]
    assert step.target.hold and step.state.state == assist_core.STOPPED
    assert core.on_command(2.0, 'start') == ''
    step = run(core, 2.0, 2.01)[-1]
    assert not step.target.hold and step.state.state == assist_core.ASSISTING


def test_stop_holds_even_familiar_motion_that_comes_back(core):
    core.on_command(0.0, 'stop')
    assert all(s.target.hold for s in run(core, 0.0, 1.0))


@pytest.mark.parametrize('text', ['Stop', 'halt', '', 'start stop'])
def test_an_unknown_command_is_ignored_with_a_warning(core, text):
    run(core, 0.0, 0.5)
    core.on_command(0.5, 'stop')
    assert 'ignored' in core.on_command(0.5, text)
    assert run(core, 0.5, 0.51)[-1].state.state == assist_core.STOPPED


def test_without_a_model_it_is_off_with_the_problem_and_sends_no_target():
    core = AssistCore(None, problem='waiting for the model file /m.npz')
    core.on_leader_pose(0.0, pose())
    step = core.step(0.0)
    assert step.target is None and step.ghost is None and step.publish_state
    assert step.state == assist_core.Status(
        'off', '', '', '', '', 0.0, 'assist off: waiting for the model file /m.npz')
    assert core.on_model(1.0, Predictor()) == ''
    assert run(core, 1.0, 1.5)[-1].state.state == assist_core.READY


def test_a_model_that_does_not_name_baxters_two_arms_is_refused():
    predictor = Predictor()
    predictor.follower = 'right'
    core = AssistCore(None)
    assert 'not Baxter' in core.on_model(0.0, predictor)
    assert core.step(0.0).state.state == assist_core.OFF and core.predictor is None


@pytest.mark.parametrize('fail', [
    lambda: 1 / 0,
    lambda: Prediction([math.nan] * 7, False, 0.9, True),
    lambda: Prediction([0.0] * 6, False, 0.9, True),
    lambda: Prediction([0.0] * 7, False, 1.5, True)])
def test_a_model_that_fails_or_predicts_garbage_holds_with_a_warning(core, fail):
    run(core, 0.0, 0.5)
    core.predictor.fail = fail
    core.on_leader_pose(0.5, pose())
    step = core.step(0.5)
    assert step.warning.startswith('the model failed')
    assert step.target.hold and step.target.detail == 'assist holding: the model failed'
    assert step.target.positions == [-a for a in pose()]  # the last valid prediction's pose


def test_the_predictor_steps_once_per_leader_pose_with_its_time(core):
    core.on_leader_pose(0.003, pose())
    for t in (0.01, 0.02, 0.03):
        core.step(t)
    assert core.predictor.steps == [(0.003, pose())]


def test_the_state_goes_out_on_change_and_every_half_second_not_every_step(core):
    steps = run(core, 0.0, 2.0)
    sent = [i * DT for i, s in enumerate(steps) if s.publish_state]
    changes = [i * DT for i, s in enumerate(steps)
               if i == 0 or s.state.state != steps[i - 1].state.state]
    assert set(changes) <= set(sent)
    assert all(0.0 < b - a <= 0.5 + 1e-9 for a, b in zip(sent, sent[1:]))
    assert len(sent) <= 6


def test_the_ghost_shows_both_arms_at_about_25_hz(core):
    steps = run(core, 0.0, 0.4)
    ghosts = [s for s in steps if s.ghost is not None]
    assert 9 <= len(ghosts) <= 11
    assert ghosts[-1].ghost == [-a for a in pose()] and ghosts[-1].leader_pose == pose()


def test_arm_positions_takes_the_arms_joints_by_name():
    names = ['head_pan'] + ['left_' + j for j in ('w2', 'w1', 'w0', 'e1', 'e0', 's1', 's0')]
    assert assist_core.arm_positions(names, range(8), 'left') == [7, 6, 5, 4, 3, 2, 1]
    with pytest.raises(ValueError, match='no right_s0'):
        assist_core.arm_positions(names, range(8), 'right')
    with pytest.raises(ValueError, match='8 names but 7 positions'):
        assist_core.arm_positions(names, range(7), 'left')
