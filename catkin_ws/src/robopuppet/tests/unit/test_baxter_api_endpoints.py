"""Tests of robopuppet.baxter_sim.baxter_api's cycle and commands for the endpoint state, the
joint efforts, /robot/joint_state_publish_rate, inverse_dynamics_command and the gripper's
rsdk topics, without ROS."""
import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_api as api
from robopuppet.baxter_sim.baxter_model import BaxterModel

POSITION, TORQUE = 1, 3
LEFT_COMMAND = '/robot/limb/left/joint_command'
RATE = '/robot/joint_state_publish_rate'


def make_api(enabled=True):
    sim = api.BaxterApi(BaxterModel(bd.load(), 0.0), 0.2)
    if enabled:
        sim.set_enabled('/robot/set_super_enable', True, 0.0)
    return sim


def efforts(cycle):
    names, _, _, values = cycle.joints
    return dict(zip(names, values))


def test_a_holding_arm_reports_its_gravity_torques_a_disabled_one_none():
    sim = make_api()
    held = efforts(sim.cycle(0.01))
    gravity = sim.statics['left'].gravity([bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES])
    assert held['left_s1'] == gravity[1] and held['left_s1'] < -20.0
    assert held['right_s1'] < -20.0 and held['head_pan'] == 0.0
    sim.set_enabled('/robot/set_super_enable', False, 0.0)
    assert not any(efforts(sim.cycle(0.02)).values())


def test_torque_mode_reports_the_commanded_torques_and_its_timeout_gravity_again():
    sim = make_api()
    sim.joint_command(LEFT_COMMAND, 'left', TORQUE, ['left_s1'], [5.0], 0.0, 0.0)
    assert efforts(sim.cycle(0.01))['left_s1'] == 5.0
    assert efforts(sim.cycle(1.0))['left_s1'] < -20.0   # timed out: held in position mode


def test_a_moving_arm_has_a_twist_a_still_one_none():
    sim = make_api()
    assert not sim.cycle(0.01).endpoints['left'].twist.any()
    sim.joint_command(LEFT_COMMAND, 'left', 4, ['left_s0'], [1.0], 0.01, 0.0)
    endpoint = sim.cycle(0.05).endpoints['left']
    arm = sim.model.arms['left']
    assert arm.velocities['left_s0'] > 0.5
    assert np.allclose(endpoint.twist[3:], [0.0, 0.0, arm.velocities['left_s0']])
    assert not sim.cycle(0.06).endpoints['right'].twist.any()


def test_a_torque_command_is_the_wrench_at_the_tool_point():
    sim = make_api()
    sim.cycle(0.0)
    jacobian = sim.statics['left'].jacobian(
        [sim.model.arms['left'].positions[n] for n in bd.arm_joint_names('left')])
    push = jacobian.T @ np.array([0.0, 0.0, -5.0, 0.0, 0.0, 0.0])
    sim.joint_command(LEFT_COMMAND, 'left', TORQUE, bd.arm_joint_names('left'), list(push),
                      0.0, 0.0)
    cycle = sim.cycle(1e-6)
    assert np.allclose(cycle.endpoints['left'].wrench, [0, 0, -5.0, 0, 0, 0], atol=1e-3)
    assert not cycle.endpoints['right'].wrench.any()


def test_a_publish_rate_above_the_loop_is_logged_with_the_rate_published():
    sim = api.BaxterApi(BaxterModel(bd.load(), 0.0), 0.2, loop_rate_hz=100.0)
    reply = sim.publish_rate(RATE, 500, 0.0)
    assert 'at 100 Hz' in reply.warning and reply.change is None
    assert all(sim.cycle(i / 100.0).joints is not None for i in range(1, 50))
    reply = sim.publish_rate(RATE, 25, 10.0)
    assert reply.warning is None and '25 Hz' in reply.change
    sent = [sim.cycle(1.0 + i / 100.0).joints is not None for i in range(100)]
    assert sum(sent) == 25
    assert all(sim.cycle(3.0 + i / 100.0).endpoints for i in range(4))   # still every cycle
    assert 'zero rate' in sim.publish_rate(RATE, 0, 20.0).warning


def test_feed_forward_and_custom_gripper_topics_are_refused_with_their_reasons():
    sim = make_api()
    topic = '/robot/limb/right/inverse_dynamics_command'
    line = sim.inverse_dynamics(topic, 'right', [0.0] * 7, [0.0] * 7, [], 0.0).warning
    assert 'kinematic' in line and topic in line
    assert 'not 7' in sim.inverse_dynamics(topic, 'right', [0.0], [], [], 0.1).warning
    props = '/robot/end_effector/left_gripper/rsdk/set_properties'
    line = sim.custom_gripper(props, 'left', 131073, 0.0).warning
    assert 'custom gripper' in line and 'electric gripper' in line and props in line
    assert sim.custom_gripper(props, 'left', 131073, 0.5).warning is None   # throttled
    state = '/robot/end_effector/left_gripper/rsdk/set_state'
    assert 'custom gripper' in sim.custom_gripper(state, 'left', 0, 0.6).warning
