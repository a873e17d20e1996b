"""arm_X (robot host): drives Baxter from one puppet arm through Baxter's API (arm.controller)."""
import gc
import threading
import time

import rospy
from baxter_core_msgs.msg import AssemblyState, EndEffectorState
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String, UInt8

from robopuppet import interface as ifc, settings
from robopuppet.arm import arm_params, command_loop, link_topics, teleop_topics
from robopuppet.link_recovery import LinkRecovery
from robopuppet.periodic import Guard
from robopuppet_msgs.msg import ArmSettings, AssistTarget, TeleopState


class ArmNode:
    """Wire robopuppet.arm.controller.ArmController to its topics: each topic to its input.

    Every controller call is made under one lock; steps run on fresh puppet joint states and at
    least at ~command_rate; arm.command_loop sends their actions (its watchdog faults a stall).

    ROS API (<ns>: interface.puppet_ns(~arm_side), e.g. /puppet/arm_R; <side>: left, right):
      Subscribes: <ns>/joint_states (by name joint_0..joint_6; tagged in header.frame_id with
        their angle settings, arm.angle_settings), <ns>/joint_J/enc_stat, <ns>/heartbeat,
        <ns>/user_btn (button 1 cycles the opmode limp -> hold -> feel -> limp), <ns>/gripper_3
        (the end-piece button), <ns>/opmode (the opmode others set, adopted; its own messages
        and repeats change nothing), <ns>/stored_settings (config_X's, latched: a change of an
        angle setting stops following), <ns>/assist_target (the assist's prediction of the other
        Baxter arm: arm.assist_follow), the other puppet's teleop_state, /robot/state,
        /robot/joint_states, /robot/end_effector/<side>_gripper/state.
      Publishes: /robot/limb/<side>/joint_command (position mode), /robot/set_super_enable,
        /robot/end_effector/<side>_gripper/command, <ns>/opmode (limp, hold, feel),
        <ns>/joint_J/setpoint (std_msgs/Float32, rad: Baxter's pose on entering hold; in feel
        Baxter's pose mapped back, once per puppet sample; arm.opmode); <ns>/teleop_state, its
        /diagnostics status and the keep-out zone markers (arm.teleop_topics).
      The link to the operator host (arm.link_topics): publishes <ns>/link_ping, <ns>/link_state
        and its /diagnostics status, subscribes <ns>/link_echo; after a cut, link_recovery
        connects anew once <ns>/joint_states or <ns>/link_echo is stuck.
      Parameters (arm.arm_params): ~arm_side ('L' or 'R', required), ~command_rate (Hz, 100,
        at least 10), ~comm_rate (Hz, 10: the puppet's state-set rate; the state timeout follows,
        arm.timing), ~heartbeat_timeout (s, 2.5), ~approach_speed (rad/s, 0.5, capped per joint
        by the URDF's velocity limit), ~max_sample_age (s, 0.35: an older puppet sample on
        arrival is dropped, so that Baxter never follows more than 0.5 s late; before the first
        echo, and 3 s after the last, no age is known: nothing follows; arm.timing),
        ~zones_file (str, '' for none; e.g. config/zones.yaml: keep-out zones that cut every
        command of a following arm, docs/zones.md; a bad file stops the node).
    """

    def __init__(self):
        side = ifc.check_side(rospy.get_param('~arm_side'))
        self._name, ns = 'arm_' + side, ifc.puppet_ns(side)
        self._lock, self._guard = threading.Lock(), Guard(self._name, rospy.logerr)
        self._core, period_s, zones = arm_params.make_controller(side, self._guard, self._name)
        core, self._report = self._core, teleop_topics.TeleopTopics(ns, zones, self._name)
        self._steps = command_loop.CommandLoop(side, core, self._lock, self._guard, period_s,
                                               self._report.publish, self._name)
        inputs = [  # (topic, type, take(monotonic now, message)): the controller's inputs
            (ns + '/' + ifc.STORED_SETTINGS, ArmSettings, self._on_stored_settings),
            (ns + '/' + ifc.HEARTBEAT, Empty, lambda t, m: core.on_heartbeat(t)),
            (ns + '/' + ifc.USER_BUTTON, UInt8, lambda t, m: core.on_button(m.data)),
            (ifc.gripper_topic(side, ifc.END_PIECE_GRIPPER), Float32,
             lambda t, m: core.on_end_piece(m.data)),
            (ns + '/' + ifc.ASSIST_TARGET, AssistTarget, lambda t, m: core.on_assist_target(
                t, m.side, m.position, m.gripper_closed, m.hold, m.detail)),
            (ifc.puppet_ns(*set(ifc.PUPPET_SIDES) - {side}) + '/' + ifc.TELEOP_STATE, TeleopState,
             lambda t, m: core.on_other_puppet(t, m.follow_left, m.follow_right)),
            (ifc.ROBOT_STATE, AssemblyState,
             lambda t, m: core.on_robot_state(t, m.enabled, m.stopped, m.error)),
            (ifc.ROBOT_JOINT_STATES, JointState, lambda t, m: core.on_robot_joints(
                t, m.name, m.position, m.velocity,  # the age from the stamp:
                (rospy.Time.now() - m.header.stamp).to_sec() if m.header.stamp else 0.0))]
        inputs += [(ifc.joint_topic(side, j, 'enc_stat'), String,
                    lambda t, m, j=j: core.on_status(j, m.data)) for j in settings.JOINTS]
        for topic, kind, take in inputs:
            rospy.Subscriber(topic, kind, lambda m, take=take: self._call(take, m), queue_size=10)
        rospy.Subscriber(ns + '/' + ifc.JOINT_STATES, JointState, lambda m: self._call(
            self._on_joint_states, m, link_topics.ros_now_s()),  # received: before the lock
            queue_size=10, tcp_nodelay=True)
        rospy.Subscriber(ns + '/' + ifc.OPMODE, String, self._on_opmode, ns + '/' + ifc.OPMODE,
                         queue_size=10)
        for s in ifc.BAXTER_SIDES:
            rospy.Subscriber(ifc.baxter_gripper_topic(s, 'state'), EndEffectorState, lambda m, s=s:
                             self._call(self._on_gripper_state, s, m), queue_size=1)
        self._loops = self._steps.loops + [
            link_topics.LinkTopics(ns, core, self._lock, self._guard, self._name).loop,
            LinkRecovery(self._name, [ns + '/' + ifc.JOINT_STATES, ns + '/' + ifc.LINK_ECHO]).loop]
        core.done(time.monotonic())  # the stall watch counts from here, not from the set-up
        for loop in self._loops:
            loop.start()
        rospy.on_shutdown(self._shut_down)

    def _shut_down(self):
        """Stop the loops, then send the last teleop_state (TeleopTopics.shut_down)."""
        for loop in self._loops:
            loop.stop()
        with self._lock:
            self._report.shut_down()

    def _call(self, take, *args):
        """Call take(now, *args) under the lock (now: monotonic s); log a problem it returns."""
        with self._lock:
            problem = take(time.monotonic(), *args)
        if problem:
            rospy.logwarn_throttle(5, '%s: %s', self._name, problem)

    def _on_joint_states(self, now, msg, received_s):
        taken, problem = self._core.on_joint_states(
            now, msg.name, msg.position, msg.header.stamp.to_sec(), received_s, msg.header.frame_id)
        if problem:
            rospy.logwarn_throttle(5, '%s: %s', self._name, problem)
        if taken:  # act on fresh data at once
            self._guard.call('step on joint states', self._steps.step, now)

    def _on_stored_settings(self, now, msg):
        news = self._core.on_stored_settings([(j.joint, {n: getattr(j, n) for n in (
            settings.ANGLE_SETTINGS)}) for j in msg.joints])
        if news:
            rospy.logwarn('%s: %s (revision %d from %s)', self._name, news, msg.revision,
                          msg._connection_header.get('callerid'))
            self._guard.call('step on stored settings', self._steps.step, now)

    def _on_opmode(self, msg, topic):
        """Adopt the opmode others set; this node's own messages come back here too: skipped."""
        if msg._connection_header.get('callerid') == rospy.get_name():
            return
        with self._lock:
            problem = self._core.on_opmode(msg.data)
        if problem:
            rospy.logwarn('%s: %s on %s', self._name, problem, topic)

    def _on_gripper_state(self, now, side, msg):
        calibrated = msg.calibrated == EndEffectorState.STATE_TRUE
        for calibrate in self._core.on_gripper_state(now, side, msg.id, calibrated):
            rospy.loginfo("%s: calibrating Baxter's %s gripper", self._name, side)
            self._steps.carry_out(calibrate)


def main():
    """Run the arm controller until shutdown."""
    rospy.init_node('arm')
    try:
        ArmNode()
    except (KeyError, ValueError) as error:
        rospy.logfatal('arm node cannot start: %s', error)
        raise SystemExit(1)
    # Start-up's objects live as long as the node: a full gc then stops ~0.2 ms, not ~12 ms.
    gc.freeze()
    rospy.spin()
