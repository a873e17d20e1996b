"""Tests of robopuppet.baxter_sim.baxter_publishers without a ROS master: a Cycle as messages."""
import rospy
from roslib.message import get_message_class

from robopuppet import interface
from robopuppet.baxter_sim import baxter_topics as topics
from robopuppet.baxter_sim.baxter_api import Cycle
from robopuppet.baxter_sim.baxter_publishers import CyclePublishers

STAMP = rospy.Time(3, 500)


class Recorder:
    """A publisher that keeps what it is given."""

    def __init__(self, data_class=None):
        self.messages, self.data_class = [], data_class

    def publish(self, msg):
        self.messages.append(msg)


def test_a_cycle_is_published_stamped_field_for_field():
    pubs = CyclePublishers.__new__(CyclePublishers)
    pubs.joints = Recorder()
    pubs.endpoints = {'left': Recorder()}
    pubs.grippers = {'left': Recorder()}
    pubs.io = {topic: Recorder(get_message_class(kind)) for topic, kind in topics.io_publications()}
    analog = interface.analog_io_state_topic('left_hand_range')
    cycle = Cycle((['a', 'b'], [1.0, 2.0], [0.1, 0.2], [0.0, 3.0]),
                  {'left': ((0.5, 0.25, 0.125), (0.0, 0.0, 0.0, 1.0))},
                  {'left': dict(id=7, position=42.0)}, False,
                  {analog: dict(value=5.0, isInputOnly=True),
                   interface.HEAD_STATE: dict(pan=0.5, isTurning=True)})
    pubs.publish(cycle, STAMP)
    (joints,) = pubs.joints.messages
    assert joints.header.stamp == STAMP and joints.name == ['a', 'b']
    assert (joints.position, joints.velocity, joints.effort) == ([1.0, 2.0], [0.1, 0.2],
                                                                 [0.0, 3.0])
    (endpoint,) = pubs.endpoints['left'].messages
    assert endpoint.header.frame_id == 'base' and endpoint.header.stamp == STAMP
    assert (endpoint.pose.position.z, endpoint.pose.orientation.w) == (0.125, 1.0)
    (gripper,) = pubs.grippers['left'].messages
    assert (gripper.timestamp, gripper.id, gripper.position) == (STAMP, 7, 42.0)
    (range_state,) = pubs.io[analog].messages
    assert range_state.timestamp == STAMP and range_state.value == 5.0   # stamped: it has one
    (head,) = pubs.io[interface.HEAD_STATE].messages
    assert head.pan == 0.5 and head.isTurning
