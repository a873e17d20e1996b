#!/usr/bin/python3
"""rostest, main_sim end to end: seeded garbage on every topic a robopuppet node subscribes.

The topics come from the master (getSystemState, getTopicTypes), so a subscription added later
is fuzzed too; the messages from message_garbage.MessageGarbage. While Baxter's right arm
follows the right puppet, every topic gets a burst of garbage; then, after a quiet second:
every node is still up with the same pid and nothing logged a traceback; every command the arm
controllers sent and every joint state of the stand-in was finite and within the URDF limits;
and, once the garbage's effects are undone (opmode, settings, Baxter's enable, speed ratio,
timeout, the follow buttons), every topic a node published periodically before it publishes
again (a periodic callback that died silently stops there), config_X answers get_config, the
recorder answers, and Baxter's right arm follows a puppet move.
"""
import collections
import math
import os
import threading
import time
import unittest
import xmlrpc.client

import rosgraph
import roslib.message
import rospy
import rostest
from baxter_core_msgs.msg import AssemblyState, DigitalOutputCommand, JointCommand
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty, Float64

from hand_pose import HAND_POSE
from message_garbage import MessageGarbage
from robopuppet import baxter_description, interface, settings
from robopuppet.baxter_sim.baxter_collision import cuff_input
from robopuppet_msgs.srv import GetConfig, Record, SetConfig
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

SEED = 20261124
GARBAGE_S = 4.0
QUIET_S = 1.0
WINDOW_S = 2.0        # the window in which the periodic publications are found
PERIODIC_COUNT = 3    # a (topic, publisher) seen this often in a window publishes periodically
# Each periodic publication must come again within this once the system is restored: a callback
# that died stays silent, while the loaded 2-core machine has stalled a simulated puppet for 3 s.
RESUME_S = 10.0
POSE_L = [0.3, -0.8, 0.4, 1.2, 0.2, 0.5, -0.2]   # test_main_sim_both.py's left pose
MOVED = list(HAND_POSE[:3]) + [HAND_POSE[3] + 0.4] + list(HAND_POSE[4:])   # clear of the zones
# No topic is skipped by name: those only ROS's own nodes subscribe (/rosout: rosout;
# /ghost/joint_states, /target/joint_states: robot_state_publisher) are not a robopuppet node's
# (is_robopuppet_node), and main_sim has no /clock.
LOGS = {'/rosout', '/rosout_agg'}   # not periodic work: lines come when there is news
ARM_NODES = ('/arm_L', '/arm_R')
MAX_LOG_CHARS = 2000


def master():
    return rosgraph.Master(rospy.get_name())


def node_pid(name):
    """Return the process id of a node, asked through its own XML-RPC API, or why not."""
    try:
        api = xmlrpc.client.ServerProxy(master().lookupNode(name))
        code, message, pid = api.getPid(rospy.get_name())
    except (OSError, rosgraph.MasterError) as error:
        return 'gone: %s' % error
    return pid if code == 1 else 'gone: %s' % message


def settled_system_state(still_s=2.0, timeout_s=30.0):
    """Return (publishers, subscribers) from the master once they have not changed for
    still_s: every node of the launch file has registered all of its topics."""
    deadline = time.monotonic() + timeout_s
    last, since = None, time.monotonic()
    while time.monotonic() < deadline:
        publishers, subscribers, _ = master().getSystemState()
        now = (sorted(map(str, publishers)), sorted(map(str, subscribers)))
        if now != last:
            last, since = now, time.monotonic()
        elif time.monotonic() - since >= still_s:
            return publishers, subscribers
        time.sleep(0.25)
    raise AssertionError('the master\'s system state did not settle in %.0f s' % timeout_s)


def is_robopuppet_node(pid):
    """True when the process runs an executable of this package (devel/lib/robopuppet/X or
    robopuppet/nodes/X), not a ROS node such as robot_state_publisher or rosout."""
    with open('/proc/%d/cmdline' % pid, 'rb') as cmdline:
        argv = cmdline.read().decode(errors='replace').split('\0')
    return any(os.path.basename(os.path.dirname(a)) in ('robopuppet', 'nodes')
               and '/robopuppet' in a for a in argv[:2])


class Traffic:
    """Reception times of every message on the given topics, by (topic, publisher).

    Create it after every typed subscriber of the test: rospy gives a topic one message class
    per process, the first subscriber's, so a later typed subscriber would get AnyMsg.
    """

    def __init__(self, topics):
        self._lock = threading.Lock()
        self._seen = collections.defaultdict(list)
        self._subs = [rospy.Subscriber(t, rospy.AnyMsg, self._on_msg, callback_args=t,
                                       queue_size=100) for t in topics]

    def _on_msg(self, msg, topic):
        with self._lock:
            self._seen[topic, msg._connection_header['callerid']].append(time.monotonic())

    def last(self, topic):
        """Return when the newest message on topic came (monotonic s), or None."""
        with self._lock:
            return max((times[-1] for (t, _), times in self._seen.items() if t == topic),
                       default=None)

    def seen(self, start, end, count=1):
        """Return the (topic, publisher) seen at least count times in [start, end]."""
        with self._lock:
            return {key for key, times in self._seen.items()
                    if sum(start <= t <= end for t in times) >= count}


class Watch:
    """Everything to check for the whole run: the arm controllers' commands, the stand-in's
    joint states, /rosout lines with a traceback and lines so long that garbage floods the
    log (a bad value belongs in a log line cut short, reprlib). Long lines are kept by node:
    ROS's own nodes on a fuzzed topic (diagnostic_aggregator on /diagnostics) log whole names,
    and only ours are held to the rule."""

    def __init__(self):
        self.lock = threading.Lock()
        self.commands, self.joints, self.tracebacks, self.long_lines = [], [], [], []
        for side in interface.BAXTER_SIDES:
            rospy.Subscriber(interface.limb_topic(side, 'joint_command'), JointCommand,
                             self._on_command, callback_args=side, queue_size=1000)
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_joints,
                         queue_size=1000)
        rospy.Subscriber('/rosout', Log, self._on_log, queue_size=1000)
        self.robot_state = None
        rospy.Subscriber(interface.ROBOT_STATE, AssemblyState, self._on_robot_state, queue_size=10)

    def _on_robot_state(self, msg):
        if msg._connection_header['callerid'] == '/baxter_sim':
            self.robot_state = msg

    def _on_command(self, msg, side):
        if msg._connection_header['callerid'] in ARM_NODES:
            with self.lock:
                self.commands.append((side, msg._connection_header['callerid'], msg))

    def _on_joints(self, msg):
        if msg._connection_header['callerid'] == '/baxter_sim':
            with self.lock:
                self.joints.append(msg)

    def _on_log(self, msg):
        if len(msg.msg) > MAX_LOG_CHARS and msg.name != rospy.get_name():
            with self.lock:
                self.long_lines.append((msg.name, '%s: %d characters: %s' % (
                    msg.name, len(msg.msg), msg.msg[:160])))
        if msg.level >= Log.ERROR and 'Traceback' in msg.msg:
            lines = msg.msg.splitlines()   # what failed, and where: the innermost frames
            with self.lock:
                self.tracebacks.append(
                    '%s: %s' % (msg.name, '\n'.join(lines[:1] + lines[-5:])))


class TopicGarbageTest(unittest.TestCase):
    maxDiff = None

    def test_garbage_on_every_subscribed_topic(self):
        watch = Watch()
        right, left, baxter = PuppetArm('R'), PuppetArm('L'), Baxter()
        for puppet in (right, left):
            wait_for(lambda: puppet.state() == interface.CALIBRATING, 60,
                     'arm_%s calibrating' % puppet.side)
            puppet.end_piece(False)
        calibrate(right, HAND_POSE)
        calibrate(left, POSE_L)
        self.follow(left, False, False)
        self.follow_until(right, baxter, HAND_POSE)
        stored = {side: self.get_config(side) for side in interface.PUPPET_SIDES}

        # Who is up and what they subscribe and publish, from the master.
        publishers, subscribers = settled_system_state()
        types = dict(master().getTopicTypes())
        me = rospy.get_name()
        nodes = {n for _, ns in subscribers + publishers for n in ns} - {me}
        pids = {n: node_pid(n) for n in nodes}
        ours = {n for n in nodes if is_robopuppet_node(pids[n])}
        fuzzed = {}   # topic -> its subscribers among our nodes
        for topic, subs in subscribers:
            mine = sorted(set(subs) & ours)
            if mine:
                fuzzed[topic] = mine
        per_node = collections.Counter(n for subs in fuzzed.values() for n in subs)
        rospy.loginfo('fuzzing %d topics; per node: %s', len(fuzzed), sorted(per_node.items()))
        traffic = Traffic(sorted({t for t, ns in publishers if set(ns) - {me}} - LOGS))
        start = time.monotonic()
        time.sleep(WINDOW_S)
        before = {k for k in traffic.seen(start, time.monotonic(), PERIODIC_COUNT)
                  if k[1] != me}

        # The garbage: every topic in turn, rounds until GARBAGE_S is over.
        garbage = MessageGarbage(SEED)
        pubs = {t: rospy.Publisher(t, roslib.message.get_message_class(types[t]),
                                   queue_size=100)
                for t in sorted(fuzzed)}
        for topic, pub in pubs.items():
            wait_for(lambda: pub.get_num_connections() >= len(fuzzed[topic]), 20,
                     'the subscribers of %s' % topic)
        sent, end = 0, time.monotonic() + GARBAGE_S
        while time.monotonic() < end:
            for topic, pub in pubs.items():
                pub.publish(garbage.message(pub.data_class))
                sent += 1
        rospy.loginfo('garbage: %d messages on %d topics in %.1f s', sent, len(pubs), GARBAGE_S)
        time.sleep(QUIET_S)

        # Every robopuppet node is still up, the same process; nothing died in a callback. ROS's
        # own are up again: Debian's robot_state_publisher aborts on a joint state stamped past
        # the end of ROS time ("Time is out of dual 32-bit range"); baxter_sim.launch respawns it.
        self.assertEqual({n: node_pid(n) for n in ours}, {n: pids[n] for n in ours})
        wait_for(lambda: all(isinstance(node_pid(n), int) for n in nodes - ours), 20,
                 "ROS's own nodes up: %s" % sorted(nodes - ours))
        with watch.lock:
            self.assertEqual(watch.tracebacks, [])
            self.assertEqual([line for name, line in watch.long_lines if name in ours], [])
            commands, joints = list(watch.commands), list(watch.joints)
        self.check_commands(commands)
        self.check_joints(joints)

        # Undo what the garbage may have changed, then the system works end to end.
        # config_X writes its file for every accepted setting: its queues may still hold
        # garbage. Restore once neither has stored a change for a second.
        stored_topics = ['%s/%s' % (interface.puppet_ns(side), interface.STORED_SETTINGS)
                         for side in interface.PUPPET_SIDES]
        wait_for(lambda: all(time.monotonic() - (traffic.last(t) or 0.0) > 1.0
                             for t in stored_topics), 30, 'config_X done with the garbage')
        self.restore(stored, right, left, pubs, watch)
        self.follow(left, False, False)
        right.hand(MOVED)
        self.follow_until(right, baxter, MOVED)
        start = time.monotonic()
        wait_for(lambda: not before - traffic.seen(start, time.monotonic()), RESUME_S)
        after = traffic.seen(start, time.monotonic())   # one message: the loop runs
        self.assertEqual(sorted(before - after), [], 'periodic publications that stopped')
        with watch.lock:
            self.assertEqual(watch.tracebacks, [])
            self.check_commands(watch.commands)

    # Checks.

    def check_commands(self, commands):
        limits = {s: {lim.name: lim for lim in baxter_description.arm_limits(s)}
                  for s in interface.BAXTER_SIDES}
        self.assertGreater(len(commands), 0)
        for side, node, msg in commands:
            self.assertIn(msg.mode, (JointCommand.POSITION_MODE, JointCommand.RAW_POSITION_MODE),
                          (node, msg))
            self.assertEqual(len(msg.names), len(msg.command), (node, msg))
            for name, value in zip(msg.names, msg.command):
                limit = limits[side].get(name)
                self.assertIsNotNone(limit, (node, side, name))
                self.assertTrue(math.isfinite(value) and limit.lower <= value <= limit.upper,
                                (node, name, value))

    def check_joints(self, joints):
        limits = {lim.name: lim for s in interface.BAXTER_SIDES
                  for lim in baxter_description.arm_limits(s)}
        self.assertGreater(len(joints), 0)
        for msg in joints:
            for name, position in zip(msg.name, msg.position):
                self.assertTrue(math.isfinite(position), (name, position))
                if name in limits:
                    self.assertTrue(limits[name].lower - 1e-9 <= position
                                    <= limits[name].upper + 1e-9, (name, position))

    # Putting things back.

    def get_config(self, side):
        """Return [GetConfigResponse] of joints 0..6 of config_<side>."""
        ns = interface.puppet_ns(side)
        get = rospy.ServiceProxy('%s/%s' % (ns, interface.GET_CONFIG), GetConfig)
        get.wait_for_service(10)
        return [get(joint) for joint in settings.JOINTS]

    def restore(self, stored, right, left, pubs, watch):
        """Undo the garbage's lasting effects: recording, settings, opmode, Baxter's state and
        cuffs, the operator's hands and end pieces."""
        for pub in pubs.values():
            pub.unregister()
        record = rospy.ServiceProxy('/puppet/record', Record)
        record(start=False, notes='')    # an episode button 4 garbage started, if any
        for puppet in (right, left):   # config_X refuses a new home or sign while one follows
            self.unfollow(puppet)
        for side in interface.PUPPET_SIDES:
            set_config = rospy.ServiceProxy('%s/%s' % (interface.puppet_ns(side),
                                                       interface.SET_CONFIG), SetConfig)
            for joint, old in zip(settings.JOINTS, stored[side]):
                # Twice, the first a little off: the second is a change that makes config_X
                # publish active_settings again, over any garbage serial_X took.
                for nudge in (1e-3, 0.0):
                    values = [getattr(old, n) for n in settings.NAMES]
                    values[settings.NAMES.index('pid_kd')] += nudge
                    answer = set_config(joint=joint, names=list(settings.NAMES), values=values)
                    self.assertTrue(answer.stored, (side, joint, answer.error))
            self.assertEqual(self.get_config(side), stored[side])
        for puppet, pose in ((right, HAND_POSE), (left, POSE_L)):
            puppet.set_opmode(interface.LIMP)
            puppet.end_piece(False)
            puppet.hand(pose)
        wait_for(lambda: right.teleop.opmode == left.teleop.opmode == interface.LIMP, 10,
                 'both arms limp')
        # The stand-in's simulated hand lets go of both cuffs (a squeeze holds an arm in zero-g).
        hand = rospy.Publisher(interface.SIM_DIGITAL_INPUT, DigitalOutputCommand, queue_size=2)
        wait_for(lambda: hand.get_num_connections() > 0, 10, 'the stand-in\'s simulated hand')
        for side in interface.BAXTER_SIDES:
            hand.publish(DigitalOutputCommand(name=cuff_input(side), value=False))
        reset = rospy.Publisher(interface.SET_SUPER_RESET, Empty, queue_size=1, latch=True)
        enable = rospy.Publisher(interface.SET_SUPER_ENABLE, Bool, queue_size=1, latch=True)
        ratios = [rospy.Publisher(interface.limb_topic(s, t), Float64, queue_size=1, latch=True)
                  for s in interface.BAXTER_SIDES
                  for t in ('set_speed_ratio', 'joint_command_timeout')]
        for pub, value in zip(ratios, [0.3, 0.2, 0.3, 0.2]):
            pub.publish(Float64(value))

        def enabled():
            state = watch.robot_state
            if state.stopped:
                reset.publish(Empty())
            elif not state.enabled:
                enable.publish(Bool(True))
            return state.enabled and not state.stopped
        wait_for(enabled, 10, 'Baxter enabled')
        # What the harness saw of the puppets includes the garbage: wait for the real joint
        # states and statuses again (serial_X republishes every status at its topic rate). The
        # garbage's settings may have made serial_X drop every frame as implausible and re-open
        # the port: the restored ones end that. Calibrate only if the device lost it.
        for puppet, pose in ((right, HAND_POSE), (left, POSE_L)):
            puppet.wait_sets(3, timeout_s=20)
            try:
                wait_for(lambda: puppet.statuses == [interface.WORKING] * settings.NUM_JOINTS,
                         5, 'puppet %s Working' % puppet.side)
            except AssertionError:
                calibrate(puppet, pose)

    def unfollow(self, puppet, timeout_s=30.0):
        """Press 2 and 3 on the puppet until no Baxter arm follows it (any state)."""
        deadline = time.monotonic() + timeout_s
        while puppet.teleop.follow_left or puppet.teleop.follow_right:
            if time.monotonic() > deadline:
                raise AssertionError('puppet %s still drives Baxter after %.0f s (%s)' % (
                    puppet.side, timeout_s, puppet.teleop))
            arm = 'follow_left' if puppet.teleop.follow_left else 'follow_right'
            puppet.press(interface.BUTTON_LEFT if arm == 'follow_left' else
                         interface.BUTTON_RIGHT)
            try:
                wait_for(lambda: not getattr(puppet.teleop, arm), 2,
                         'arm_%s letting go' % puppet.side)
            except AssertionError:
                pass   # the press came in a state that ignores it: pressed again

    def follow(self, puppet, follow_left, follow_right, timeout_s=30.0):
        """Press 2 and 3 on the puppet until it drives exactly the Baxter arms asked for.

        Pressed again after a fault: on the shared 2-core machine a puppet's state sets may
        come late enough (arm_X's 0.4 s) for a fault, after which only a new press follows.
        """
        deadline = time.monotonic() + timeout_s
        wanted = {'follow_left': follow_left, 'follow_right': follow_right}
        while True:
            wait_for(lambda: puppet.state() in (interface.READY, interface.FOLLOWING,
                                                interface.FAULT), deadline - time.monotonic(),
                     'puppet %s ready (%s)' % (puppet.side, puppet.teleop))
            wrong = [name for name, want in wanted.items()
                     if getattr(puppet.teleop, name) != want]
            if not wrong:
                return
            if time.monotonic() > deadline:
                raise AssertionError('puppet %s: %s not %s after %.0f s (%s)' % (
                    puppet.side, wrong, wanted, timeout_s, puppet.teleop))
            puppet.press(interface.BUTTON_LEFT if wrong[0] == 'follow_left'
                         else interface.BUTTON_RIGHT)
            # arm_X's answer, on teleop_state (a press it ignored is pressed again).
            wait_for(lambda: getattr(puppet.teleop, wrong[0]) == wanted[wrong[0]], 2.0)

    def follow_until(self, puppet, baxter, pose, timeout_s=45.0):
        """Make the puppet drive Baxter's right arm until the arm is on the puppet at pose."""
        deadline = time.monotonic() + timeout_s
        while True:
            self.follow(puppet, False, True, deadline - time.monotonic())
            try:
                wait_for(lambda: max_error(puppet.angles, pose) < 0.1
                         and max_error(baxter.arm('right'), puppet.angles) < 0.02,
                         min(10.0, deadline - time.monotonic()),
                         'the right arm following the puppet to %s' % pose)
                return
            except AssertionError:
                if time.monotonic() > deadline or puppet.teleop.follow_right:
                    raise


if __name__ == '__main__':
    rospy.init_node('test_topic_garbage')
    rostest.rosrun('robopuppet', 'topic_garbage', TopicGarbageTest)
