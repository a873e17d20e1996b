"""Tests of robopuppet.baxter_sim.baxter_io and baxter_ik, and of the model's velocity and torque
modes: digital IO and navigators, the head's pan speed and nod, IK round trips."""
import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_ik, baxter_io
from robopuppet.baxter_sim.baxter_joint_command import TORQUE_MODE, VELOCITY_MODE
from robopuppet.baxter_sim.baxter_model import BaxterModel
from robopuppet.baxter_sim.baxter_refusals import CommandError, NotEnabledError

DESC = bd.load()


def enabled_model():
    model = BaxterModel(DESC, 0.0)
    model.set_enabled(True)
    return model


def test_a_command_switches_a_light_and_a_press_an_input():
    io = baxter_io.DigitalIO()
    io.command('left_inner_light', True)
    io.press('right_lower_cuff', True)
    states = io.digital_states()
    assert states['left_inner_light'] == dict(state=1, isInputOnly=False)
    assert states['right_lower_cuff'] == dict(state=1, isInputOnly=True)
    assert states['left_lower_cuff']['state'] == 0
    assert io.navigator_states()['left']['lights'] == [True, False]


@pytest.mark.parametrize('call, name, value, reason', [
    ('command', 'left_lower_cuff', True, 'input only'),
    ('press', 'left_inner_light', True, 'not an input'),
    ('command', 'left_itb_light_inner', True, 'unknown component'),
    ('press', 'left_lower_cuff', 1, 'bad value'),
])
def test_bad_io_commands_change_nothing(call, name, value, reason):
    io = baxter_io.DigitalIO()
    before = io.digital_states()
    with pytest.raises(CommandError) as error:
        getattr(io, call)(name, value)
    assert error.value.reason == reason and io.digital_states() == before


def test_the_torso_fan_is_an_analog_output_the_range_sensors_inputs():
    analog = baxter_io.AnalogIO()
    assert analog.states()['torso_fan'] == dict(value=0.0, isInputOnly=False)
    analog.command('torso_fan', 100)
    assert analog.states()['torso_fan']['value'] == 100.0
    assert analog.states()['left_hand_range'] == dict(value=baxter_io.RANGE_NOTHING_IN_REACH,
                                                      isInputOnly=True)


@pytest.mark.parametrize('name, value, reason', [
    ('torso_fan', 101, 'bad value'),
    ('torso_fan', -1, 'bad value'),
    ('torso_fan', 50.0, 'bad value'),
    ('torso_fan', True, 'bad value'),
    ('left_hand_range', 10, 'input only'),
    ('x' * 10 ** 5, 10, 'unknown component'),
])
def test_bad_analog_commands_change_nothing(name, value, reason):
    analog = baxter_io.AnalogIO()
    analog.command('torso_fan', 40)
    before = analog.states()
    with pytest.raises(CommandError) as error:
        analog.command(name, value)
    assert error.value.reason == reason and analog.states() == before
    assert len(str(error.value)) < 200


def test_navigator_buttons_follow_their_inputs():
    io = baxter_io.DigitalIO()
    io.press('torso_left_button_back', True)
    state = io.navigator_states()['torso_left']
    assert state['buttons'] == [False, True, False]
    # SDK 1.2's NavigatorState names them; baxter_interface finds the lights by name.
    assert (state['button_names'], state['light_names']) == (['ok', 'back', 'show'],
                                                           ['inner', 'outer'])


def test_the_head_pans_at_the_commanded_speed_and_stops_at_the_target():
    model = enabled_model()
    model.head_pan(1.0, 0.5, baxter_io.REQUEST_PAN_VOID)
    model.step(0.5)
    speed = 0.5 * DESC.limit(bd.HEAD_PAN).velocity
    assert model.head.pan_rad == pytest.approx(0.5 * speed)
    assert model.head.state()['isTurning']
    model.step(5.0)
    assert model.head.pan_rad == 1.0 and not model.head.state()['isTurning']


def test_the_head_refuses_bad_pan_commands_and_obeys_pan_disable():
    model = enabled_model()
    for args in ((float('nan'), 1.0, 2), (0.5, 1.5, 2), (0.5, 0.5, 7)):
        with pytest.raises(CommandError):
            model.head_pan(*args)
    model.head_pan(0.5, 1.0, baxter_io.REQUEST_PAN_DISABLE)
    model.step(2.0)
    assert model.head.pan_rad == 0.0 and not model.head.state()['isPanEnabled']
    model.set_enabled(False)
    with pytest.raises(NotEnabledError):
        model.head_pan(0.5, 1.0, baxter_io.REQUEST_PAN_ENABLE)


def test_a_nod_lasts_its_duration():
    model = enabled_model()
    model.head.command_nod(True)
    model.step(0.1)
    assert model.head.state()['isNodding']
    model.step(0.1 + baxter_io.NOD_DURATION_S)
    assert not model.head.state()['isNodding']


def test_velocity_mode_integrates_within_limits_and_times_out():
    model = enabled_model()
    arm = model.arms['left']
    start = arm.positions['left_e1']
    t = 0.0
    while t < 0.5 - 1e-9:      # commands at 100 Hz, 0.4 rad/s
        model.joint_command('left', VELOCITY_MODE, ['left_e1'], [0.4], t)
        t = round(t + 0.01, 9)
        model.step(t)
    assert arm.positions['left_e1'] == pytest.approx(start + 0.2, abs=1e-6)
    assert arm.velocities['left_e1'] == pytest.approx(0.4)
    model.step(t + 0.1)        # still within the 0.2 s command timeout: moves on
    model.step(t + 2.0)        # commands stopped: it held 0.2 s after the last one (at 0.49 s)
    assert arm.positions['left_e1'] == pytest.approx(start + 0.2 + 0.4 * 0.19, abs=1e-6)
    model.step(t + 2.1)
    assert arm.velocities['left_e1'] == 0.0
    model.joint_command('left', VELOCITY_MODE, ['left_e1'], [99.0], 3.0)   # clamped to 1.5
    model.step(3.1)
    assert arm.velocities['left_e1'] == pytest.approx(DESC.limit('left_e1').velocity)


def test_velocity_mode_stops_at_the_joint_limit():
    model = enabled_model()
    for i in range(200):
        model.joint_command('left', VELOCITY_MODE, ['left_s0'], [1.5], i * 0.01)
        model.step((i + 1) * 0.01)
    assert model.arms['left'].positions['left_s0'] == DESC.limit('left_s0').upper


def test_torque_mode_moves_a_damped_joint_and_reports_the_effort():
    model = enabled_model()
    arm = model.arms['left']
    start = arm.positions['left_w0']
    model.joint_command('left', TORQUE_MODE, ['left_w0'], [7.5], 0.0)   # half of 15 N m
    model.step(0.1)
    assert arm.positions['left_w0'] == pytest.approx(start + 0.5 * 4.0 * 0.1)
    names, _, _, efforts = model.joint_state()
    assert dict(zip(names, efforts))['left_w0'] == 7.5
    model.step(1.0)
    assert dict(zip(*model.joint_state()[::3]))['left_w0'] == 0.0   # timed out: holds


@pytest.mark.parametrize('side', ['left', 'right'])
def test_ik_round_trip_reaches_random_reachable_poses_within_1_mm(side):
    ik = baxter_ik.ArmIK(DESC, side)
    rng = np.random.default_rng(7)
    tip = bd.gripper_link(side)
    for _ in range(15):
        q = rng.uniform(ik.lower + 0.1, ik.upper - 0.1)
        xyz, quaternion = DESC.pose(dict(zip(ik.names, q)), tip)
        answer = ik.solve_seeded(xyz, quaternion, {}, bd.neutral_pose(side), baxter_ik.SEED_AUTO)
        assert answer.positions is not None and answer.result_type != baxter_ik.RESULT_INVALID
        solved = dict(zip(ik.names, answer.positions))
        for name, value in solved.items():
            limit = DESC.limit(name)
            assert limit.lower <= value <= limit.upper
        xyz2, quaternion2 = DESC.pose(solved, tip)
        assert np.linalg.norm(np.subtract(xyz2, xyz)) < 1e-3
        assert abs(np.dot(quaternion2, quaternion)) > 1 - 1e-5


def test_ik_seeded_at_the_answer_reports_the_user_seed():
    ik = baxter_ik.ArmIK(DESC, 'left')
    pose = dict(bd.neutral_pose('left'), left_s0=0.3)
    xyz, quaternion = DESC.pose(pose, 'left_gripper')
    answer = ik.solve_seeded(xyz, quaternion, pose, bd.neutral_pose('left'), baxter_ik.SEED_AUTO)
    assert answer.result_type == baxter_ik.SEED_USER


@pytest.mark.parametrize('xyz, quaternion', [
    ((2.0, 0.0, 0.5), (0.0, 1.0, 0.0, 0.0)),      # far out of reach
    ((0.0, 0.26, 0.12), (0.0, 0.0, 0.0, 1.0)),    # inside the shoulder
])
def test_ik_reports_unreachable_poses_invalid(xyz, quaternion):
    answer = baxter_ik.ArmIK(DESC, 'left').solve_seeded(
        xyz, quaternion, {}, bd.neutral_pose('left'), baxter_ik.SEED_AUTO)
    assert answer.positions is None and answer.result_type == baxter_ik.RESULT_INVALID


@pytest.mark.parametrize('xyz, quaternion', [((float('nan'), 0, 0), (0, 0, 0, 1)),
                                             ((0.5, 0.5, 0.2), (0, 0, 0, 0))])
def test_ik_refuses_unusable_poses(xyz, quaternion):
    with pytest.raises(ValueError):
        baxter_ik.ArmIK(DESC, 'left').solve_seeded(xyz, quaternion, {}, bd.neutral_pose('left'),
                                                   baxter_ik.SEED_AUTO)
