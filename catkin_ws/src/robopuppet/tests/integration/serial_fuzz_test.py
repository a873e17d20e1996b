#!/usr/bin/python3
"""serial_L on a pty fed with line noise between clean state sets: nothing false gets out."""
import math
import os
import random
import threading
import time
import tty
import unittest

import roslaunch
import rospy
import rostest
from roslaunch.core import Node
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, UInt8

from robopuppet import interface, settings
from robopuppet.protocol import codec
from serial_test_support import ActiveSettings, seed_values, topic
from waiting import wait_for

RATE_HZ = 100.0  # state sets, time-compressed (the firmware's 10 Hz would take too long)
HEARTBEAT_EVERY = 100  # sets: one heartbeat a second, as the firmware sends
PALETTE = (0xA5,) * 4 + (0x00,) * 4 + (0x20, 0x40, 0x41, 0x01, 0x02, 0x03, 0x3F, 0x80)
PI32 = math.pi + 1e-6


def real_set(seq):
    """The seq-th state set; joints 0 and 1 carry seq (exact in float32), values plausible."""
    joints = [codec.JointState(0, 0, (seq % 320) / 128.0 - 1.25, 0.0),
              codec.JointState(1, 0, (seq // 320) / 128.0 - 1.25, 0.5)]
    joints += [codec.JointState(j, j % 3, 0.125 * j, -0.25 * j) for j in range(2, 7)]
    grippers = [codec.Gripper(g, ((seq + g) % 64) / 64.0) for g in range(interface.NUM_GRIPPERS)]
    return joints + grippers + [codec.Buttons(seq % 5)]


def seq_of(position):
    return int(round((position[0] + 1.25) * 128)) + 320 * int(round((position[1] + 1.25) * 128))


def noise(rng, size):
    """Half uniform random bytes, half bytes rich in start bytes, ids and small numbers."""
    if rng.random() < 0.5:
        return bytes(rng.randrange(256) for _ in range(size))
    return bytes(rng.choice(PALETTE) for _ in range(size))


class SerialFuzzTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('serial_fuzz_test')
        seed_file = rospy.get_param('~seed_file')
        values = seed_values(seed_file)
        per_joint = len(settings.NAMES)
        cls.voltage = [(values[j * per_joint + settings.CONFIG_ID['voltage_min']],
                        values[j * per_joint + settings.CONFIG_ID['voltage_max']])
                       for j in settings.JOINTS]
        cls.noise_bytes = int(rospy.get_param('~noise_bytes'))
        cls.rng = random.Random(int(rospy.get_param('~seed')))
        cls.lock = threading.Lock()
        cls.states, cls.grippers, cls.buttons, cls.heartbeats = [], [], [], []
        cls.device_frames = []
        cls.subs = [
            rospy.Subscriber(topic(interface.JOINT_STATES), JointState, cls.keep, cls.states,
                             queue_size=5000),
            rospy.Subscriber(topic(interface.USER_BUTTON), UInt8, cls.keep, cls.buttons,
                             queue_size=5000),
            rospy.Subscriber(topic(interface.HEARTBEAT), Empty, cls.keep, cls.heartbeats,
                             queue_size=100)]
        cls.subs += [rospy.Subscriber(interface.gripper_topic('L', g), Float32, cls.keep,
                                      cls.grippers, queue_size=5000)
                     for g in range(interface.NUM_GRIPPERS)]
        cls.master, cls.slave = os.openpty()
        tty.setraw(cls.slave)
        cls.stop = False
        threading.Thread(target=cls.drain, daemon=True).start()
        cls.stored = ActiveSettings()
        cls.stored.publish(values)
        cls.launch = roslaunch.scriptapi.ROSLaunch()
        cls.launch.start()
        cls.serial = cls.launch.launch(Node(
            'robopuppet', 'serial_interface', name='serial_L', namespace='/',
            args='_arm_side:=L _port_name:=%s _comm_rate:=%s' % (os.ttyname(cls.slave), RATE_HZ)))

    @classmethod
    def tearDownClass(cls):
        cls.stop = True
        cls.serial.stop()
        cls.launch.stop()
        os.close(cls.master)
        os.close(cls.slave)

    @classmethod
    def keep(cls, msg, into):
        with cls.lock:
            into.append(msg)

    @classmethod
    def drain(cls):
        """Read what the host sends (settings, opmode) and answer nothing."""
        decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        while not cls.stop:
            try:
                data = os.read(cls.master, 4096)
            except OSError:
                return
            with cls.lock:
                cls.device_frames.extend(decoder.feed(data))

    def write(self, data):
        view = memoryview(data)
        while view:
            view = view[os.write(self.master, view):]

    def test_noise_makes_no_false_value_and_costs_no_clean_set(self):
        # Clean sets until the settings are loaded (opmode limp after them) and joints flow.
        seq = 0
        deadline = time.monotonic() + 30.0
        while time.monotonic() < deadline and not rospy.is_shutdown():
            self.write(b''.join(codec.encode(m) for m in real_set(seq)))
            seq += 1
            time.sleep(0.05)
            with self.lock:
                if self.states and any(isinstance(m, codec.Opmode) for m in self.device_frames):
                    break
        self.assertTrue(self.states, 'no joint_states before the noise started')
        with self.lock:
            del self.heartbeats[:]
        first = seq
        # Then the noise, in bursts between clean sets (a heartbeat before every 100th set).
        left, beats_sent, period = self.noise_bytes, 0, 1.0 / RATE_HZ
        next_s = time.monotonic()
        while left > 0:
            burst = noise(self.rng, min(left, self.rng.randrange(1, 200)))
            left -= len(burst)
            frames = real_set(seq)
            if (seq - first) % HEARTBEAT_EVERY == 0:
                frames.insert(0, codec.Heartbeat())
                beats_sent += 1
            self.write(burst + b''.join(codec.encode(m) for m in frames))
            seq += 1
            next_s += period
            time.sleep(max(0.0, next_s - time.monotonic()))
        for _ in range(3):  # then clean sets only: the last of them marks the end
            self.write(b''.join(codec.encode(m) for m in real_set(seq)))
            seq += 1
            time.sleep(period)
        sent = range(first, seq)
        self.assertTrue(wait_for(lambda: seq - 1 in self.received(), 5.0),
                        'the last clean set never arrived')
        received = self.received()
        with self.lock:
            states, grippers = list(self.states), list(self.grippers)
            buttons, beats = list(self.buttons), len(self.heartbeats)
        # Nothing implausible, and nothing that was not sent.
        for msg in states:
            for joint, (angle, volts) in enumerate(zip(msg.position, msg.effort)):
                low, high = self.voltage[joint]
                self.assertTrue(-PI32 <= angle <= PI32, 'joint %d angle %r' % (joint, angle))
                self.assertTrue(low <= volts <= high, 'joint %d voltage %r' % (joint, volts))
            seq_here = seq_of(msg.position)
            expected = real_set(seq_here)[:settings.NUM_JOINTS]
            self.assertEqual(list(msg.position), [m.angle_rad for m in expected])
            self.assertEqual(list(msg.effort), [m.voltage_v for m in expected])
        self.assertTrue(all(0.0 <= m.data <= 1.0 for m in grippers), 'a gripper out of [0, 1]')
        self.assertTrue(all(0 <= m.data <= 4 for m in buttons), 'a button out of 0..4')
        self.assertEqual(len(received), len(set(received)), 'a set published twice')
        # No heartbeat from noise beyond a small bound; the real ones still count.
        self.assertLessEqual(beats, beats_sent + 3, 'heartbeats counted from noise')
        self.assertGreaterEqual(beats, beats_sent // 2)
        # >= 99 % of the clean sets arrive.
        arrived = sum(1 for s in sent if s in set(received))
        rospy.loginfo('serial_fuzz: %d noise bytes, %d of %d clean sets arrived, %d of %d '
                      'heartbeats counted', self.noise_bytes, arrived, len(sent), beats,
                      beats_sent)
        self.assertGreaterEqual(arrived, 0.99 * len(sent),
                                '%d of %d clean sets arrived' % (arrived, len(sent)))

    def received(self):
        with self.lock:
            return [seq_of(m.position) for m in self.states]


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'serial_fuzz', SerialFuzzTest)
