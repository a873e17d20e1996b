"""The interface table agrees with the messages and the wire it names."""
import pytest

from robopuppet import interface, settings
from robopuppet.protocol import codec
from robopuppet_msgs.msg import JointSettings, TeleopState
from robopuppet_msgs.srv import GetConfigResponse


def test_teleop_states_are_the_messages_constants():
    constants = (TeleopState.NO_ROBOT, TeleopState.CALIBRATING, TeleopState.READY,
                 TeleopState.FOLLOWING, TeleopState.FAULT)
    assert interface.TELEOP_STATES == constants


def test_wire_codes_index_the_enumerations():
    assert interface.OPMODES[codec.LIMP] == interface.LIMP == 'limp'
    assert interface.OPMODES[codec.HOLD] == interface.HOLD == 'hold'
    assert interface.ENC_STATUS[codec.WORKING] == interface.WORKING
    assert interface.ENC_STATUS[codec.UNCALIBRATED] == interface.UNCALIBRATED
    assert interface.END_PIECE_GRIPPER in range(interface.NUM_GRIPPERS)


def test_settings_messages_carry_the_settings_table_in_order():
    assert tuple(GetConfigResponse.__slots__) == settings.NAMES
    assert tuple(JointSettings.__slots__) == ('joint',) + settings.NAMES


def test_names():
    assert interface.puppet_ns('R') == '/puppet/arm_R'
    assert interface.sim_ns('L') == '/puppet_sim/arm_L'
    assert interface.joint_topic('L', 3, 'enc_stat') == '/puppet/arm_L/joint_3/enc_stat'
    assert interface.gripper_topic('R', 3) == '/puppet/arm_R/gripper_3'
    assert [interface.BAXTER_SIDE[s] for s in interface.PUPPET_SIDES] == list(
        interface.BAXTER_SIDES)


def test_baxter_topics_are_rethinks():
    assert interface.limb_topic('left', 'joint_command') == '/robot/limb/left/joint_command'
    assert interface.baxter_gripper_topic('right', 'command') == \
        '/robot/end_effector/right_gripper/command'


@pytest.mark.parametrize('side', ['X', 'l', '', None, 'left'])
def test_a_bad_side_is_refused(side):
    with pytest.raises(ValueError, match="'L' or 'R'"):
        interface.puppet_ns(side)
