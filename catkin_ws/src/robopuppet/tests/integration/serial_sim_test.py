#!/usr/bin/python3
"""serial_L against the simulated puppet over a pty: settings, tracking, forwarding, line noise.

The test publishes active_settings itself, as config_X does; test_6 and test_7 (feel mode) run
the real config_X.
"""
import math
import threading
import time
import unittest

import roslaunch
import rospy
import rostest
from roslaunch.core import Node
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, Float32MultiArray, String, UInt8, UInt8MultiArray

from robopuppet import interface, settings
from robopuppet.config import feel_profile
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_arm import REST_POSE_RAD, wrap
from serial_test_support import (PER_JOINT, SIM, ActiveSettings, TempConfig,
                                 Watcher, index, seed_values, topic)
from waiting import seconds_until, wait_for

# A hand pose that takes every quadrature joint across its index mark from the rest pose.
HAND_RAD = (-0.4, 0.3, 0.3, 0.6, -0.2, -0.5, 0.25)
ID = settings.CONFIG_ID
ABSOLUTE = settings.HALL_JOINTS  # their angle is known from the start
HOME_STEP_RAD = 0.3125  # exact in float32, as the device holds it


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


class SerialSimTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('serial_sim_test')
        cls.seed_file = rospy.get_param('~seed_file')
        cls.seed = seed_values(cls.seed_file)
        cls.watch = Watcher()
        cls.launch = roslaunch.scriptapi.ROSLaunch()
        cls.launch.start()
        cls.stored = ActiveSettings()  # nothing published until test_1 says so
        cls.joint_topics = []  # (time, topic) of every joint_3 angle/voltage/enc_stat message
        cls.grippers = []  # time of every gripper_0 message
        cls.subs = [rospy.Subscriber(interface.joint_topic('L', 3, topic), kind,
                                     cls.on_joint_topic, topic)
                    for topic, kind in (('angle', Float32), ('voltage', Float32),
                                        ('enc_stat', String))]
        cls.subs.append(rospy.Subscriber(interface.gripper_topic('L', 0), Float32,
                                         lambda _msg: cls.grippers.append(time.monotonic())))
        cls.watch.listen()  # serial_L's first warnings must be heard
        cls.serial = cls.launch.launch(Node(
            'robopuppet', 'serial_interface', name='serial_L', namespace='/',
            args='_arm_side:=L _port_name:=%s _comm_rate:=50.0' % rospy.get_param('~link')))
        cls.pub_hand = rospy.Publisher(topic(interface.SIM_HAND, SIM), JointState, queue_size=1,
                                       latch=True)
        cls.pub_button = rospy.Publisher(topic(interface.SIM_BUTTON, SIM), UInt8, queue_size=1,
                                         latch=True)
        cls.pub_grippers = rospy.Publisher(topic(interface.SIM_GRIPPERS, SIM), Float32MultiArray,
                                           queue_size=1, latch=True)
        cls.pub_noise = rospy.Publisher(topic(interface.SIM_LINE_NOISE, SIM), UInt8MultiArray,
                                        queue_size=10)
        cls.pub_opmode = rospy.Publisher(topic(interface.OPMODE), String, queue_size=1,
                                         latch=True)

    @classmethod
    def tearDownClass(cls):
        cls.serial.stop()
        cls.launch.stop()

    @classmethod
    def on_joint_topic(cls, _msg, topic):
        cls.joint_topics.append((time.monotonic(), topic))

    def position(self):
        state = self.watch.latest_state()
        return [math.nan] * settings.NUM_JOINTS if state is None else state.position

    def device_config(self):
        with self.watch.lock:
            return self.watch.device_config

    def wait_device_holds(self, values, timeout_s=20.0):
        self.assertTrue(wait_for(lambda: self.device_config() == values, timeout_s),
                        'device holds %s, expected %s' % (self.device_config(), values))

    def steady_angle(self, joint, since_s):
        """Wait until a joint's angle is steady over 10 sets since since_s; return their mean."""
        def angles():
            return [s.position[joint] for s in self.watch.states_since(since_s)[-10:]]
        self.assertTrue(wait_for(lambda: len(angles()) == 10
                                      and max(angles()) - min(angles()) < 0.002, 10.0),
                        'joint %d never steady' % joint)
        return sum(angles()) / 10

    def test_1_no_joint_states_until_settings_loaded_then_84_settings_and_limp(self):
        rospy.wait_for_message(topic(interface.HEARTBEAT), Empty, 10.0)  # the link works
        # Without settings there are no angles: a bare hold is refused (the firmware would hold
        # 0 rad). With seven setpoints it is passed on (setpoints and opmode travel on separate
        # topics, so ask again until the device holds).
        self.pub_opmode.publish(String(interface.HOLD))
        self.assertTrue(wait_for(lambda: self.watch.warnings_with('hold refused'), 5.0))
        setpoints = [rospy.Publisher(interface.joint_topic('L', j, 'setpoint'), Float32,
                                     queue_size=1, latch=True) for j in settings.JOINTS]
        for pub in setpoints:
            pub.publish(Float32(0.0))

        def hold():
            self.pub_opmode.publish(String(interface.HOLD))
            return seconds_until(lambda: self.watch.device_opmode == interface.HOLD, 0.5)
        self.assertTrue(wait_for(hold, 10.0))
        self.assertTrue(wait_for(lambda: 'waiting for settings' in self.watch.diagnostics.get(
            'message', ''), 5.0), self.watch.diagnostics)
        # About 100 state sets (50 Hz) go through, seen on gripper_0, but no joint topic.
        counted = len(self.grippers)
        self.assertTrue(wait_for(lambda: len(self.grippers) >= counted + 100, 10.0))
        self.assertEqual(self.watch.states_since(0.0), [], 'joint_states before the settings')
        self.assertEqual(self.joint_topics, [], 'joint_3 topics before the settings')
        # Said once, not repeated (the first line may go out before this test's /rosout
        # subscription reaches serial_L, and /rosout keeps nothing for a late subscriber).
        self.assertLessEqual(len(self.watch.warnings_with('publishing no joint states')), 1,
                             self.watch.warnings)
        self.assertEqual((self.watch.diagnostics['settings loaded'],
                          self.watch.diagnostics['active settings']), ('False', 'none yet'))
        started = time.monotonic()
        revision = self.stored.publish(self.seed)
        self.wait_device_holds(self.seed)
        self.assertEqual(len(self.seed), 84)
        # The load ends with limp: the device left the hold it was put in above.
        self.assertTrue(wait_for(lambda: self.watch.device_opmode == interface.LIMP, 5.0))
        self.assertEqual(self.watch.device_opmodes[-2:], [interface.HOLD, interface.LIMP])
        self.assertTrue(wait_for(lambda: len(self.watch.states_since(started)) >= 10, 5.0))
        self.assertTrue(wait_for(lambda: {t for _, t in self.joint_topics}
                                      == {'angle', 'voltage', 'enc_stat'}, 5.0))
        self.assertTrue(wait_for(lambda: (
            self.watch.diagnostics.get('settings loaded'),
            self.watch.diagnostics.get('active settings'),
            self.watch.diagnostics.get('active settings publishers'))
            == ('True', 'revision %d' % revision, '1'), 5.0), self.watch.diagnostics)

    def test_2_topics_track_the_hand_buttons_and_grippers(self):
        self.wait_device_holds(self.seed)
        home = self.seed[ID['home_angle']::PER_JOINT]
        sign = self.seed[ID['sign_angle']::PER_JOINT]
        # The firmware's formula, signs sent before home: sign x wrap(raw - home x sign).
        rest = [wrap(s * a - h) for h, s, a in zip(home, sign, REST_POSE_RAD)]
        # Absolute encoders report the rest pose as soon as the settings are in (rate-limited).
        self.assertTrue(wait_for(lambda: close(
            [self.position()[j] for j in ABSOLUTE], [rest[j] for j in ABSOLUTE], 0.05), 5.0))
        self.pub_hand.publish(JointState(name=settings.JOINT_NAMES, position=HAND_RAD))
        expected = [wrap(s * a - h) for h, s, a in zip(home, sign, HAND_RAD)]
        took = seconds_until(lambda: close(self.position(), expected, 0.05), 10.0)
        self.assertIsNotNone(took, 'joint_states %s, expected %s'
                             % (self.position(), expected))
        for joint in settings.JOINTS:
            self.assertEqual(rospy.wait_for_message(interface.joint_topic('L', joint, 'enc_stat'),
                                                    String, 5.0).data, interface.WORKING)
        angle = rospy.wait_for_message(interface.joint_topic('L', 4, 'angle'), Float32, 5.0).data
        self.assertAlmostEqual(angle, expected[4], delta=0.05)
        self.pub_button.publish(UInt8(3))
        self.pub_grippers.publish(Float32MultiArray(data=[0.25, 0.5, 0.75, 0.0]))
        self.assertTrue(wait_for(lambda: rospy.wait_for_message(
            topic(interface.USER_BUTTON), UInt8, 5.0).data == 3, 5.0))
        self.assertTrue(wait_for(lambda: rospy.wait_for_message(
            interface.gripper_topic('L', 3), Float32, 5.0).data == 0.0, 5.0))
        self.assertEqual(rospy.wait_for_message(interface.gripper_topic('L', 1), Float32,
                                                5.0).data, 0.5)

    def test_3_a_new_stored_revision_reaches_the_device_at_once(self):
        self.wait_device_holds(self.seed)
        joint = 3
        before = self.steady_angle(joint, time.monotonic())
        # home_angle +0.3125 rad: the firmware reports sign x wrap(raw - home x sign), which is
        # 0.3125 rad less whatever the sign.
        values = list(self.seed)
        values[index(joint, 'home_angle')] += HOME_STEP_RAD
        changed = time.monotonic()
        self.stored.publish(values)
        took = seconds_until(lambda: abs(self.position()[joint] - (before - HOME_STEP_RAD)) < 0.01,
                        5.0, 0.002)
        self.assertIsNotNone(took, 'joint %d at %.3f rad, expected %.3f' % (
            joint, self.position()[joint], before - HOME_STEP_RAD))
        rospy.loginfo('serial_sim: a home_angle change shows in joint_states %.0f ms after '
                      'active_settings was published', 1000.0 * took)
        self.wait_device_holds(values, 5.0)
        self.assertAlmostEqual(self.steady_angle(joint, changed + took), before - HOME_STEP_RAD,
                               delta=0.01)
        # A burst of revisions: the device ends with the newest.
        for step in range(1, 11):
            values[index(2, 'pid_kd')] = step / 4.0
            self.stored.publish(values)
        self.wait_device_holds(values, 5.0)
        self.stored.publish(self.seed)
        self.wait_device_holds(self.seed, 5.0)

    def test_4_opmode_and_setpoints_are_forwarded(self):
        self.wait_device_holds(self.seed)
        self.pub_opmode.publish(String(interface.HOLD))
        self.assertTrue(wait_for(lambda: self.watch.device_opmode == interface.HOLD, 5.0))
        # Let go of joint 5: in hold the device drives it to its setpoint.
        setpoint = rospy.Publisher(interface.joint_topic('L', 5, 'setpoint'), Float32,
                                   queue_size=1, latch=True)
        self.assertTrue(wait_for(lambda: setpoint.get_num_connections() >= 1, 5.0))
        setpoint.publish(Float32(0.2))
        self.pub_hand.publish(JointState(name=settings.JOINT_NAMES,
                                         position=HAND_RAD[:5] + (math.nan,) + HAND_RAD[6:]))
        self.assertTrue(wait_for(
            lambda: abs(self.position()[5] - 0.2) < 0.1, 10.0),
            'joint 5 at %s, setpoint 0.2' % self.position()[5])
        self.pub_opmode.publish(String(interface.LIMP))
        self.assertTrue(wait_for(lambda: self.watch.device_opmode == interface.LIMP, 5.0))

    def test_5_garbage_bursts_lose_no_later_frame(self):
        self.assertTrue(wait_for(lambda: 'incomplete joint sets' in self.watch.diagnostics,
                                      10.0))
        before = dict(self.watch.diagnostics)
        truncated = codec.encode(codec.JointState(2, 0, 0.5, 0.5))[:7]
        bursts = [bytes([0xA5]) * 40, bytes(range(256)), truncated, b'\xa5\x20', b'\xa5\x41',
                  bytes([0xA5, 0x40, 0x01]) + truncated, b'\x00\xa5\x00\xa5']
        # As in the decoder's fuzz test: zeros after each burst, so that a false start in the
        # garbage cannot take the real frame that follows into a valid false frame.
        gap = bytes(codec.MAX_FRAME_LEN - 1)
        start = time.monotonic()
        for burst in bursts * 3:
            sent = time.monotonic()
            self.pub_noise.publish(UInt8MultiArray(data=burst + gap))
            # The simulator puts it on the line before the next set: wait for two sets.
            self.assertTrue(wait_for(lambda: len(self.watch.states_since(sent)) >= 2, 5.0))
        # A status made after the last burst went through covers all of them.
        done = time.monotonic()
        self.assertTrue(wait_for(lambda: self.watch.diagnostics_since(done) >= 2, 5.0))
        after = dict(self.watch.diagnostics)
        self.assertGreaterEqual(int(after['dropped bytes']), int(before['dropped bytes']) + 42)
        self.assertEqual(after['incomplete joint sets'], before['incomplete joint sets'],
                         'a joint state frame right after a garbage burst was lost')
        # Every set still comes through (loosely: the machine may be loaded; the benchmark
        # measures loss precisely).
        seconds = time.monotonic() - start
        self.assertGreaterEqual(len(self.watch.states_since(start)), int(50 * seconds * 0.5))

    def test_6_with_the_real_config_node_a_change_it_stores_reaches_the_device(self):
        self.stored.stop()  # config_X takes over active_settings
        config = TempConfig(self.launch, self.seed_file)
        try:
            self.assertTrue(wait_for(
                lambda: self.watch.diagnostics.get('active settings') == 'revision 0', 20.0),
                self.watch.diagnostics)
            self.wait_device_holds(self.seed)
            # The 2020 topics: a value config_X refuses never reaches the device; one it
            # stores does.
            angle_min = rospy.Publisher(interface.joint_topic('L', 2, 'angle_min'), Float32,
                                        queue_size=10)
            self.assertTrue(wait_for(lambda: angle_min.get_num_connections() >= 1, 5.0))
            angle_min.publish(Float32(3.0))  # above angle_max: refused
            angle_min.publish(Float32(-1.25))  # on the same topic: stored after
            values = list(self.seed)
            values[index(2, 'angle_min')] = -1.25
            self.wait_device_holds(values, 5.0)
            with self.watch.lock:
                seen = {c[index(2, 'angle_min')] for c in self.watch.device_configs}
            self.assertNotIn(3.0, seen)
        finally:
            config.stop()

    def test_7_feel_mode_gentle_gains_while_setpoints_flow_then_limp_when_they_stop(self):
        config = TempConfig(self.launch, self.seed_file)  # its new file gets the [feel] defaults
        streamer = SetpointStreamer()
        announced = []  # (caller, mode) of every opmode message
        sub = rospy.Subscriber(topic(interface.OPMODE), String, lambda msg: announced.append(
            (msg._connection_header.get('callerid'), msg.data)), queue_size=10)
        joints = [dict(zip(settings.NAMES, self.seed[j * PER_JOINT:(j + 1) * PER_JOINT]))
                  for j in settings.JOINTS]
        gentle = [v for values in feel_profile.active_joints('feel', joints, {
            'gain_scale': 0.25, 'voltage_limit': 2.0}) for v in values.values()]
        self.assertNotEqual(gentle, self.seed)

        def serial_said_limp():
            return ('/serial_L', interface.LIMP) in announced
        try:
            self.assertTrue(wait_for(
                lambda: self.watch.diagnostics.get('active settings') == 'revision 0', 20.0),
                self.watch.diagnostics)
            self.wait_device_holds(self.seed)
            streamer.start(self.position)
            self.pub_opmode.publish(String(interface.FEEL))
            self.wait_device_holds(gentle, 10.0)
            self.assertEqual(self.watch.device_opmode, interface.HOLD)
            rospy.sleep(1.5)  # setpoints flowing (20 Hz): feel lasts
            self.assertEqual(self.watch.device_opmode, interface.HOLD)
            self.assertFalse(serial_said_limp(), announced)
            self.pub_opmode.publish(String(interface.HOLD))  # the stored gains again
            self.wait_device_holds(self.seed, 10.0)
            streamer.stop()
            rospy.sleep(1.5)  # hold is never timed out
            self.assertEqual(self.watch.device_opmode, interface.HOLD)
            self.assertFalse(serial_said_limp(), announced)

            streamer.start(self.position)
            self.pub_opmode.publish(String(interface.FEEL))
            self.wait_device_holds(gentle, 10.0)
            last_s = streamer.stop()  # arm_X dies
            self.assertTrue(wait_for(lambda: self.watch.device_opmode == interface.LIMP,
                                          5.0), 'no limp after the setpoints stopped')
            took_s = time.monotonic() - last_s
            rospy.loginfo('serial_sim: the device went limp %.2f s after the last setpoint '
                          '(~feel_setpoint_timeout 0.5 s)', took_s)
            self.assertGreaterEqual(took_s, 0.45)
            self.assertLess(took_s, 2.5)  # 0.5 s plus a loaded machine's delays
            self.assertTrue(wait_for(serial_said_limp, 5.0), announced)
            self.assertTrue(self.watch.warnings_with('no joint setpoint for'), self.watch.warnings)
            self.wait_device_holds(self.seed, 10.0)  # config_X heard the limp too
        finally:
            streamer.stop()
            sub.unregister()
            self.pub_opmode.publish(String(interface.LIMP))
            config.stop()


class SetpointStreamer:
    """Play arm_X in feel mode: publish every joint's setpoint (where it is) at 20 Hz."""

    def __init__(self):
        self._publishers = [rospy.Publisher(interface.joint_topic('L', j, 'setpoint'), Float32,
                                            queue_size=10) for j in settings.JOINTS]
        self._thread, self._stop, self.last_s = None, threading.Event(), None

    def start(self, position):
        self._stop.clear()
        self._thread = threading.Thread(target=self._run, args=(position,), daemon=True)
        self._thread.start()
        assert wait_for(lambda: self.last_s is not None, 5.0)

    def _run(self, position):
        while not self._stop.wait(0.05):
            for publisher, angle in zip(self._publishers, position()):
                publisher.publish(Float32(angle))
            self.last_s = time.monotonic()

    def stop(self):
        """Stop publishing; return when the last setpoint went out (monotonic s)."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(1.0)
        return self.last_s


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_sim', SerialSimTest)
