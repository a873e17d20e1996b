"""ROS node baxter_sim: a kinematic Baxter stand-in that speaks Baxter's own ROS API.

Motion is baxter_model's, every decision baxter_api's, every topic baxter_topics', the parameters
baxter_params' and the state messages baxter_publishers': this adapter wires them to topics.
Callbacks and the publishing loop run through a robopuppet.periodic Guard.
"""
import functools
import sys
import threading
import time

import rospkg
import rospy
from baxter_core_msgs.msg import AssemblyState
from baxter_core_msgs.srv import SolvePositionIK, SolvePositionIKResponse
from roslib.message import get_message_class
from sensor_msgs.msg import JointState

from robopuppet import interface
from robopuppet.baxter_sim import baxter_api as api, baxter_topics as topics
from robopuppet.baxter_sim.baxter_params import api_from_params
from robopuppet.baxter_sim.baxter_publishers import CyclePublishers
from robopuppet.interface import BAXTER_SIDES
from robopuppet.periodic import Guard, Loop

SWITCH_INTERVAL_S = 0.0005


class BaxterSimNode:
    """Publish Baxter's state and obey its commands, through BaxterApi and BaxterModel.

    ROS API (docs/baxter_sim.md has the types and units):
      Subscribes: /robot/set_super_enable, _reset, _stop; /robot/limb/<side>/joint_command,
        set_speed_ratio, joint_command_timeout, inverse_dynamics_command; the grippers' command,
        rsdk/set_*; IO, head, joint_state_publish_rate, /baxter_sim/digital_input (baxter_topics).
      Publishes every cycle: /robot/joint_states (or at its publish rate), endpoint_state (base),
        /robot/end_effector/<side>_gripper/state and every baxter_topics.io_publications() topic
        (baxter_publishers); /robot/state (latched, rate_hz/5 and on change), gripper properties
        (latched).
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
        self._api, self._rate_hz = api_from_params()
        self._lock = threading.Lock()         # the api and model, between loop and callbacks
        self._state_lock = threading.Lock()   # orders /robot/state messages like the changes
        self._guard = Guard(rospy.get_name(), self._log_failure)
        rospy.set_param(interface.SOFTWARE_VERSION_PARAM, api.SOFTWARE_VERSION)
        self._state_pub = rospy.Publisher(interface.ROBOT_STATE, AssemblyState, queue_size=1,
                                          latch=True)
        self._publishers = CyclePublishers()
        for sub in topics.subscriptions():
            self._subscribe(sub)
        for side in BAXTER_SIDES:
            rospy.Service(interface.ik_service(side), SolvePositionIK,
                          functools.partial(self._solve_ik, side))
        self._publish_state()

    def _subscribe(self, sub):
        """Subscribe: a message runs the api's sub.method in the Guard (see Subscription)."""
        command = getattr(self._api, sub.method)
        head = (sub.topic,) if sub.side is None else (sub.topic, sub.side)

        def guarded(msg):
            args = head + tuple(getattr(msg, field) for field in sub.fields)
            if sub.timed:
                args += (rospy.get_time(),)
            self._guard.call(sub.topic, self._command, command, *args)
        rospy.Subscriber(sub.topic, get_message_class(sub.kind), guarded, queue_size=10)

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
            self._command(self._api.ik_refused, interface.ik_service(side), text)
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
        self._publishers.publish(cycle, stamp)
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
