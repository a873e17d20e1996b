"""The baxter_sim node's publishers of Baxter's state: a baxter_api.Cycle as messages.

A ROS adapter beside baxter_sim_node: it builds messages and publishes them, and decides nothing.
"""
import functools

import rospy
from baxter_core_msgs.msg import EndEffectorProperties, EndEffectorState, EndpointState
from geometry_msgs.msg import Point, Pose, Quaternion
from roslib.message import get_message_class
from sensor_msgs.msg import JointState
from std_msgs.msg import Header

from robopuppet import baxter_description as bd, interface
from robopuppet.baxter_sim import baxter_api as api, baxter_topics as topics
from robopuppet.interface import BAXTER_SIDES


class CyclePublishers:
    """Publish each cycle's states; latch the grippers' properties once, at construction.

    Publishes: /robot/joint_states, /robot/limb/<side>/endpoint_state (frame base),
    /robot/end_effector/<side>_gripper/state and properties (latched), and every
    baxter_topics.io_publications() topic.
    """

    def __init__(self):
        self.joints = rospy.Publisher(interface.ROBOT_JOINT_STATES, JointState, queue_size=10)
        self.endpoints, self.grippers = {}, {}
        for side in BAXTER_SIDES:
            self.endpoints[side] = rospy.Publisher(
                interface.limb_topic(side, 'endpoint_state'), EndpointState, queue_size=10)
            grip = functools.partial(interface.baxter_gripper_topic, side)
            self.grippers[side] = rospy.Publisher(grip('state'), EndEffectorState, queue_size=10)
            rospy.Publisher(grip('properties'), EndEffectorProperties, queue_size=1, latch=True
                            ).publish(EndEffectorProperties(**api.gripper_properties(side)))
        self.io = {topic: rospy.Publisher(topic, get_message_class(kind), queue_size=10)
                   for topic, kind in topics.io_publications()}

    def publish(self, cycle, stamp):
        """Publish a baxter_api.Cycle's states (but /robot/state), stamped `stamp` (rospy.Time)."""
        names, positions, velocities, efforts = cycle.joints
        self.joints.publish(JointState(Header(stamp=stamp), names, positions, velocities,
                                       efforts))
        for side, (xyz, quaternion) in cycle.poses.items():
            self.endpoints[side].publish(EndpointState(
                header=Header(stamp=stamp, frame_id=bd.BASE_FRAME),
                pose=Pose(Point(*xyz), Quaternion(*quaternion))))
        for side, fields in cycle.grippers.items():
            self.grippers[side].publish(EndEffectorState(timestamp=stamp, **fields))
        for topic, fields in cycle.io.items():
            kind = self.io[topic].data_class
            if 'timestamp' in kind.__slots__:
                fields = dict(fields, timestamp=stamp)
            self.io[topic].publish(kind(**fields))
