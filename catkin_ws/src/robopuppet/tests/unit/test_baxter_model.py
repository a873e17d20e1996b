"""Tests of robopuppet.baxter_sim.baxter_model and baxter_gripper: enable state, arm motion
limits, timeout hold, refusals, hold at the measured pose, grippers."""
import math

import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_gripper import MAX_TEXT_CHARS
from robopuppet.baxter_sim.baxter_joint_command import POSITION_MODE, RAW_POSITION_MODE
from robopuppet.baxter_sim.baxter_model import (DEFAULT_COMMAND_TIMEOUT_S, SMOOTHING_TIME_S,
                                                BaxterModel)
from robopuppet.baxter_sim.baxter_refusals import CommandError, NotEnabledError

DESC = bd.load()
LEFT = bd.arm_joint_names('left')
DT = 0.01


def enabled_model(**kwargs):
    model = BaxterModel(DESC, 0.0, **kwargs)
    model.set_enabled(True)
    return model


def run(model, start_s, end_s, command=None, every_s=DT):
    """Step the model from start_s to end_s, re-sending command=(side, mode, names, values)."""
    t = start_s
    while t < end_s - 1e-9:
        if command is not None:
            model.joint_command(*command, t)
        t = round(t + every_s, 9)
        model.step(t)
    return t


def test_starts_disabled_in_the_neutral_pose():
    model = BaxterModel(DESC, 0.0)
    assert not model.enabled
    assert model.arms['left'].positions == bd.neutral_pose('left')


def test_commands_are_ignored_while_disabled():
    model = BaxterModel(DESC, 0.0)
    with pytest.raises(NotEnabledError):
        model.joint_command('left', RAW_POSITION_MODE, ['left_s0'], [1.0], 0.0)
    model.step(1.0)
    assert model.arms['left'].positions['left_s0'] == 0.0


def test_stop_latches_until_reset():
    model = enabled_model()
    model.stop()
    assert model.stopped and not model.enabled
    with pytest.raises(CommandError):
        model.set_enabled(True)
    model.reset()
    assert not model.stopped and not model.enabled
    model.set_enabled(True)
    assert model.enabled


def test_robot_reset_leaves_gripper_errors_to_the_gripper_reset():
    model = enabled_model()
    gripper = model.grippers['left']
    gripper.error = True
    model.reset()
    assert gripper.error
    model.gripper_command('left', 'reset', '', 's', 1)
    assert not gripper.error


def test_raw_mode_moves_at_the_velocity_limit_and_clamps_to_the_joint_limit():
    model = enabled_model()
    cmd = ('left', RAW_POSITION_MODE, ['left_s0', 'left_w0'], [5.0, -5.0])
    run(model, 0.0, 0.5, cmd)
    positions = model.arms['left'].positions
    assert positions['left_s0'] == pytest.approx(1.5 * 0.5)   # s0: 1.5 rad/s
    assert positions['left_w0'] == pytest.approx(-4.0 * 0.5)  # w0: 4.0 rad/s
    run(model, 0.5, 3.0, cmd)
    assert positions['left_s0'] == pytest.approx(1.70167993878)   # clamped at the upper limit
    assert positions['left_w0'] == pytest.approx(-3.059)


def test_position_mode_speed_is_scaled_by_the_speed_ratio():
    model = enabled_model()
    cmd = ('left', POSITION_MODE, ['left_s0'], [1.5])
    run(model, 0.0, 0.5, cmd)
    assert model.arms['left'].velocities['left_s0'] == pytest.approx(0.3 * 1.5)
    model.set_speed_ratio('left', 1.0)
    run(model, 0.5, 0.6, cmd)
    assert model.arms['left'].velocities['left_s0'] == pytest.approx(1.5)


def test_position_mode_settles_on_the_target_without_overshoot():
    model = enabled_model()
    cmd = ('left', POSITION_MODE, ['left_e1'], [1.0])
    trace = []
    t = 0.0
    for _ in range(300):
        model.joint_command(*cmd, t)
        t += DT
        model.step(t)
        trace.append(model.arms['left'].positions['left_e1'])
    assert all(b >= a for a, b in zip(trace, trace[1:]))
    assert max(trace) <= 1.0
    assert trace[-1] == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize('mode', [POSITION_MODE, RAW_POSITION_MODE])
def test_speed_never_exceeds_the_velocity_limit(mode):
    model = enabled_model()
    model.set_speed_ratio('left', 1.0)
    limits = {lim.name: lim.velocity for lim in bd.arm_limits('left')}
    t = 0.0
    for i, dt in enumerate([0.001, 0.3, 0.01, 0.05, 0.002, 0.1] * 5):
        sign = 1 if i % 4 < 2 else -1
        model.joint_command('left', mode, LEFT, [sign * 3.0] * 7, t)
        before = dict(model.arms['left'].positions)
        t += dt
        model.step(t)
        for name in LEFT:
            moved = abs(model.arms['left'].positions[name] - before[name])
            assert moved <= limits[name] * dt + 1e-12
            assert abs(model.arms['left'].velocities[name]) <= limits[name] + 1e-9


def test_arm_holds_when_commands_stop_for_the_timeout():
    model = enabled_model()
    model.joint_command('left', RAW_POSITION_MODE, ['left_s0'], [1.5], 0.0)
    run(model, 0.0, 1.0)
    # Followed for exactly the 0.2 s timeout at 1.5 rad/s, then held.
    assert model.arms['left'].positions['left_s0'] == pytest.approx(0.3)
    assert model.arms['left'].velocities['left_s0'] == 0.0
    model.set_command_timeout('left', 0.5)
    model.joint_command('left', RAW_POSITION_MODE, ['left_s0'], [1.5], 1.0)
    run(model, 1.0, 2.0)
    assert model.arms['left'].positions['left_s0'] == pytest.approx(1.05)


def test_a_late_step_still_honours_the_timeout():
    model = enabled_model()
    model.joint_command('left', RAW_POSITION_MODE, ['left_s0'], [1.5], 0.0)
    model.step(1.0)   # one long step: only the first 0.2 s count
    assert model.arms['left'].positions['left_s0'] == pytest.approx(0.3)


def test_names_in_any_order_and_subsets():
    model = enabled_model()
    model.joint_command('left', RAW_POSITION_MODE, ['left_w2', 'left_s1'], [0.1, -0.5], 0.0)
    run(model, 0.0, 0.15)
    positions = model.arms['left'].positions
    assert positions['left_w2'] == pytest.approx(0.1)
    assert positions['left_s1'] == pytest.approx(-0.5)
    assert positions['left_e1'] == pytest.approx(0.75)   # untouched neutral value


@pytest.mark.parametrize('mode, names, values, reason', [
    (5, ['left_s0'], [0.1], 'unknown mode'),
    (2, ['left_s0'], [float('inf')], 'non-finite value'),
    (-7, ['left_s0'], [0.1], 'unknown mode'),
    (1, ['left_s0', 'left_s1'], [0.1], 'length mismatch'),
    (1, [], [], 'empty'),
    (4, [], [], 'empty'),
    (1, ['right_s0'], [0.1], 'unknown joint'),           # the other arm's joint
    (1, ['left_s0', 'bogus'], [0.1, 0.2], 'unknown joint'),
    (1, ['left_s0', 'left_s0'], [0.1, -0.1], 'repeated joint'),
    (1, LEFT * 20000, [0.1] * 140000, 'too many joints'),
    (1, ['left_s0'], [float('nan')], 'non-finite value'),
    (4, ['left_s0', 'left_e1'], [0.1, float('-inf')], 'non-finite value'),
])
def test_bad_commands_are_dropped_whole(mode, names, values, reason):
    model = enabled_model()
    with pytest.raises(CommandError) as caught:
        model.joint_command('left', mode, names, values, 0.0)
    assert caught.value.reason == reason
    assert len(str(caught.value)) < 300
    run(model, 0.0, 0.1)
    assert model.arms['left'].positions == bd.neutral_pose('left')


@pytest.mark.parametrize('names, values', [
    ([], []),                                    # empty: what kept s0 moving for 3 s before
    (['bogus'], [0.1]),
    (['left_s0'], []),
    (['left_e1'], [float('nan')]),
    (['left_w0', 'left_w0'], [0.0, 0.0]),
])
def test_commands_carrying_nothing_usable_neither_restart_the_timeout_nor_switch_mode(
        names, values):
    model = enabled_model()
    model.joint_command('left', RAW_POSITION_MODE, ['left_s0'], [1.5], 0.0)
    t = 0.0
    while t < 3.0:
        with pytest.raises(CommandError):
            model.joint_command('left', POSITION_MODE, names, values, t)
        t = round(t + DT, 9)
        model.step(t)
    arm = model.arms['left']
    assert arm.mode == RAW_POSITION_MODE   # mode 1 would have gone on to the target (no timeout)
    # Followed for the 0.2 s timeout only (mode 4 at 1.5 rad/s at most), then held.
    assert 0.0 < arm.positions['left_s0'] <= 1.5 * 0.2 + 1e-9
    assert arm.velocities['left_s0'] == 0.0


@pytest.mark.parametrize('mode', [POSITION_MODE, RAW_POSITION_MODE])
@pytest.mark.parametrize('resend', [True, False])
def test_a_command_to_the_measured_pose_stops_the_arm_at_once(mode, resend):
    """The arm controller's fault hold: command the pose /robot/joint_states reported.

    The measurement is 20 ms old when the hold arrives (two more steps toward the old target);
    from then on the arm must not go one step further toward the old target, and must settle on
    the measured pose, whether the hold is re-sent at 100 Hz or sent once.
    """
    model = enabled_model()
    model.set_speed_ratio('left', 1.0)
    far = {lim.name: lim.upper for lim in bd.arm_limits('left')}
    cmd = ('left', mode, list(far), list(far.values()))
    t = run(model, 0.0, 0.1, cmd)
    names, positions, _, _ = model.joint_state()
    measured = {n: p for n, p in zip(names, positions) if n in far}
    t = run(model, t, t + 0.02, cmd)            # the measurement travels to the controller
    arm = model.arms['left']
    at_hold = dict(arm.positions)
    assert all(at_hold[n] > measured[n] + 1e-3 for n in far)   # it was moving toward `far`
    hold = ('left', mode, list(measured), list(measured.values()))
    model.joint_command(*hold, t)
    for _ in range(100):
        before = dict(arm.positions)
        t = run(model, t, t + DT, hold if resend else None)
        for name in far:
            assert arm.positions[name] <= before[name] + 1e-12, name    # never on toward `far`
            assert arm.positions[name] >= measured[name] - 1e-12, name  # nor past the hold
    # Sent once, mode 1's lag (0.05 s) has the 0.2 s command timeout to undo the 20 ms of
    # motion since the measurement: it ends within exp(-4) of that (<= 1.5 mrad), then holds.
    for name, limit in arm.limits.items():
        tolerance = 1e-6
        if mode == POSITION_MODE and not resend:
            tolerance = 0.02 * limit.velocity * math.exp(-DEFAULT_COMMAND_TIMEOUT_S
                                                         / SMOOTHING_TIME_S) + 1e-6
        assert arm.positions[name] == pytest.approx(measured[name], abs=tolerance)
        assert abs(arm.velocities[name]) < 1e-3


def test_bad_settings_are_refused():
    model = enabled_model()
    for ratio in (float('nan'), float('inf'), -float('inf')):   # -0.1, 1.5: clipped, as Baxter
        with pytest.raises(CommandError):
            model.set_speed_ratio('left', ratio)
    with pytest.raises(CommandError):
        model.set_command_timeout('left', 0.0)
    assert model.arms['left'].speed_ratio == 0.3


def test_joint_state_lists_every_joint_with_equal_lengths():
    model = enabled_model()
    names, positions, velocities, efforts = model.joint_state()
    movable = {n for n, j in DESC.joints.items() if j.type != 'fixed'}
    assert set(names) == movable | {'torso_t0', 'head_pan'}
    assert len(names) == len(positions) == len(velocities) == len(efforts) == len(set(names))


def gripper_go(model, position, sequence, side='left'):
    model.gripper_command(side, 'go', '{"position": %s}' % position, 'test_go', sequence)


def test_gripper_must_be_calibrated_before_go():
    model = enabled_model()
    with pytest.raises(CommandError):
        gripper_go(model, 0, 1)
    assert model.grippers['left'].last_command == ('go', 'test_go', 1)   # still acknowledged
    model.gripper_command('left', 'calibrate', '', 'test_cal', 2)
    model.step(0.1)
    assert model.grippers['left'].calibrated
    model.gripper_command('left', 'clear_calibration', '', 'test_clear', 3)
    assert not model.grippers['left'].calibrated


def test_gripper_closes_at_a_finite_speed_and_moves_the_fingers():
    model = enabled_model(gripper_calibrated=True)
    gripper = model.grippers['left']
    gripper_go(model, 0, 7)
    speed_pct_s = 0.05 / 0.020833 * 100.0 * 0.5    # finger limit 0.05 m/s, velocity 50 %
    model.step(0.2)
    assert gripper.position == pytest.approx(100.0 - speed_pct_s * 0.2)
    assert gripper.moving
    names, positions, _, _ = model.joint_state()
    finger = dict(zip(names, positions))
    assert finger['l_gripper_l_finger_joint'] == pytest.approx(gripper.position / 100 * 0.020833)
    assert finger['l_gripper_r_finger_joint'] == -finger['l_gripper_l_finger_joint']
    model.step(2.0)
    assert gripper.position == 0.0 and not gripper.moving and gripper.missed
    assert model.grippers['right'].position == 100.0


def test_gripper_configure_stop_and_errors():
    model = enabled_model(gripper_calibrated=True)
    gripper = model.grippers['left']
    model.gripper_command('left', 'configure', '{"velocity": 100.0, "dead_zone": 2}', 's', 1)
    assert gripper.parameters['velocity'] == 100.0
    gripper_go(model, 0, 2)
    model.step(0.1)
    model.gripper_command('left', 'stop', '', 's', 3)
    model.step(0.5)
    assert gripper.position == pytest.approx(100.0 - 0.05 / 0.020833 * 100.0 * 0.1)
    for command, args, reason in [
            ('configure', '{"speed": 1}', 'unknown parameter'),
            ('configure', '{"velocity": 10, "dead_zone": "x"}', 'bad value'),  # all or nothing
            ('go', 'not json', 'malformed args'),
            ('go', '{"position": ' + '[' * 4000, 'malformed args'),   # was a RecursionError
            ('go', '[' * 2000 + ']' * 2000, 'malformed args'),
            ('go', '{"position": 1' + '0' * 400 + '}', 'bad value'),  # was an OverflowError
            ('go', '{"position": 1e999}', 'bad value'),
            ('go', '{"position": NaN}', 'bad value'),
            ('go', '{"position": "50"}', 'bad value'),
            ('go', '{"position": true}', 'bad value'),
            ('go', '{}', 'malformed args'),
            ('grip', '', 'unknown command'),
            ('go', '{"position": "half"}', 'bad value'),
            ('go', '[1]', 'malformed args')]:
        with pytest.raises(CommandError) as caught:
            model.gripper_command('left', command, args, 's', 4)
        assert caught.value.reason == reason, args[:40]
        assert len(str(caught.value)) < 300
        assert gripper.last_command == (command, 's', 4)   # acknowledged although refused
    assert gripper.parameters['velocity'] == 100.0 and gripper.target == gripper.position


def test_gripper_refuses_text_too_long_to_echo_without_acknowledging_it():
    model = enabled_model(gripper_calibrated=True)
    gripper = model.grippers['left']
    model.gripper_command('left', 'no_op', '', 's', 1)
    for command, args, sender in [('go', '{"position": 0}', 'x' * (MAX_TEXT_CHARS + 1)),
                                  ('go', ' ' * 10 ** 6 + '{"position": 0}', 's'),
                                  ('g' * 10 ** 6, '', 's')]:
        with pytest.raises(CommandError) as caught:
            model.gripper_command('left', command, args, sender, 2)
        assert caught.value.reason == 'too long'
    assert gripper.last_command == ('no_op', 's', 1) and gripper.target == 100.0


def test_gripper_does_not_move_while_disabled():
    model = BaxterModel(DESC, 0.0, gripper_calibrated=True)
    gripper_go(model, 0, 1)
    model.step(1.0)
    assert model.grippers['left'].position == 100.0


def test_endpoint_pose_follows_the_arm():
    model = enabled_model()
    before, _ = model.endpoint_pose('left')
    run(model, 0.0, 0.2, ('left', RAW_POSITION_MODE, ['left_s0'], [0.3]))
    after, _ = model.endpoint_pose('left')
    # s0 turns the whole arm about the vertical axis of its mount: height is unchanged.
    assert after[2] == pytest.approx(before[2])
    assert math.hypot(after[0] - before[0], after[1] - before[1]) > 0.1


def test_a_command_takes_effect_when_it_arrives_not_at_the_last_step():
    """Between two steps the arm moves toward the old target until the new command arrives (a
    real arm cannot obey a command before it gets it)."""
    model = enabled_model()
    far = {lim.name: lim.upper for lim in bd.arm_limits('left')}
    run(model, 0.0, 0.1, ('left', RAW_POSITION_MODE, list(far), list(far.values())))
    arm = model.arms['left']
    speeds = dict(arm.velocities)
    assert all(v > 0.1 for v in speeds.values())  # moving toward `far` at its limits
    # At 0.105 s, halfway to the next step, "stay where you are now" arrives.
    now = {n: arm.positions[n] + speeds[n] * 0.005 for n in far}
    model.joint_command('left', RAW_POSITION_MODE, list(now), list(now.values()), 0.105)
    model.step(0.11)
    for name in far:
        assert arm.positions[name] == pytest.approx(now[name], abs=1e-9), name
        assert arm.velocities[name] == pytest.approx(0.0, abs=1e-6), name
