"""Tests of robopuppet.baxter_model: enable state, arm motion limits, timeout hold, grippers."""
import math

import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_model import (BaxterModel, CommandError, NotEnabledError,
                                     POSITION_MODE, RAW_POSITION_MODE)

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


@pytest.mark.parametrize('mode, names, values', [
    (2, ['left_s0'], [0.1]),                      # velocity mode
    (3, ['left_s0'], [0.1]),                      # torque mode
    (1, ['left_s0', 'left_s1'], [0.1]),           # length mismatch
    (1, ['right_s0'], [0.1]),                     # the other arm's joint
    (1, ['left_s0'], [float('nan')]),
])
def test_bad_commands_are_dropped_whole(mode, names, values):
    model = enabled_model()
    with pytest.raises(CommandError):
        model.joint_command('left', mode, names, values, 0.0)
    run(model, 0.0, 0.1)
    assert model.arms['left'].positions == bd.neutral_pose('left')


def test_bad_settings_are_refused():
    model = enabled_model()
    for ratio in (-0.1, 1.5, float('inf')):
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
    for command, args in [('configure', '{"speed": 1}'), ('go', 'not json'), ('grip', ''),
                          ('go', '{"position": "half"}'), ('go', '[1]')]:
        with pytest.raises(CommandError):
            model.gripper_command('left', command, args, 's', 4)


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
