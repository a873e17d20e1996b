#!/usr/bin/python3
"""rostest: arm_R on the robot host (robot.launch: the real arm_R and the Baxter stand-in) with
this test as the operator host, whose clock runs SKEW_S ahead and whose samples a network
delays.

The test stands in for serial_R: it stamps joint_states on its skewed clock, answers arm_R's
pings on link_echo (as serial_X does) and holds each sample back a configurable delay before
publishing it. Before its first echo nothing follows; with fresh samples Baxter follows after
button 3; with the delay grown past max_sample_age (60 ms more per sample, so that no gap
between samples reaches the state timeout) arm_R drops the late samples and faults once no
usable one came for the state timeout, naming the stream stale with the newest one's age,
LinkState says network and shows the age, and Baxter's commands stop; with the delay gone
nothing moves until a new press, and then Baxter approaches slowly. LinkState's clock offset is
SKEW_S within rtt / 2.
"""
import math
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String, UInt8

from robopuppet import baxter_description, interface, settings
from robopuppet_msgs.msg import LinkPing, LinkState, TeleopState
from teleop_harness import Baxter, max_error
from waiting import wait_for

SIDE = 'R'
SKEW_S = 100.0            # the operator host's clock minus the robot host's
DELAY_S = 0.6             # the network's delay once it has grown past max_sample_age
GROW_S = 0.06             # ... growing by this much per sample
MAX_SAMPLE_AGE_S = 0.35   # arm.launch's default
APPROACH_RAD_S = 0.5      # arm_X's default approach speed
NEUTRAL = [baxter_description.NEUTRAL_POSE[s] for s in baxter_description.ARM_JOINT_SUFFIXES]
# Raised from neutral (s1 -0.3): 7 cm or more from config/zones.yaml's zones up to POSE_B.
POSE_A = [a + d for a, d in zip(NEUTRAL, (0.1, -0.3, -0.1, 0.1, 0.1, -0.1, 0.1))]
POSE_B = [a + d for a, d in zip(POSE_A, (0.0, 0.0, 0.0, 0.4, 0.0, 0.0, 0.0))]


class OperatorHost:
    """serial_R's part as arm_R sees it, on a clock SKEW_S ahead, behind a delaying network."""

    def __init__(self):
        ns = interface.puppet_ns(SIDE) + '/'
        self.angles, self.button, self.delay_s, self.grow_s = list(POSE_A), 0, 0.0, 0.0
        self.echo = False
        self._lock, self._queue, self._stop = threading.Lock(), [], threading.Event()
        self._states = rospy.Publisher(ns + interface.JOINT_STATES, JointState, queue_size=50,
                                       tcp_nodelay=True)
        self._echo = rospy.Publisher(ns + interface.LINK_ECHO, LinkPing, queue_size=50,
                                     tcp_nodelay=True)
        self._heartbeat = rospy.Publisher(ns + interface.HEARTBEAT, Empty, queue_size=10)
        self._button = rospy.Publisher(ns + interface.USER_BUTTON, UInt8, queue_size=10)
        self._end_piece = rospy.Publisher(
            interface.gripper_topic(SIDE, interface.END_PIECE_GRIPPER), Float32, queue_size=10)
        self._status = [rospy.Publisher(interface.joint_topic(SIDE, j, 'enc_stat'), String,
                                        queue_size=10) for j in settings.JOINTS]
        rospy.Subscriber(ns + interface.LINK_PING, LinkPing, self._on_ping, queue_size=50,
                         tcp_nodelay=True)
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    @staticmethod
    def clock():
        """Return the operator host's clock: ROS time SKEW_S ahead."""
        return rospy.Time.now() + rospy.Duration(SKEW_S)

    def _on_ping(self, msg):
        if self.echo and not self._stop.is_set():
            self._echo.publish(LinkPing(seq=msg.seq, sent=msg.sent, echoed=self.clock()))

    def press(self, button):
        """Hold a button for three state sets, then let go."""
        self.button = button
        time.sleep(0.35)
        self.button = 0

    def _run(self):
        next_s = beat_s = time.monotonic()
        while not self._stop.is_set() and not rospy.is_shutdown():
            now = time.monotonic()
            if now >= next_s:   # a state set at 10 Hz, stamped now, delivered delay_s later
                msg = JointState(name=list(settings.JOINT_NAMES), position=list(self.angles),
                                 effort=[0.0] * settings.NUM_JOINTS)
                msg.header.stamp = self.clock()
                self.delay_s = min(self.delay_s + self.grow_s, DELAY_S)
                with self._lock:   # in order, as TCP delivers
                    due = max([now + self.delay_s] + [q[0] for q in self._queue[-1:]])
                    self._queue.append((due, msg))
                for publisher in self._status:
                    publisher.publish(String(interface.WORKING))
                self._button.publish(UInt8(self.button))
                self._end_piece.publish(Float32(1.0))
                next_s += 0.1
            if now >= beat_s:
                self._heartbeat.publish(Empty())
                beat_s += interface.HEARTBEAT_PERIOD_S
            with self._lock:
                due = [m for t, m in self._queue if t <= now]
                self._queue = self._queue[len(due):]
            for msg in due:
                self._states.publish(msg)
            time.sleep(0.005)

    def stop(self):
        self._stop.set()
        self._thread.join(2.0)


class ArmR:
    """What arm_R reports: teleop_state, link_state and its link status on /diagnostics."""

    def __init__(self):
        ns = interface.puppet_ns(SIDE) + '/'
        self.teleop, self.link, self.diag = None, None, {}
        self.teleop_log = []
        rospy.Subscriber(ns + interface.TELEOP_STATE, TeleopState, self._on_teleop)
        rospy.Subscriber(ns + interface.LINK_STATE, LinkState, self._on_link)
        rospy.Subscriber(interface.DIAGNOSTICS, DiagnosticArray, self._on_diag, queue_size=50)

    def _on_teleop(self, msg):
        self.teleop = msg
        self.teleop_log.append((time.monotonic(), msg))

    def _on_link(self, msg):
        self.link = msg

    def _on_diag(self, msg):
        for status in msg.status:
            if (status.hardware_id == interface.puppet_ns(SIDE)
                    and status.name.endswith(interface.DIAG_NETWORK)):
                self.diag = {kv.key: kv.value for kv in status.values}

    def state(self):
        return None if self.teleop is None else self.teleop.state

    def link_is(self, **fields):
        return self.link is not None and all(getattr(self.link, k) == v
                                             for k, v in fields.items())


class LinkSkewTest(unittest.TestCase):

    def test_sample_ages_on_a_skewed_clock_behind_a_delaying_network(self):
        baxter, arm, operator = Baxter(), ArmR(), OperatorHost()
        self.addCleanup(operator.stop)

        # No echo yet: the samples' age is unknown and nothing follows, even on a press.
        wait_for(lambda: arm.state() == interface.CALIBRATING and "operator host's echo"
                 in arm.teleop.detail, 30, 'arm_R waiting for the echo (%s)' % (arm.teleop,))
        wait_for(lambda: arm.link_is(clock_known=False, fault=LinkState.NETWORK), 5,
                 'LinkState: clock unknown, network')
        start = time.monotonic()
        operator.press(interface.BUTTON_RIGHT)
        time.sleep(0.5)
        self.assertEqual(baxter.commands_since('right', start), [])
        self.assertEqual(arm.state(), interface.CALIBRATING)

        # Echoes: the clock is known, fresh samples are used; Baxter follows after button 3.
        operator.echo = True
        wait_for(lambda: arm.state() == interface.READY, 10, 'ready once echoes come back')
        wait_for(lambda: arm.link_is(clock_known=True), 5, 'LinkState: clock known')
        link = arm.link
        print('rtt %.4f s, clock offset %.4f s, sample age %.4f s'
              % (link.rtt, link.clock_offset, link.sample_age))
        self.assertLessEqual(abs(link.clock_offset - SKEW_S), link.rtt / 2 + 1e-3)
        self.assertLess(link.sample_age, 0.1)
        self.assertAlmostEqual(link.max_sample_age, MAX_SAMPLE_AGE_S, places=5)
        wait_for(lambda: arm.diag.get('clock_known') == 'True', 5, 'the link on /diagnostics')
        self.assertLess(abs(float(arm.diag['clock_offset_s']) - SKEW_S), 0.05)
        operator.press(interface.BUTTON_RIGHT)
        wait_for(lambda: max_error(baxter.arm('right'), POSE_A) < 0.02, 15,
                 "Baxter's right arm on the puppet pose")
        self.assertEqual(arm.state(), interface.FOLLOWING)
        # Healthy once the pings lost before the first echo have left the 5 s loss window.
        wait_for(lambda: arm.link_is(fault=LinkState.NONE, level=0), 10,
                 'LinkState healthy (%s)' % (arm.link,))

        # The delay grows past max_sample_age: a fault naming the age, LinkState network with the
        # age, and no more commands, although the hand moves on.
        if arm.state() != interface.FOLLOWING:   # a hiccup of this loaded host ended it
            print('following again after: %s' % arm.teleop.detail)
            wait_for(lambda: arm.state() == interface.READY, 10, 'ready')
            operator.press(interface.BUTTON_RIGHT)
            wait_for(lambda: arm.state() == interface.FOLLOWING, 5, 'following again')
        delayed_t = time.monotonic()
        operator.grow_s = GROW_S
        wait_for(lambda: arm.state() == interface.FAULT, 5, 'a fault on stale samples')
        self.assertTrue(baxter.commands_since('right', time.monotonic() - 0.5),
                        'Baxter was not commanded right before the fault')
        operator.angles = list(POSE_B)
        print('stale: fault %.2f s after the delay began to grow by %.2f s a sample'
              % (time.monotonic() - delayed_t, GROW_S))
        self.assertRegex(arm.teleop.detail, r'^puppet joint states refused: stale, none usable '
                                            r'for 0\.\d\d s: the newest \d\.\d{3} s old, over '
                                            r'the 0\.35 s bound \(max_sample_age\)$')
        wait_for(lambda: arm.link_is(fault=LinkState.NETWORK, level=2)
                 and arm.link.sample_age > MAX_SAMPLE_AGE_S, 5,
                 'LinkState: network, samples older than the bound (%s)' % (arm.link,))
        self.assertIn('puppet samples arrive too late', arm.link.detail)
        wait_for(lambda: abs(arm.link.sample_age - DELAY_S) < 0.1, 5,
                 'LinkState: samples %.1f s old (%s)' % (DELAY_S, arm.link))
        time.sleep(0.3)   # the stay command has gone out
        count, at_stop = len(baxter.commands['right']), baxter.arm('right')
        time.sleep(1.0)
        self.assertEqual(len(baxter.commands['right']), count, 'commands after the fault')
        self.assertLess(max_error(baxter.arm('right'), POSE_A), 0.02)

        # The delay is gone: ready again, nothing moves until a new press.
        operator.grow_s = operator.delay_s = 0.0
        wait_for(lambda: arm.state() == interface.READY, 10, 'ready with fresh samples')
        # Healthy once the dropped samples have left the 5 s window of the report.
        wait_for(lambda: arm.link_is(fault=LinkState.NONE), 10, 'LinkState healthy again')
        time.sleep(1.0)
        self.assertEqual(len(baxter.commands['right']), count, 'commands without a press')
        self.assertLess(max_error(baxter.arm('right'), at_stop), 0.01)

        # A new press: Baxter approaches the moved hand slowly, without a jump.
        press_t = time.monotonic()
        operator.press(interface.BUTTON_RIGHT)
        wait_for(lambda: max_error(baxter.arm('right'), POSE_B) < 0.02, 15,
                 "Baxter's right arm on the moved hand")
        approach = [c[2] for c in baxter.commands_since('right', press_t)]
        steps = [max_error(a, b) for a, b in zip([at_stop] + approach, approach)]
        self.assertLess(max(steps), 0.03, 'a command step')
        took = baxter.commands_since('right', press_t)
        moving = [t for (t, _, c), step in zip(took, steps) if step > 1e-6]
        distance = max_error(POSE_B, at_stop)
        print('approach of %.2f rad took %.2f s' % (distance, moving[-1] - moving[0]))
        self.assertGreater(moving[-1] - moving[0], 0.8 * distance / APPROACH_RAD_S)
        self.assertTrue(all(math.isfinite(x) for c in approach for x in c))


if __name__ == '__main__':
    rospy.init_node('test_link_skew')
    rostest.rosrun('robopuppet', 'link_skew', LinkSkewTest)
