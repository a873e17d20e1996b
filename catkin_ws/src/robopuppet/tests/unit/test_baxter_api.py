"""Tests of robopuppet.baxter_sim.baxter_api: refusal log lines, enable-state changes, the
publishing schedule and the content of the state messages, without ROS."""
import io

import pytest
from baxter_core_msgs.msg import AssemblyState, EndEffectorProperties, EndEffectorState

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_api as api
from robopuppet.baxter_sim.baxter_model import BaxterModel

LEFT_COMMAND = '/robot/limb/left/joint_command'
RIGHT_COMMAND = '/robot/limb/right/joint_command'
LEFT_GRIPPER = '/robot/end_effector/left_gripper/command'
VELOCITY, POSITION, TORQUE = 2, 1, 3


def make_api(enabled=True, timeout_s=0.2, **kwargs):
    sim = api.BaxterApi(BaxterModel(bd.load(), 0.0, **kwargs), timeout_s)
    if enabled:
        sim.set_enabled('/robot/set_super_enable', True, 0.0)
    return sim


def test_bool_param_takes_only_booleans():
    assert api.bool_param('/b/gripper_calibrated', True) is True
    for value in (1, 0, 'true', None):
        with pytest.raises(ValueError, match='/b/gripper_calibrated'):
            api.bool_param('/b/gripper_calibrated', value)


def test_refusals_of_different_kinds_and_sides_are_each_logged():
    # Before: all joint-command refusals shared one throttle slot, so only the first was logged.
    # Within 2 s of a velocity refusal: a torque command on the other arm and an unknown joint
    # on the same arm are each logged.
    sim = make_api()
    nan = float('nan')
    lines = [sim.joint_command(LEFT_COMMAND, 'left', VELOCITY, ['left_s0'], [nan], 1.0, 100.0),
             sim.joint_command(RIGHT_COMMAND, 'right', TORQUE, ['right_s0'], [nan], 1.0, 100.5),
             sim.joint_command(LEFT_COMMAND, 'left', POSITION, ['right_s0'], [0.1], 1.0, 101.0),
             sim.joint_command(LEFT_COMMAND, 'left', 7, ['left_s0'], [0.1], 1.0, 101.5)]
    assert all(reply.change is None for reply in lines)
    for reply, words in zip(lines, (('left', 'left_s0', 'non-finite value'),
                                    ('right', 'right_s0', RIGHT_COMMAND),
                                    ('left', 'right_s0', 'unknown joint'),
                                    ('left', 'mode 7', 'unknown mode'))):
        assert reply.warning and all(w in reply.warning for w in words), (reply, words)


def test_repeats_of_one_refusal_are_throttled_and_counted():
    sim = make_api()
    warnings = [sim.joint_command(LEFT_COMMAND, 'left', 9, ['left_s0'], [0.1], 1.0,
                                  100.0 + 0.01 * i).warning for i in range(150)]
    assert warnings[0] is not None and warnings[1:] == [None] * 149
    later = sim.joint_command(LEFT_COMMAND, 'left', 9, ['left_s0'], [0.1], 1.0, 102.5)
    assert '149 more since the last line' in later.warning
    assert 'at most every 2 s' in later.warning


def test_a_taken_command_says_nothing():
    sim = make_api()
    reply = sim.joint_command(LEFT_COMMAND, 'left', POSITION, ['left_s0'], [0.5], 1.0, 100.0)
    assert reply == api.Reply(None, None)
    assert sim.model.arms['left'].targets['left_s0'] == 0.5


def test_a_gripper_command_for_another_id_is_refused_unacknowledged():
    sim = make_api(gripper_calibrated=True)
    reply = sim.gripper_command(LEFT_GRIPPER, 'left', api.GRIPPER_ID + 1, 'go',
                                '{"position": 0}', 'me', 7, 100.0)
    assert 'wrong id' in reply.warning and str(api.GRIPPER_ID + 1) in reply.warning
    assert sim.model.grippers['left'].last_command == ('', '', 0)
    assert sim.model.grippers['left'].target == 100.0
    # Another reason on the same topic is still logged within the interval.
    nested = sim.gripper_command(LEFT_GRIPPER, 'left', api.GRIPPER_ID, 'go',
                                 '{"position": ' + '[' * 4000, 'me', 8, 100.1)
    assert 'nested too deeply' in nested.warning and len(nested.warning) < 400
    assert sim.model.grippers['left'].last_command == ('go', 'me', 8)


def test_enable_changes_are_reported_once_and_refusals_change_nothing():
    sim = make_api(enabled=False)
    topic = '/robot/set_super_enable'
    assert sim.set_enabled(topic, False, 0.0) == api.Reply(None, None)   # already disabled
    assert sim.set_enabled(topic, True, 0.0).change == 'robot enabled'
    assert sim.set_enabled(topic, True, 0.1).change is None              # a repeat
    assert sim.stop('/robot/set_super_stop', 0.2).change == 'robot stopped'
    refused = sim.set_enabled(topic, True, 0.3)
    assert refused.change is None and 'reset it first' in refused.warning
    assert sim.reset('/robot/set_super_reset', 0.4).change == 'robot reset (it stays disabled)'
    assert sim.set_enabled(topic, False, 0.5).change is None
    assert sim.set_enabled(topic, True, 0.6).change == 'robot enabled'
    assert sim.set_enabled(topic, False, 0.7).change == 'robot disabled'


def test_robot_state_reports_the_stop_as_the_users_estop():
    sim = make_api(enabled=False)
    assert sim.robot_state() == dict(
        ready=False, enabled=False, stopped=False, error=False,
        estop_button=AssemblyState.ESTOP_BUTTON_UNPRESSED,
        estop_source=AssemblyState.ESTOP_SOURCE_NONE)
    sim.set_enabled('/robot/set_super_enable', True, 0.0)
    assert sim.robot_state()['ready'] and sim.robot_state()['enabled']
    sim.stop('/robot/set_super_stop', 0.0)
    state = sim.robot_state()
    assert (state['ready'], state['enabled'], state['stopped']) == (False, False, True)
    assert state['estop_source'] == AssemblyState.ESTOP_SOURCE_USER
    AssemblyState(**state).serialize(io.BytesIO())   # every field exists and has its type


def test_robot_state_is_due_every_fifth_cycle():
    sim = make_api()
    due = [sim.cycle(0.01 * i).state_due for i in range(1, 16)]
    assert [i for i, d in enumerate(due, 1) if d] == [5, 10, 15]


def test_a_cycle_steps_the_model_and_reports_both_arms_and_grippers():
    sim = make_api(gripper_calibrated=True)
    sim.joint_command(LEFT_COMMAND, 'left', 4, ['left_s0'], [0.5], 0.0, 0.0)
    sim.gripper_command(LEFT_GRIPPER, 'left', api.GRIPPER_ID, 'go', '{"position": 0}', 'me',
                        3, 0.0)
    cycle = sim.cycle(0.1)
    names, positions, velocities, efforts = cycle.joints
    left_s0 = names.index('left_s0')
    assert 0.0 < positions[left_s0] < 0.5 and velocities[left_s0] > 0.0   # moving, not jumped
    assert len(names) == len(positions) == len(velocities) == len(efforts)
    assert set(cycle.poses) == set(cycle.grippers) == {'left', 'right'}
    assert cycle.poses['left'] == bd.load().pose(dict(zip(names, positions)), 'left_gripper')
    left = cycle.grippers['left']
    assert (left['command'], left['command_sender'], left['command_sequence']) == ('go', 'me', 3)
    assert left['moving'] and not left['ready'] and 0.0 < left['position'] < 100.0
    assert cycle.grippers['right']['ready'] and not cycle.grippers['right']['moving']
    EndEffectorState(**left).serialize(io.BytesIO())


def test_a_gripper_is_not_ready_while_the_robot_is_disabled():
    sim = make_api(enabled=False, gripper_calibrated=True)
    grippers = sim.cycle(0.1).grippers
    assert not grippers['left']['ready'] and not grippers['left']['enabled']


def test_the_initial_command_timeout_holds_both_arms():
    sim = make_api(timeout_s=0.05)
    for side in ('left', 'right'):
        assert sim.model.arms[side].command_timeout_s == 0.05
    sim.joint_command(LEFT_COMMAND, 'left', 4, ['left_s0'], [1.0], 0.0, 0.0)
    sim.cycle(0.5)
    held = sim.model.arms['left'].positions['left_s0']
    assert 0.0 < held < 0.2   # 0.05 s at most at the velocity limit, not on to 1.0
    names, positions, _, _ = sim.cycle(1.0).joints
    assert positions[names.index('left_s0')] == held


def test_gripper_properties_are_a_valid_electric_gripper_message():
    props = EndEffectorProperties(**api.gripper_properties('left'))
    props.serialize(io.BytesIO())
    assert props.ui_type == EndEffectorProperties.ELECTRIC_GRIPPER
    assert props.id == api.GRIPPER_ID and props.serial_number == 'RP-SIM-LEFT'
