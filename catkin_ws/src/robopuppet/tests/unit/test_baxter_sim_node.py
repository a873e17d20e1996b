"""Tests of robopuppet.baxter_sim.baxter_sim_node without a ROS master: the messages of a cycle,
log lines and /robot/state of commands, the publishing loop's survival."""
import threading
import time

import pytest
import rospy
from baxter_core_msgs.msg import AnalogIOState, AssemblyState, HeadState
from roslib.message import get_message_class

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_api, baxter_topics
from robopuppet.baxter_sim.baxter_model import BaxterModel
from robopuppet.baxter_sim.baxter_publishers import CyclePublishers
from robopuppet.baxter_sim.baxter_sim_node import BaxterSimNode
from robopuppet.periodic import Guard, Loop


class Recorder:
    """A publisher that keeps what it is given; its first `failures` publishes raise."""

    def __init__(self, failures=0, data_class=None):
        self.messages, self.failures, self.data_class = [], failures, data_class

    def publish(self, msg):
        if self.failures:
            self.failures -= 1
            raise OverflowError('a value too large for the message')
        self.messages.append(msg)


@pytest.fixture(name='node')
def fixture_node(monkeypatch):
    """The node around a disabled model, with recording publishers and logs, without a master."""
    node = BaxterSimNode.__new__(BaxterSimNode)
    node._lock, node._state_lock = threading.Lock(), threading.Lock()
    node._api = baxter_api.BaxterApi(BaxterModel(bd.load(), 0.0, gripper_calibrated=True), 0.2)
    node._guard = Guard('/baxter_sim', node._log_failure)
    node._state_pub = Recorder()
    node._publishers = publishers = CyclePublishers.__new__(CyclePublishers)
    publishers.joints = Recorder()
    publishers.endpoints = {side: Recorder() for side in ('left', 'right')}
    publishers.grippers = {side: Recorder() for side in ('left', 'right')}
    publishers.io = {topic: Recorder(data_class=get_message_class(kind))
                     for topic, kind in baxter_topics.io_publications()}
    node.logs = []
    for level in ('logwarn', 'loginfo', 'logerr'):
        monkeypatch.setattr(rospy, level, lambda text, *args, level=level: node.logs.append(
            (level, text % args)))
    monkeypatch.setattr(rospy, 'get_rostime', lambda: rospy.Time(12, 500000000))
    return node


def test_a_cycle_publishes_stamped_joints_endpoints_and_grippers(node):
    node._loop_once()
    joints = node._publishers.joints.messages[-1]
    assert joints.header.stamp == rospy.Time(12, 500000000)
    assert len(joints.name) == len(joints.position) == len(joints.velocity) == len(joints.effort)
    positions = dict(zip(joints.name, joints.position))
    for side in ('left', 'right'):
        endpoint = node._publishers.endpoints[side].messages[-1]
        assert endpoint.header.frame_id == 'base' and endpoint.header.stamp == joints.header.stamp
        (x, y, z), (qx, qy, qz, qw) = bd.load().pose(positions, '%s_gripper' % side)
        p, o = endpoint.pose.position, endpoint.pose.orientation
        assert (p.x, p.y, p.z, o.x, o.y, o.z, o.w) == (x, y, z, qx, qy, qz, qw)
        gripper = node._publishers.grippers[side].messages[-1]
        assert gripper.timestamp == joints.header.stamp and gripper.id == baxter_api.GRIPPER_ID
        assert gripper.position == 100.0 and gripper.calibrated and not gripper.enabled
    assert node._state_pub.messages == []   # /robot/state every fifth cycle only
    for _ in range(4):
        node._loop_once()
    assert len(node._state_pub.messages) == 1


def test_commands_log_refusals_and_publish_changes_of_the_robot_state(node):
    enable = '/robot/set_super_enable'
    node._command(node._api.set_enabled, enable, True)
    node._command(node._api.set_enabled, enable, True)          # a repeat: no line, no state
    node._command(node._api.stop, '/robot/set_super_stop')
    node._command(node._api.set_enabled, enable, True)          # refused while stopped
    assert [level for level, _ in node.logs] == ['loginfo', 'loginfo', 'logwarn']
    assert node.logs[0][1] == 'robot enabled' and node.logs[1][1] == 'robot stopped'
    assert node.logs[2][1].startswith('refused on /robot/set_super_enable: cannot enable')
    enabled, stopped = node._state_pub.messages
    assert enabled.enabled and enabled.ready and not enabled.stopped
    assert stopped.stopped and not stopped.enabled
    assert stopped.estop_source == AssemblyState.ESTOP_SOURCE_USER


def test_the_publishing_loop_survives_an_exception_and_logs_the_count(node):
    node._publishers.joints = Recorder(failures=2)
    loop = Loop(node._guard, 'publishing loop', 0.005, node._loop_once).start()
    deadline = time.monotonic() + 10.0
    while len(node._publishers.joints.messages) < 10 and time.monotonic() < deadline:
        time.sleep(0.01)
    loop.stop()
    assert len(node._publishers.joints.messages) >= 10   # it kept running after the exceptions
    assert node._guard.errors == 2
    errors = [text for level, text in node.logs if level == 'logerr']
    assert len(errors) == 1                     # the second one within 5 s is counted, not logged
    assert 'OverflowError' in errors[0] and '[1 failures in all since start]' in errors[0]


def test_a_cycle_publishes_every_io_and_head_state_with_its_type(node):
    node._loop_once()
    for topic, kind in baxter_topics.io_publications():
        messages = node._publishers.io[topic].messages
        assert len(messages) == 1 and messages[0]._type == kind, topic
    cuff = node._publishers.io['/robot/digital_io/left_lower_cuff/state'].messages[0]
    assert (cuff.state, cuff.isInputOnly) == (0, True)
    light = node._publishers.io['/robot/digital_io/torso_right_outer_light/state'].messages[0]
    assert light.isInputOnly is False
    analog = node._publishers.io['/robot/analog_io/left_hand_range/state'].messages[0]
    assert isinstance(analog, AnalogIOState) and analog.timestamp == rospy.Time(12, 500000000)
    head = node._publishers.io['/robot/head/head_state'].messages[0]
    assert isinstance(head, HeadState) and head.isPanEnabled and head.pan == 0.0
