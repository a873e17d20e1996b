#!/usr/bin/python3
"""serial_L against the simulated puppet over a pty: settings, tracking, forwarding, line noise."""
import math
import os
import time
import unittest

import roslaunch
import rospy
import rostest
from roslaunch.core import Node
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, Float32MultiArray, String, UInt8, UInt8MultiArray

from robopuppet import settings
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_model import REST_POSE_RAD, wrap
from robopuppet_msgs.srv import GetConfig
from serial_test_support import NS, SIM, TempConfig, Watcher, seed_values, wait_for

# A hand pose that takes every quadrature joint across its index mark from the rest pose.
HAND_RAD = (-0.4, 0.3, 0.3, 0.6, -0.2, -0.5, 0.25)
ID = settings.CONFIG_ID


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
        cls.config = None  # started by start_config()
        cls.joint_topics = []  # (time, topic) of every joint_3 angle/voltage/enc_stat message
        cls.subs = [rospy.Subscriber('%s/joint_3/%s' % (NS, topic), kind, cls.on_joint_topic,
                                     topic)
                    for topic, kind in (('angle', Float32), ('voltage', Float32),
                                        ('enc_stat', String))]
        time.sleep(1.0)  # let the log subscription connect before serial_L's first warning
        cls.serial = cls.launch.launch(Node(
            'robopuppet', 'serial_interface', name='serial_L', namespace='/',
            args='_arm_side:=L _port_name:=%s' % rospy.get_param('~link')))
        cls.pub_hand = rospy.Publisher(SIM + '/hand', JointState, queue_size=1, latch=True)
        cls.pub_button = rospy.Publisher(SIM + '/button', UInt8, queue_size=1, latch=True)
        cls.pub_grippers = rospy.Publisher(SIM + '/grippers', Float32MultiArray, queue_size=1,
                                           latch=True)
        cls.pub_noise = rospy.Publisher(SIM + '/line_noise', UInt8MultiArray, queue_size=10)
        cls.pub_opmode = rospy.Publisher(NS + '/opmode', String, queue_size=1, latch=True)

    @classmethod
    def tearDownClass(cls):
        cls.serial.stop()
        if cls.config is not None:
            cls.config.stop()
        cls.launch.stop()

    @classmethod
    def on_joint_topic(cls, _msg, topic):
        cls.joint_topics.append((time.monotonic(), topic))

    @classmethod
    def start_config(cls):
        """Start config_L once; every test but the first finds it running."""
        if cls.config is None:
            cls.config = TempConfig(cls.launch, cls.seed_file)
            rospy.wait_for_service(NS + '/get_config', 20.0)

    def position(self):
        state = self.watch.latest_state()
        return [math.nan] * settings.NUM_JOINTS if state is None else state.position

    def device_config(self):
        with self.watch.lock:
            return self.watch.device_config

    def test_1_no_joint_states_until_settings_loaded_then_84_settings_and_limp(self):
        self.assertIsNone(self.config, 'test_1 must run before config_L starts')
        # The link works: heartbeats come through, and an opmode reaches the device. Without
        # angles the node passes a hold on only after seven setpoints (the firmware holds the
        # setpoints it has); setpoints and opmode travel on separate topics, so ask again.
        rospy.wait_for_message(NS + '/heartbeat', Empty, 10.0)
        setpoints = [rospy.Publisher('%s/joint_%d/setpoint' % (NS, j), Float32, queue_size=1,
                                     latch=True) for j in settings.JOINTS]
        for pub in setpoints:
            pub.publish(Float32(0.0))

        def hold():
            self.pub_opmode.publish(String('hold'))
            return wait_for(lambda: self.watch.device_opmode == 'hold', 0.5)
        self.assertIsNotNone(wait_for(hold, 10.0))
        self.assertIsNotNone(wait_for(lambda: 'waiting for settings' in self.watch.diagnostics.get(
            'message', ''), 5.0), self.watch.diagnostics)
        time.sleep(2.0)  # about 100 state sets at 50 Hz
        self.assertEqual(self.watch.states_since(0.0), [], 'joint_states before the settings')
        self.assertEqual(self.joint_topics, [], 'joint_3 topics before the settings')
        with self.watch.lock:
            waiting = [w for w in self.watch.warnings if 'publishing no joint states' in w]
        self.assertEqual(len(waiting), 1, self.watch.warnings)
        self.assertEqual(self.watch.diagnostics['settings loaded'], 'False')
        started = time.monotonic()
        self.start_config()
        self.assertIsNotNone(wait_for(lambda: self.device_config() == self.seed, 20.0),
                             'device holds %s, ini has %s' % (self.device_config(), self.seed))
        self.assertEqual(len(self.seed), 84)
        # The load ends with limp: the device left the hold it was put in above.
        self.assertIsNotNone(wait_for(lambda: self.watch.device_opmode == 'limp', 5.0))
        self.assertEqual(self.watch.device_opmodes[-2:], ['hold', 'limp'])
        self.assertIsNotNone(wait_for(lambda: len(self.watch.states_since(started)) >= 10, 5.0))
        self.assertIsNotNone(wait_for(lambda: {t for _, t in self.joint_topics}
                                      == {'angle', 'voltage', 'enc_stat'}, 5.0))
        self.assertIsNotNone(wait_for(
            lambda: self.watch.diagnostics.get('settings loaded') == 'True', 5.0))

    def test_2_topics_track_the_hand_buttons_and_grippers(self):
        self.start_config()
        self.assertIsNotNone(wait_for(lambda: self.device_config() == self.seed, 20.0))
        home = self.seed[ID['home_angle']::len(settings.NAMES)]
        sign = self.seed[ID['sign_angle']::len(settings.NAMES)]
        # The firmware's formula, signs sent before home: sign x wrap(raw - home x sign).
        rest = [wrap(s * a - h) for h, s, a in zip(home, sign, REST_POSE_RAD)]
        # Absolute encoders report the rest pose as soon as the settings are in (rate-limited).
        absolute = (1, 3, 5)
        self.assertIsNotNone(wait_for(lambda: close(
            [self.position()[j] for j in absolute],
            [rest[j] for j in absolute], 0.05), 5.0))
        self.pub_hand.publish(JointState(name=settings.JOINT_NAMES, position=HAND_RAD))
        expected = [wrap(s * a - h) for h, s, a in zip(home, sign, HAND_RAD)]
        took = wait_for(lambda: close(self.position(), expected, 0.05), 10.0)
        self.assertIsNotNone(took, 'joint_states %s, expected %s'
                             % (self.position(), expected))
        for joint in settings.JOINTS:
            self.assertEqual(rospy.wait_for_message('%s/joint_%d/enc_stat' % (NS, joint), String,
                                                    5.0).data, 'Working')
        angle = rospy.wait_for_message(NS + '/joint_4/angle', Float32, 5.0).data
        self.assertAlmostEqual(angle, expected[4], delta=0.05)
        self.pub_button.publish(UInt8(3))
        self.pub_grippers.publish(Float32MultiArray(data=[0.25, 0.5, 0.75, 0.0]))
        self.assertIsNotNone(wait_for(lambda: rospy.wait_for_message(
            NS + '/user_btn', UInt8, 5.0).data == 3, 5.0))
        self.assertIsNotNone(wait_for(lambda: rospy.wait_for_message(
            NS + '/gripper_3', Float32, 5.0).data == 0.0, 5.0))
        self.assertEqual(rospy.wait_for_message(NS + '/gripper_1', Float32, 5.0).data, 0.5)

    def test_3_settings_opmode_and_setpoints_are_forwarded(self):
        self.start_config()
        self.assertIsNotNone(wait_for(lambda: self.device_config() == self.seed, 20.0))
        index = 2 * len(settings.NAMES)
        # The device gets what config_L stored: a burst ends with the last value, and a value
        # that config_L refuses (angle_min above angle_max) never reaches the device.
        kd = rospy.Publisher(NS + '/joint_2/pid_kd', Float32, queue_size=20)
        angle_min = rospy.Publisher(NS + '/joint_2/angle_min', Float32, queue_size=20)
        for pub in (kd, angle_min):  # config_L and serial_L
            self.assertIsNotNone(wait_for(lambda: pub.get_num_connections() >= 2, 5.0))
        for value in range(1, 11):
            kd.publish(Float32(value / 4.0))
        self.assertIsNotNone(wait_for(lambda: self.device_config()[index + ID['pid_kd']] == 2.5,
                                      5.0), self.device_config())
        angle_min.publish(Float32(3.0))  # above angle_max: refused
        angle_min.publish(Float32(-1.25))  # on the same topic: config_L stores it after
        self.assertIsNotNone(wait_for(
            lambda: self.device_config()[index + ID['angle_min']] == -1.25, 5.0))
        with self.watch.lock:
            seen = {c[index + ID['angle_min']] for c in self.watch.device_configs}
        self.assertNotIn(3.0, seen)
        # A value that config_L cannot save (its file is now a directory) is not stored, so
        # the device does not get it either; the next value, saved again, does.
        os.remove(self.config.path)
        os.mkdir(self.config.path)
        kd.publish(Float32(7.0))
        self.assertIsNotNone(wait_for(lambda: self.watch.config_errors, 5.0))
        os.rmdir(self.config.path)
        kd.publish(Float32(3.0))
        self.assertIsNotNone(wait_for(lambda: self.device_config()[index + ID['pid_kd']] == 3.0,
                                      5.0))
        with self.watch.lock:
            self.assertNotIn(7.0, {c[index + ID['pid_kd']] for c in self.watch.device_configs})
        stored = rospy.ServiceProxy(NS + '/get_config', GetConfig)(2)
        self.assertEqual(self.device_config()[index:index + len(settings.NAMES)],
                         [getattr(stored, n) for n in settings.NAMES])
        self.pub_opmode.publish(String('hold'))
        self.assertIsNotNone(wait_for(lambda: self.watch.device_opmode == 'hold', 5.0))
        # Let go of joint 5: in hold the device drives it to a setpoint.
        setpoint = rospy.Publisher(NS + '/joint_5/setpoint', Float32, queue_size=1, latch=True)
        time.sleep(0.5)
        setpoint.publish(Float32(0.2))
        self.pub_hand.publish(JointState(name=settings.JOINT_NAMES,
                                         position=HAND_RAD[:5] + (math.nan,) + HAND_RAD[6:]))
        self.assertIsNotNone(wait_for(
            lambda: abs(self.position()[5] - 0.2) < 0.1, 10.0),
            'joint 5 at %s, setpoint 0.2' % self.position()[5])
        self.pub_opmode.publish(String('limp'))
        self.assertIsNotNone(wait_for(lambda: self.watch.device_opmode == 'limp', 5.0))

    def test_4_garbage_bursts_lose_no_later_frame(self):
        self.start_config()
        self.assertIsNotNone(wait_for(lambda: 'incomplete joint sets' in self.watch.diagnostics,
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
            self.pub_noise.publish(UInt8MultiArray(data=burst + gap))
            time.sleep(0.1)
        # Wait for two diagnostics periods so the counters cover the bursts.
        self.assertIsNotNone(wait_for(lambda: int(self.watch.diagnostics['dropped bytes'])
                                      >= int(before['dropped bytes']) + 21 * 2, 5.0))
        time.sleep(1.2)
        after = self.watch.diagnostics
        self.assertEqual(after['incomplete joint sets'], before['incomplete joint sets'],
                         'a joint state frame right after a garbage burst was lost')
        # Every set still comes through (loosely: the machine may be loaded; the benchmark
        # measures loss precisely).
        seconds = time.monotonic() - start
        received = len(self.watch.states_since(start))
        self.assertGreaterEqual(received, int(50 * seconds * 0.5))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_sim', SerialSimTest)
