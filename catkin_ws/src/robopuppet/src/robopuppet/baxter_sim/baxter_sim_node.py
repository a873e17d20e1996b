"""ROS node baxter_sim: a kinematic Baxter stand-in that speaks Baxter's own ROS API.

Motion is baxter_model's, every decision baxter_api's: this adapter only wires them to topics
and converts messages. Callbacks and the publishing loop run through a robopuppet.periodic Guard.
"""
import functools
import sys
import threading
import time

import rospkg
import rospy
from baxter_core_msgs.msg import (AssemblyState, EndEffectorCommand, EndEffectorProperties,
                                  EndEffectorState, EndpointState, JointCommand)
from baxter_core_msgs.srv import SolvePositionIK, SolvePositionIKResponse
from roslib.message import get_message_class
from geometry_msgs.msg import Point, Pose, Quaternion
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty, Float64, Header

from robopuppet import baxter_description as bd, interface, params
from robopuppet.baxter_sim import baxter_api as api
from robopuppet.baxter_sim.baxter_contact import arm_contacts
from robopuppet.baxter_sim.baxter_model import BaxterModel
from robopuppet.interface import BAXTER_SIDES
from robopuppet.periodic import Guard, Loop
from robopuppet.world import obstacles

SWITCH_INTERVAL_S = 0.0005


def _param(name, default, check):
    return check(rospy.resolve_name(name), rospy.get_param(name, default))


def _contacts(description, urdf_text):
    """Return the arms' ArmContacts with the ~obstacles_file's obstacles: {} when there are
    none, and {} with an error logged when the file cannot be used."""
    value = rospy.get_param('~obstacles_file', None)
    try:
        if value is not None and not isinstance(value, str):
            raise ValueError('~obstacles_file must be a file path, got %r' % (value,))
        path = obstacles.chosen_path(value, rospkg.RosPack().get_path('robopuppet'))
        shapes = obstacles.load_obstacles(path) if path else []
        contacts = arm_contacts(description, urdf_text, shapes)
    except ValueError as error:   # also ObstacleFileError and arm_capsules.CapsuleError
        rospy.logerr('baxter_sim: running without obstacles: %s', error)
        return {}
    rospy.loginfo('baxter_sim: %s', 'obstacles from %s: %s' % (
        path, ', '.join(s.name for s in shapes)) if shapes else 'no obstacles')
    return contacts


class BaxterSimNode:
    """Publish Baxter's state and obey its commands, through BaxterApi and BaxterModel.

    ROS API (docs/baxter_sim.md has the types and units):
      Subscribes: /robot/set_super_enable, _reset, _stop; /robot/limb/<side>/joint_command,
        set_speed_ratio, joint_command_timeout; /robot/end_effector/<side>_gripper/command;
        baxter_api.IO_SUBSCRIPTIONS (digital outputs, head pan and nod, /baxter_sim/digital_input).
      Publishes every cycle: /robot/joint_states, /robot/limb/<side>/endpoint_state (frame base),
        /robot/end_effector/<side>_gripper/state and every baxter_api.io_publications() topic;
        /robot/state (latched, rate_hz/5 and on change), gripper properties (latched).
      Serves: /ExternalTools/<side>/PositionKinematicsNode/IKService (SolvePositionIK).
      Sets: /rethink/software_version = '1.2.0'.
      Logs: a refused command, at most every 2 s per topic and reason; an exception in a
        callback or the loop (both go on), with the count of failures since start.
      Parameters: /robot_description (URDF text; the package's urdf/baxter.urdf when unset),
        ~rate_hz (float, 100), ~joint_command_timeout (float s, 0.2, initial value for both
        arms), ~gripper_calibrated (bool, false: like the real grippers after power-up),
        ~obstacles_file (str, unset: the package's config/obstacles.yaml when it exists; '':
        none): shapes that block the arms (a file that cannot be used is logged as an error
        and the node runs without obstacles).
    """

    def __init__(self):
        """Read and check the parameters (ValueError naming an unusable one), then wire up."""
        text = rospy.get_param('/robot_description', None)
        try:
            if not text:
                with open(bd.urdf_path(rospkg.RosPack().get_path('robopuppet'))) as urdf:
                    text = urdf.read()
            description = bd.Description(text)
        except (OSError, bd.DescriptionError) as error:
            raise ValueError('parameter /robot_description: %s' % error) from error
        self._rate_hz = _param('~rate_hz', 100.0, params.positive)
        timeout_s = _param('~joint_command_timeout', 0.2, params.positive)
        calibrated = _param('~gripper_calibrated', False, api.bool_param)
        self._lock = threading.Lock()         # the api and model, between loop and callbacks
        self._state_lock = threading.Lock()   # orders /robot/state messages like the changes
        self._guard = Guard(rospy.get_name(), self._log_failure)
        self._api = api.BaxterApi(BaxterModel(description, rospy.get_time(),
                                              gripper_calibrated=calibrated,
                                              contacts=_contacts(description, text)), timeout_s)
        rospy.set_param(interface.SOFTWARE_VERSION_PARAM, api.SOFTWARE_VERSION)
        self._state_pub = rospy.Publisher(interface.ROBOT_STATE, AssemblyState, queue_size=1,
                                          latch=True)
        self._joint_pub = rospy.Publisher(interface.ROBOT_JOINT_STATES, JointState, queue_size=10)
        self._endpoint_pub, self._gripper_pub = {}, {}
        a, data = self._api, lambda m: (m.data,)
        self._io_pub = {topic: rospy.Publisher(topic, get_message_class(kind), queue_size=10)
                        for topic, kind in api.io_publications()}
        for topic, kind, method, names in api.IO_SUBSCRIPTIONS:
            self._subscribe(topic, get_message_class(kind), getattr(a, method), None,
                            lambda m, names=names: tuple(getattr(m, n) for n in names))
        for side in BAXTER_SIDES:
            limb, grip = (functools.partial(f, side)
                          for f in (interface.limb_topic, interface.baxter_gripper_topic))
            self._endpoint_pub[side] = rospy.Publisher(limb('endpoint_state'), EndpointState,
                                                       queue_size=10)
            self._gripper_pub[side] = rospy.Publisher(grip('state'), EndEffectorState,
                                                      queue_size=10)
            properties = EndEffectorProperties(**api.gripper_properties(side))
            rospy.Publisher(grip('properties'), EndEffectorProperties, queue_size=1,
                            latch=True).publish(properties)
            self._subscribe(limb('joint_command'), JointCommand, a.joint_command, side,
                            lambda m: (m.mode, m.names, m.command, rospy.get_time()))
            self._subscribe(limb('set_speed_ratio'), Float64, a.speed_ratio, side, data)
            self._subscribe(limb('joint_command_timeout'), Float64, a.command_timeout, side, data)
            self._subscribe(grip('command'), EndEffectorCommand, a.gripper_command, side,
                            lambda m: (m.id, m.command, m.args, m.sender, m.sequence))
            rospy.Service(api.ik_service(side), SolvePositionIK,
                          functools.partial(self._solve_ik, side))
        self._subscribe(interface.SET_SUPER_ENABLE, Bool, a.set_enabled, None, data)
        self._subscribe(interface.SET_SUPER_RESET, Empty, a.reset, None, lambda m: ())
        self._subscribe(interface.SET_SUPER_STOP, Empty, a.stop, None, lambda m: ())
        self._publish_state()

    def _subscribe(self, topic, msg_type, command, side, fields):
        """Subscribe: a message runs command(topic, [side,] *fields(msg), wall_s) in the Guard."""
        head = (topic,) if side is None else (topic, side)

        def guarded(msg):
            self._guard.call(topic, self._command, command, *head, *fields(msg))
        rospy.Subscriber(topic, msg_type, guarded, queue_size=10)

    def _solve_ik(self, side, request):
        """Answer a SolvePositionIK: one solution (or isValid false) per pose, seeded."""
        with self._lock:
            current = self._api.model.positions()
        poses = [(p.header.frame_id, (p.pose.position.x, p.pose.position.y, p.pose.position.z),
                  (p.pose.orientation.x, p.pose.orientation.y, p.pose.orientation.z,
                   p.pose.orientation.w)) for p in request.pose_stamp]
        seeds = [dict(zip(seed.name, seed.position)) for seed in request.seed_angles]
        answers, problems = self._api.solve_ik(side, poses, seeds, request.seed_mode, current)
        for text in problems:
            self._command(self._api.ik_refused, api.ik_service(side), text)
        return SolvePositionIKResponse(
            [JointState(name=a.names, position=a.positions or []) for a in answers],
            [a.positions is not None for a in answers], bytes(a.result_type for a in answers))

    def _log_failure(self, text):
        """Log a callback's or the loop's exception (the Guard throttles and counts them)."""
        rospy.logerr('%s [%d failures in all since start]', text, self._guard.errors)

    def _command(self, command, *args):
        with self._lock:
            reply = command(*args, time.monotonic())
        if reply.warning:
            rospy.logwarn('%s', reply.warning)
        if reply.change:
            rospy.loginfo('%s', reply.change)
            self._publish_state()

    def _publish_state(self):
        # Read and publish under one lock: the loop and the enable callbacks both publish, and
        # the latched message must be the newest state, never an older one published late.
        with self._state_lock:
            with self._lock:
                state = self._api.robot_state()
            self._state_pub.publish(AssemblyState(**state))

    def _loop_once(self):
        if rospy.is_shutdown():
            return
        stamp = rospy.get_rostime()
        with self._lock:
            cycle = self._api.cycle(stamp.to_sec())
        names, positions, velocities, efforts = cycle.joints
        self._joint_pub.publish(JointState(Header(stamp=stamp), names, positions, velocities,
                                           efforts))
        for side, (xyz, quaternion) in cycle.poses.items():
            self._endpoint_pub[side].publish(EndpointState(
                header=Header(stamp=stamp, frame_id=bd.BASE_FRAME),
                pose=Pose(Point(*xyz), Quaternion(*quaternion))))
        for side, fields in cycle.grippers.items():
            self._gripper_pub[side].publish(EndEffectorState(timestamp=stamp, **fields))
        for topic, fields in cycle.io.items():
            kind = self._io_pub[topic].data_class
            if 'timestamp' in kind.__slots__:
                fields = dict(fields, timestamp=stamp)
            self._io_pub[topic].publish(kind(**fields))
        if cycle.state_due:
            self._publish_state()

    def spin(self):
        """Step and publish at rate_hz (on a Loop thread) until shutdown."""
        loop = Loop(self._guard, 'publishing loop', 1.0 / self._rate_hz, self._loop_once)
        rospy.on_shutdown(loop.stop)
        loop.start()
        rospy.spin()
        loop.stop()


def main():
    """Run the baxter_sim node."""
    # The publishing loop must wake on time: let it take the GIL from subscriber threads within
    # 0.5 ms instead of Python's default 5 ms.
    sys.setswitchinterval(SWITCH_INTERVAL_S)
    rospy.init_node('baxter_sim')
    try:
        node = BaxterSimNode()
    except (ValueError, rospkg.ResourceNotFound) as error:
        rospy.logfatal('baxter_sim cannot start: %s', error)
        raise SystemExit(1)
    node.spin()
