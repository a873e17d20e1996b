#!/usr/bin/python3
"""serial_L against the simulated puppet over a pty: settings, tracking, forwarding, line noise."""
import math
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, Float32MultiArray, String, UInt8, UInt8MultiArray

from robopuppet import codec, settings
from robopuppet.puppet_model import REST_POSE_RAD, wrap
from serial_test_support import NS, SIM, Watcher, seed_values, wait_for

# A hand pose that takes every quadrature joint across its index mark from the rest pose.
HAND_RAD = (-0.4, 0.3, 0.3, 0.6, -0.2, -0.5, 0.25)
ID = settings.CONFIG_ID


def close(a, b, tol):
    return all(abs(x - y) <= tol for x, y in zip(a, b))


class SerialSimTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('serial_sim_test')
        cls.seed = seed_values(rospy.get_param('~seed_file'))
        cls.watch = Watcher()
        cls.pub_hand = rospy.Publisher(SIM + '/hand', JointState, queue_size=1, latch=True)
        cls.pub_button = rospy.Publisher(SIM + '/button', UInt8, queue_size=1, latch=True)
        cls.pub_grippers = rospy.Publisher(SIM + '/grippers', Float32MultiArray, queue_size=1,
                                           latch=True)
        cls.pub_noise = rospy.Publisher(SIM + '/line_noise', UInt8MultiArray, queue_size=10)
        cls.pub_opmode = rospy.Publisher(NS + '/opmode', String, queue_size=1, latch=True)

    def position(self):
        state = self.watch.latest_state()
        return [math.nan] * settings.NUM_JOINTS if state is None else state.position

    def device_config(self):
        with self.watch.lock:
            return self.watch.device_config

    def test_1_device_receives_all_84_settings_then_limp(self):
        self.assertIsNotNone(wait_for(lambda: self.device_config() == self.seed, 20.0),
                             'device holds %s, ini has %s' % (self.device_config(), self.seed))
        self.assertEqual(len(self.seed), 84)
        self.assertEqual(self.watch.device_opmode, 'limp')

    def test_2_topics_track_the_hand_buttons_and_grippers(self):
        self.assertIsNotNone(wait_for(lambda: self.device_config() == self.seed, 20.0))
        home = self.seed[ID['home_angle']::len(settings.NAMES)]
        sign = self.seed[ID['sign_angle']::len(settings.NAMES)]
        rest = [wrap(h + s * a) for h, s, a in zip(home, sign, REST_POSE_RAD)]
        # Absolute encoders report the rest pose as soon as the settings are in (rate-limited).
        absolute = (1, 3, 5)
        self.assertIsNotNone(wait_for(lambda: close(
            [self.position()[j] for j in absolute],
            [rest[j] for j in absolute], 0.05), 5.0))
        self.pub_hand.publish(JointState(name=['joint_%d' % j for j in settings.JOINTS],
                                         position=HAND_RAD))
        expected = [wrap(h + s * a) for h, s, a in zip(home, sign, HAND_RAD)]
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
        self.assertIsNotNone(wait_for(lambda: self.watch.device_config is not None, 20.0))
        kp = rospy.Publisher(NS + '/joint_2/pid_kp', Float32, queue_size=1, latch=True)
        bad = rospy.Publisher(NS + '/joint_2/angle_min', Float32, queue_size=1, latch=True)
        index = 2 * len(settings.NAMES)
        kp.publish(Float32(9.5))
        self.assertIsNotNone(wait_for(lambda: self.device_config()[index + ID['pid_kp']] == 9.5,
                                      5.0))
        bad.publish(Float32(3.0))  # above angle_max: refused by config and serial nodes alike
        time.sleep(1.0)
        self.assertEqual(self.device_config()[index + ID['angle_min']],
                         self.seed[index + ID['angle_min']])
        self.pub_opmode.publish(String('hold'))
        self.assertIsNotNone(wait_for(lambda: self.watch.device_opmode == 'hold', 5.0))
        # Let go of joint 5: in hold the device drives it to a setpoint.
        setpoint = rospy.Publisher(NS + '/joint_5/setpoint', Float32, queue_size=1, latch=True)
        time.sleep(0.5)
        setpoint.publish(Float32(0.2))
        names = ['joint_%d' % j for j in settings.JOINTS]
        self.pub_hand.publish(JointState(name=names, position=HAND_RAD[:5] + (math.nan,)
                                         + HAND_RAD[6:]))
        self.assertIsNotNone(wait_for(
            lambda: abs(self.position()[5] - 0.2) < 0.1, 10.0),
            'joint 5 at %s, setpoint 0.2' % self.position()[5])
        self.pub_opmode.publish(String('limp'))
        self.assertIsNotNone(wait_for(lambda: self.watch.device_opmode == 'limp', 5.0))

    def test_4_garbage_bursts_lose_no_later_frame(self):
        self.assertIsNotNone(wait_for(lambda: 'incomplete joint sets' in self.watch.diagnostics,
                                      10.0))
        before = dict(self.watch.diagnostics)
        truncated = codec.encode(codec.JointState(2, 0, 0.5, 0.5))[:7]
        bursts = [bytes([0xA5]) * 40, bytes(range(256)), truncated, b'\xa5\x20', b'\xa5\x41',
                  bytes([0xA5, 0x40, 0x01]) + truncated, b'\x00\xa5\x00\xa5']
        start = time.monotonic()
        for burst in bursts * 3:
            self.pub_noise.publish(UInt8MultiArray(data=burst))
            time.sleep(0.1)
        # Wait for two diagnostics periods so the counters cover the bursts.
        self.assertIsNotNone(wait_for(lambda: int(self.watch.diagnostics['dropped bytes'])
                                      >= int(before['dropped bytes']) + 21 * 2, 5.0))
        time.sleep(1.2)
        after = self.watch.diagnostics
        self.assertEqual(after['incomplete joint sets'], before['incomplete joint sets'],
                         'a joint state frame right after a garbage burst was lost')
        seconds = time.monotonic() - start
        received = len(self.watch.states_since(start))
        self.assertGreaterEqual(received, int(50 * seconds * 0.9))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_sim', SerialSimTest)
