"""arm_X (robot host): drives Baxter from one puppet arm through Baxter's API (arm.controller)."""
import functools
import gc
import threading
import time

import rosgraph
import rospy
from baxter_core_msgs.msg import (AssemblyState, EndEffectorCommand, EndEffectorState,
                                  JointCommand)
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty, Float32, String, UInt8

from robopuppet import baxter_description, interface as ifc, params, settings
from robopuppet.arm import (baxter_upkeep, controller, link_topics, opmode as puppet_mode,
                            timing, zone_topics)
from robopuppet.link_recovery import LinkRecovery, answers
from robopuppet.periodic import Guard, Loop
from robopuppet_msgs.msg import ArmSettings, TeleopState

MIN_COMMAND_RATE_HZ = 10.0   # Baxter drops a position command after 0.2 s; keep well inside it
WATCHDOG_PERIOD_S = 0.05     # the watchdog thread checks the command loop this often


def param(name, default, minimum=0.0):
    """Return the private parameter ~name as a positive float (ValueError: it is not one)."""
    return params.positive('~' + name, rospy.get_param('~' + name, default), minimum)


class ArmNode:
    """Follow the puppet with Baxter's arms and grippers; drive the puppet in hold and feel.

    Steps run on puppet joint states and at least at ~command_rate, on a command loop checked by
    a watchdog thread (robopuppet.periodic: exceptions are logged, counted and survived).

    ROS API (<ns>: interface.puppet_ns(~arm_side), e.g. /puppet/arm_R; <side>: left, right):
      Subscribes: <ns>/joint_states (by name joint_0..joint_6), <ns>/joint_J/enc_stat,
        <ns>/heartbeat, <ns>/user_btn (button 1 cycles the opmode limp -> hold -> feel -> limp),
        <ns>/gripper_3 (the end-piece button), <ns>/opmode (std_msgs/String: the opmode others
        set, adopted; its own messages and repeats change nothing), <ns>/stored_settings
        (config_X's, latched: a change of an angle setting stops following; a joint_states
        tagged in header.frame_id with other angle settings is not followed, see
        arm.angle_settings), the other puppet's teleop_state, /robot/state,
        /robot/joint_states, /robot/end_effector/<side>_gripper/state.
      Publishes: /robot/limb/<side>/joint_command (position mode), /robot/set_super_enable,
        /robot/end_effector/<side>_gripper/command, <ns>/opmode (limp, hold, feel),
        <ns>/joint_J/setpoint (std_msgs/Float32, rad: Baxter's pose on entering hold; in feel
        Baxter's pose mapped back, once per puppet sample; see arm.opmode), <ns>/teleop_state
        (latched; zone_left/zone_right name a zone holding an arm back), /diagnostics (name
        'arm_X: teleoperation', hardware_id <ns>).
      The link to the operator host (arm.link_topics): publishes <ns>/link_ping
        (robopuppet_msgs/LinkPing, 10 Hz, tcp_nodelay) and subscribes <ns>/link_echo (serial_X
        answers each ping with its own clock); publishes <ns>/link_state (robopuppet_msgs/
        LinkState, 5 Hz) and /diagnostics (name 'arm_X: operator-robot link', hardware_id <ns>).
        After a cut, link_recovery connects anew to the operator host's publishers once
        <ns>/joint_states or <ns>/link_echo is stuck and the host answers again.
      Parameters: ~arm_side ('L' or 'R', required), ~command_rate (Hz, 100, at least 10),
        ~comm_rate (Hz, 10: the puppet's state-set rate; the state timeout follows from it, see
        arm.timing), ~heartbeat_timeout (s, 2.5), ~approach_speed (rad/s, 0.5, capped per joint
        by the URDF's velocity limit), ~max_sample_age (s, 0.35: a puppet sample older than this
        on arrival is dropped, never followed, so that Baxter never follows more than 0.5 s
        late; no usable sample for the state timeout stops Baxter following; see arm.timing;
        before the first echo, and 3 s after the last, no age is known: nothing follows),
        ~zones_file (str, '' for none; e.g. the package's config/zones.yaml: keep-out zones that
        cut every command of a following arm, docs/zones.md; a bad file stops the node).
      Keep-out zones: publishes interface.ZONE_MARKERS (/robopuppet/keepout_zones,
        visualization_msgs/MarkerArray, latched; again, the zone holding an arm back
        highlighted, when that changes); teleop_state's detail names the zone and link that
        hold an arm back.
    """

    def __init__(self):
        side = ifc.check_side(rospy.get_param('~arm_side'))
        self._name, ns = 'arm_' + side, ifc.puppet_ns(side)
        self._period_s = 1.0 / param('command_rate', 100.0, MIN_COMMAND_RATE_HZ)
        rate = timing.state_timeout(param('comm_rate', ifc.DEFAULT_COMM_RATE_HZ))
        bound = timing.sample_age_bound(param('max_sample_age', timing.DEFAULT_MAX_SAMPLE_AGE_S))
        for told in (rate, bound):
            (rospy.loginfo if told.meets_stop else rospy.logwarn)('%s: %s', self._name,
                                                                   told.describe())
        self._lock, self._guard = threading.Lock(), Guard(self._name, rospy.logerr)
        self._last_opmode = ''
        path = zone_topics.zones_file()
        zone_guards, found = zone_topics.load_guards(path)
        rospy.loginfo('%s: %d keep-out zones%s', self._name, len(found),
                      ' from %s' % path if path else ' (~zones_file is empty)')
        self._core = core = controller.ArmController(
            side, {s: baxter_description.arm_limits(s) for s in ifc.BAXTER_SIDES}, rate,
            param('heartbeat_timeout', ifc.HEARTBEAT_TIMEOUT_S), param('approach_speed', 0.5),
            self._period_s, self._guard, time.monotonic(), bound, zone_guards)
        self._zone_view = zone_topics.publish_zones(found, self._name)
        pub, sub = (functools.partial(f, queue_size=10) for f in (rospy.Publisher,
                                                                  rospy.Subscriber))
        arm = {s: pub(ifc.limb_topic(s, 'joint_command'), JointCommand, tcp_nodelay=True)
               for s in ifc.BAXTER_SIDES}
        gripper = {s: pub(ifc.baxter_gripper_topic(s, 'command'), EndEffectorCommand)
                   for s in ifc.BAXTER_SIDES}
        enable, opmode = pub(ifc.SET_SUPER_ENABLE, Bool), pub(ns + '/' + ifc.OPMODE, String)
        setpoints = [pub(ifc.joint_topic(side, j, 'setpoint'), Float32) for j in settings.JOINTS]
        self._do = {  # how each kind of action goes out
            controller.Enable: lambda a: enable.publish(Bool(True)),
            controller.ArmCommand: lambda a: arm[a.side].publish(JointCommand(
                mode=JointCommand.POSITION_MODE, command=a.angles, names=a.names)),
            puppet_mode.SetOpmode: lambda a: opmode.publish(String(a.mode)),
            puppet_mode.SetSetpoints: lambda a: [p.publish(Float32(angle))
                                                 for p, angle in zip(setpoints, a.angles)],
            baxter_upkeep.GripperCommand: lambda a: gripper[a.side].publish(EndEffectorCommand(
                id=a.id, command=a.command, args=a.args, sender=rospy.get_name(),
                sequence=a.sequence)),
            controller.Report: self._publish}
        self._pub_state = pub(ns + '/' + ifc.TELEOP_STATE, TeleopState, latch=True)
        self._pub_diag = pub(ifc.DIAGNOSTICS, DiagnosticArray)
        call, tp, (other,) = self._call, core.teleop, set(ifc.PUPPET_SIDES) - {side}
        for j in settings.JOINTS:
            sub(ifc.joint_topic(side, j, 'enc_stat'), String,
                lambda m, j=j: call(core.on_status, j, m.data))
        sub(ns + '/' + ifc.JOINT_STATES, JointState, lambda m: call(  # received: before the lock
            self._on_joint_states, m, link_topics.ros_now_s()), tcp_nodelay=True)
        sub(ns + '/' + ifc.STORED_SETTINGS, ArmSettings,
            lambda m: call(self._on_stored_settings, m))
        sub(ns + '/' + ifc.HEARTBEAT, Empty, lambda m: call(tp.on_heartbeat))
        sub(ns + '/' + ifc.OPMODE, String, lambda m: self._on_opmode(m, ns + '/' + ifc.OPMODE))
        sub(ns + '/' + ifc.USER_BUTTON, UInt8, lambda m: call(tp.on_button, m.data))
        sub(ifc.gripper_topic(side, ifc.END_PIECE_GRIPPER), Float32,
            lambda m: call(tp.on_end_piece, m.data))
        sub(ifc.puppet_ns(other) + '/' + ifc.TELEOP_STATE, TeleopState,
            lambda m: call(tp.on_other_puppet, m.follow_left, m.follow_right))
        sub(ifc.ROBOT_STATE, AssemblyState,
            lambda m: call(core.baxter.on_robot_state, m.enabled, m.stopped, m.error))
        sub(ifc.ROBOT_JOINT_STATES, JointState, lambda m: call(
            core.on_robot_joints, m.name, m.position, m.velocity,  # the age from the stamp:
            (rospy.Time.now() - m.header.stamp).to_sec() if m.header.stamp else 0.0))
        for s in ifc.BAXTER_SIDES:
            sub(ifc.baxter_gripper_topic(s, 'state'), EndEffectorState,
                lambda m, s=s: call(self._on_gripper_state, s, m), queue_size=1)
        self._loops = [Loop(self._guard, 'command loop', self._period_s / 2,
                            lambda: call(self._on_timer)),
                       Loop(self._guard, 'watchdog', WATCHDOG_PERIOD_S, self._watch),
                       link_topics.LinkTopics(ns, core, call, self._guard, self._name).loop,
                       LinkRecovery(self._name, [ns + '/' + ifc.JOINT_STATES,
                                                 ns + '/' + ifc.LINK_ECHO]).loop]
        core.done(time.monotonic())  # the stall watch counts from here, not from the set-up
        for loop in self._loops:
            loop.start()
        rospy.on_shutdown(self._shut_down)

    def _shut_down(self):
        """Stop the loops, then tell the operator host why nothing follows any more: a last
        teleop_state (fault) and a log line; Baxter holds on its command timeout."""
        for loop in self._loops:
            loop.stop()
        with self._lock:
            master_gone = not answers(rosgraph.get_master_uri())
            detail = ('%s stopped: %s; Baxter holds where it is until %s runs again' % (
                self._name, 'the ROS master does not answer (roslaunch stops its nodes with it)'
                if master_gone else 'shut down', self._name))
            (rospy.logwarn if master_gone else rospy.loginfo)('%s', detail)
            msg = TeleopState(state=ifc.FAULT, opmode=self._last_opmode, detail=detail)
            msg.header.stamp = rospy.Time.now()
            self._pub_state.publish(msg)

    def _call(self, method, *args):
        """Return method(now, *args) with the lock held (now: monotonic s)."""
        with self._lock:
            return method(time.monotonic(), *args)

    def _on_joint_states(self, now, msg, received_s):
        taken, problem = self._core.on_joint_states(now, msg.name, msg.position,
                                                    msg.header.stamp.to_sec(), received_s,
                                                    msg.header.frame_id)
        if problem:
            rospy.logwarn_throttle(5, '%s: %s', self._name, problem)
        if taken:  # act on fresh data at once
            self._guard.call('step on joint states', self._step, now)

    def _on_stored_settings(self, now, msg):
        news = self._core.on_stored_settings(now, [(j.joint, {n: getattr(j, n) for n in (
            settings.ANGLE_SETTINGS)}) for j in msg.joints])
        if news:
            rospy.logwarn('%s: %s (revision %d from %s)', self._name, news, msg.revision,
                          msg._connection_header.get('callerid'))
            self._guard.call('step on stored settings', self._step, now)

    def _on_opmode(self, msg, topic):
        """Adopt the opmode others set; this node's own messages come back here too: skipped."""
        if msg._connection_header.get('callerid') == rospy.get_name():
            return
        problem = self._call(self._core.teleop.on_opmode, msg.data)
        if problem:
            rospy.logwarn('%s: %s on %s', self._name, problem, topic)

    def _on_gripper_state(self, now, side, msg):
        calibrated = msg.calibrated == EndEffectorState.STATE_TRUE
        for calibrate in self._core.on_gripper_state(now, side, msg.id, calibrated):
            rospy.loginfo("%s: calibrating Baxter's %s gripper", self._name, side)
            self._do[type(calibrate)](calibrate)

    def _on_timer(self, now):
        if self._core.step_due(now):
            self._step(now)

    def _watch(self):
        """Fault the teleop when the command loop has not completed a step for a while."""
        wait_s = controller.STALL_PERIODS * self._period_s
        if not self._lock.acquire(timeout=wait_s):   # starved or stuck: the stall is faulted
            rospy.logerr_throttle(5, '%s: the command loop holds its lock for over %.2f s',
                                  self._name, wait_s)   # once it lets go (core.stall)
            return
        try:
            why = self._core.stall(time.monotonic())
            if why:
                rospy.logerr_throttle(5, '%s: command loop failed: %s', self._name, why)
                self._step(time.monotonic())
        finally:
            self._lock.release()

    def _step(self, now):
        """Run one step and carry it out (lock held); a failure faults the next step."""
        try:
            for action in self._core.step(now):
                self._do[type(action)](action)
        except Exception as error:
            self._core.failed(now, error)
            raise
        self._core.done(now)

    def _publish(self, r):
        if r.changed:
            rospy.loginfo('%s: %s (%s)', self._name, r.state, r.detail)
        self._last_opmode = r.opmode
        msg = TeleopState(state=r.state, follow_left=r.follow_left, follow_right=r.follow_right,
                          opmode=r.opmode, heartbeat_age=r.heartbeat_age_s, detail=r.detail,
                          zone_left=r.zone_left, zone_right=r.zone_right)
        msg.header.stamp = rospy.Time.now()
        self._pub_state.publish(msg)
        self._zone_view.show(time.monotonic(), r.zone_left, r.zone_right)  # never raises
        self._pub_diag.publish(DiagnosticArray(header=msg.header, status=[DiagnosticStatus(
            level=getattr(DiagnosticStatus, r.level), name=r.diag_name, message=r.message,
            hardware_id=r.hardware_id, values=[KeyValue(k, v) for k, v in r.values])]))


def main():
    """Run the arm controller until shutdown."""
    rospy.init_node('arm')
    try:
        ArmNode()
    except (KeyError, ValueError) as error:
        rospy.logfatal('arm node cannot start: %s', error)
        raise SystemExit(1)
    # What start-up made lives as long as the node: out of the cyclic collector's way, a full
    # collection (now and then) stops every thread for ~0.2 ms instead of ~12 ms.
    gc.freeze()
    rospy.spin()
