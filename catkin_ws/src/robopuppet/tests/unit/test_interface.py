"""The interface table agrees with the messages and the wire it names, and is the only one."""
import ast
import pathlib

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


@pytest.mark.parametrize('topic, name, camera', [
    ('/cameras/room_camera/image/compressed', interface.CAMERA_COMPRESSED, 'room_camera'),
    ('/cameras/room_camera/image', interface.CAMERA_COMPRESSED, None),
    ('/cameras/a/b/image/compressed', interface.CAMERA_COMPRESSED, None),
    ('/cameras//image/compressed', interface.CAMERA_COMPRESSED, None),
    ('/robot/x/image/compressed', interface.CAMERA_COMPRESSED, None),
    ('/cameras/head_camera/camera_info', interface.CAMERA_INFO, 'head_camera'),
])
def test_camera_of_topic_inverts_camera_topic(topic, name, camera):
    assert interface.camera_of_topic(topic, name) == camera
    if camera:
        assert interface.camera_topic(camera, name) == topic


def test_node_names_are_the_launch_files():
    assert interface.node_param('arm', 'R', 'comm_rate') == '/arm_R/comm_rate'
    assert interface.ini_file_name('L') == 'arm_L.ini'
    assert interface.hand_camera('left') == 'left_hand_camera' in interface.BAXTER_CAMERAS


NAMESPACES = ('/robot', '/puppet', '/cameras', '/robopuppet', '/diagnostics', '/baxter_sim',
              '/ExternalTools', '/arm_', '/config_', '/serial_', '/rethink')


def test_only_the_interface_table_spells_a_topic_name():
    # One place per name: the library builds every topic, service and parameter name of the
    # system from interface.py.
    source = pathlib.Path(interface.__file__).parent
    found = []
    for path in sorted(source.rglob('*.py')):
        if path.name == 'interface.py':
            continue
        for node in ast.walk(ast.parse(path.read_text())):
            if (isinstance(node, ast.Constant) and isinstance(node.value, str)
                    and node.value.startswith(NAMESPACES) and '\n' not in node.value
                    and ' ' not in node.value):
                found.append('%s:%d %r' % (path.relative_to(source), node.lineno, node.value))
    assert found == []
