"""The baxter_sim node's publishers of Baxter's state: a baxter_api.Cycle as messages.

A ROS adapter beside baxter_sim_node: it builds messages and publishes them, and decides nothing.
"""
import functools

import rospy
from baxter_core_msgs.msg import EndEffectorProperties, EndEffectorState, EndpointState
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3, Wrench
from roslib.message import get_message_class
from sensor_msgs.msg import JointState
from std_msgs.msg import Header

from robopuppet import baxter_description as bd, interface
from robopuppet.baxter_sim import baxter_api as api, baxter_topics as topics
from robopuppet.interface import BAXTER_SIDES


class CyclePublishers:
    """Publish each cycle's states; latch the grippers' properties once, at construction.

    Publishes: /robot/joint_states (at the joint_state_publish_rate),
    /robot/limb/<side>/endpoint_state (frame base; twist and wrench of baxter_statics),
    /robot/end_effector/<side>_gripper/state and properties (latched), and every
    baxter_topics.io_publications() topic (each arm's collision_avoidance_state too). Logs
    (info) each cycle's notes: suppressions and zero-g as they change.
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
        if cycle.joints is not None:   # None: not due at the joint_state_publish_rate
            self.joints.publish(JointState(Header(stamp=stamp), *cycle.joints))
        for side, (xyz, quaternion) in cycle.poses.items():
            twist, wrench = ((cycle.endpoints[side].twist, cycle.endpoints[side].wrench)
                             if cycle.endpoints else ((0.0,) * 6, (0.0,) * 6))
            self.endpoints[side].publish(EndpointState(
                header=Header(stamp=stamp, frame_id=bd.BASE_FRAME),
                pose=Pose(Point(*xyz), Quaternion(*quaternion)),
                twist=Twist(Vector3(*twist[:3]), Vector3(*twist[3:])),
                wrench=Wrench(Vector3(*wrench[:3]), Vector3(*wrench[3:]))))
        for side, fields in cycle.grippers.items():
            self.grippers[side].publish(EndEffectorState(timestamp=stamp, **fields))
        for topic, fields in cycle.io.items():
            kind = self.io[topic].data_class
            if 'timestamp' in kind.__slots__:
                fields = dict(fields, timestamp=stamp)
            elif 'header' in kind.__slots__:   # CollisionAvoidanceState
                fields = dict(fields, header=Header(stamp=stamp))
            self.io[topic].publish(kind(**fields))
        for line in cycle.notes:   # baxter_collision's suppressions and zero-g, as they change
            rospy.loginfo('%s', line)
