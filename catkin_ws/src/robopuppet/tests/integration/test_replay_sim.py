#!/usr/bin/python3
"""rostest: replay a synthetic episode onto the stand-in; button 1 stops a replay at once; an
episode that leads into a keep-out zone stops before it."""
import math
import shutil
import subprocess
import tempfile
import threading
import time
import unittest

import numpy as np
import rosbag
import rospy
import rostest
import yaml
from baxter_core_msgs.msg import EndEffectorCommand, JointCommand
from sensor_msgs.msg import JointState
from std_msgs.msg import UInt8

from robopuppet import baxter_description, interface
from robopuppet.world import arm_capsules, zones
from hand_pose import HAND_POSE
from teleop_harness import Baxter, PuppetArm
from waiting import wait_for

RATE_HZ, DURATION_S = 100.0, 3.0
NAMES = baxter_description.arm_joint_names('right')
ZONES_FILE = baxter_description.URDF_PATH.replace('urdf/baxter.urdf', 'config/zones.yaml')
INTO_BODY_RAD = 0.4   # the zone episode lowers joint 1 (s1) this far: 7 cm into the body zone


def write_episode(directory, start, name='episode_synthetic', into_body=False):
    """Write a synthetic episode: the right arm swings joints 0 and 3 around `start` (0.15 rad
    sines, at most 0.31 rad/s: within Baxter's default mode-1 speed, 0.3 x the velocity
    limits), or with into_body lowers joint 1 by INTO_BODY_RAD at 0.2 rad/s into the
    patient-body zone; its gripper closes at 1 s and opens at 2 s. Return
    (bag path, times s, (n, 7) commanded angles)."""
    times = np.arange(0.0, DURATION_S + 1e-9, 1.0 / RATE_HZ)
    path = np.tile(start, (len(times), 1))
    if into_body:
        path[:, 1] += INTO_BODY_RAD * np.minimum(times / 2.0, 1.0)
    else:
        path[:, 0] += 0.15 * np.sin(2 * math.pi * times / DURATION_S)
        path[:, 3] -= 0.15 * np.sin(2 * math.pi * times / DURATION_S)
    bag_path = '%s/%s.bag' % (directory, name)
    t0 = rospy.Time(1000)
    with rosbag.Bag(bag_path, 'w') as bag:
        for t, angles in zip(times, path):
            bag.write(interface.limb_topic('right', 'joint_command'), JointCommand(
                mode=JointCommand.POSITION_MODE, names=NAMES, command=list(angles)),
                t0 + rospy.Duration(t))
        for t, position in ((0.0, 100.0), (1.0, 0.0), (2.0, 100.0)):
            bag.write(interface.baxter_gripper_topic('right', 'command'), EndEffectorCommand(
                command='go', args='{"position": %g}' % position), t0 + rospy.Duration(t))
    with open('%s/%s.yaml' % (directory, name), 'w') as stream:
        yaml.safe_dump({'format_version': 1, 'sides': ['R'], 'sim': True}, stream)
    return bag_path, times, path


class ReplaySimTest(unittest.TestCase):
    """The stand-in follows a replayed episode; button 1 stops a replay."""

    @classmethod
    def setUpClass(cls):
        cls.baxter, cls.puppet = Baxter(), PuppetArm('R')
        cls.measured, cls.grips, cls.button_t = [], [], None
        cls.lock = threading.Lock()
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, cls._on_joints,
                         queue_size=100)
        rospy.Subscriber(interface.baxter_gripper_topic('right', 'command'), EndEffectorCommand,
                         lambda m: cls.grips.append((time.monotonic(), m.command, m.args)))
        rospy.Subscriber(interface.puppet_ns('R') + '/' + interface.USER_BUTTON, UInt8,
                         cls._on_button)
        cls.dir = tempfile.mkdtemp(prefix='replay_test_')
        cls.addClassCleanup(shutil.rmtree, cls.dir, True)
        wait_for(lambda: not any(map(math.isnan, cls.baxter.arm('right'))), 30, 'Baxter')
        cls.puppet.hand(HAND_POSE)  # the operator's hand holds the puppet still
        wait_for(lambda: cls.puppet.angles is not None, 30, 'the puppet')
        wait_for(lambda: cls.baxter.gripper.get('right') is not None
                 and cls.baxter.gripper['right'].calibrated == 1, 30, 'the gripper calibrated')
        start = list(cls.baxter.arm('right'))
        start[1] -= 0.1  # a short approach, up: the episode stays 6.9 cm from the zones
        cls.bag, cls.times, cls.path = write_episode(cls.dir, start)

    @classmethod
    def _on_joints(cls, msg):
        position = dict(zip(msg.name, msg.position))
        if all(n in position for n in NAMES):
            with cls.lock:
                # Baxter's own stamp (when the stand-in computed the pose), not this process's
                # receipt time: the path is Baxter's, the test's scheduling is no part of it.
                cls.measured.append((msg.header.stamp.to_sec(), [position[n] for n in NAMES]))

    @classmethod
    def _on_button(cls, msg):
        if msg.data == interface.BUTTON_OPMODE and cls.button_t is None:
            cls.button_t = time.monotonic()

    def replay(self, *args, bag=None):
        return subprocess.Popen(['rosrun', 'robopuppet', 'replay', bag or self.bag] + list(args),
                                stderr=subprocess.PIPE, text=True)

    def test_1_baxter_follows_the_recorded_path(self):
        started, started_ros = time.monotonic(), rospy.get_time()
        process = self.replay()
        _, err = process.communicate(timeout=40)
        self.assertEqual(process.returncode, 0, err)
        with self.lock:
            samples = [(t, q) for t, q in self.measured if t > started_ros]
        m_t = np.array([t for t, _ in samples])
        m_q = np.array([q for _, q in samples])
        best = math.inf
        for offset in np.arange(m_t[0], m_t[-1] - DURATION_S, 0.002):  # time alignment
            inside = (m_t >= offset) & (m_t <= offset + DURATION_S)
            want = np.column_stack([np.interp(m_t[inside] - offset, self.times, column)
                                    for column in self.path.T])
            best = min(best, float(np.abs(m_q[inside] - want).max()))
        print('path error after time alignment: %.4f rad' % best)
        self.assertLess(best, 0.01)
        goes = [(t, json_position(a)) for t, c, a in self.grips if c == 'go' and t > started]
        self.assertEqual([p for _, p in goes], [100.0, 0.0, 100.0])
        self.assertAlmostEqual(goes[2][0] - goes[1][0], 1.0, delta=0.1)

    def test_2_button_1_stops_a_replay_at_once(self):
        process = self.replay('--speed', '0.5')
        start = self.path[0]
        wait_for(lambda: abs(self.baxter.arm('right')[3] - start[3]) > 0.1, 20, 'playing')
        self.puppet.press(interface.BUTTON_OPMODE)
        _, err = process.communicate(timeout=10)
        self.assertEqual(process.returncode, 1, err)
        self.assertIn('button 1', err)
        commands = self.baxter.commands_since('right', self.button_t)
        stay = commands[-1][2]
        first_stay_t = next(t for t, _, c in commands if c == stay)
        self.assertTrue(all(c == stay for t, _, c in commands if t >= first_stay_t))
        print('stop latency after button 1: %.3f s' % (first_stay_t - self.button_t))
        self.assertLess(first_stay_t - self.button_t, 0.2)
        here = self.baxter.arm('right')
        self.assertLess(max(abs(a - b) for a, b in zip(here, stay)), 0.02)

    def test_3_an_episode_into_a_keep_out_zone_stops_before_it(self):
        with open(baxter_description.URDF_PATH) as urdf:
            capsules = arm_capsules.ArmCapsules(baxter_description.load(), urdf.read(), 'right')
        guard = zones.ZoneGuard(capsules, zones.load_zones(ZONES_FILE))
        start = self.baxter.arm('right')
        self.assertGreater(guard.clearance(start).min(), 0.05)
        bag, _, path = write_episode(self.dir, start, 'episode_into_body', into_body=True)
        self.assertLess(guard.clearance(path[-1]).min(), -0.05)   # it ends 7 cm inside
        started_ros = rospy.get_time()
        process = self.replay(bag=bag)
        _, err = process.communicate(timeout=30)
        time.sleep(1.0)   # Baxter settling where it was told to stay
        self.assertEqual(process.returncode, 1, err)
        self.assertIn("keep-out zones: %s (3 zones, arm_R's zones_file)" % ZONES_FILE, err)
        self.assertRegex(err, r"stopped: keep-out zone 'patient body': \w+ of the right arm "
                              r"would enter it\n")
        with self.lock:
            rows = [q for t, q in self.measured if t > started_ros]
        self.assertGreater(len(rows), 200)
        clearance = np.array([guard.clearance(q).min() for q in rows])
        print('nearest Baxter came to a zone: %.4f m (%d samples)' % (clearance.min(),
                                                                    len(rows)))
        self.assertGreater(clearance.min(), 0.0, 'Baxter measured inside a keep-out zone')
        self.assertLess(clearance.min(), 0.03, 'the replay stopped well short of the zone')

    def test_4_a_bad_zone_file_refuses_the_replay(self):
        bad = self.dir + '/bad_zones.yaml'
        with open(bad, 'w') as stream:
            stream.write('frame: base\nshapes:\n  - {name: head, type: sphere, radius: 0, '
                         'xyz: [0.85, 0.8, -0.1]}\n')
        process = self.replay('--zones', bad)
        _, err = process.communicate(timeout=20)
        self.assertEqual(process.returncode, 2, err)
        self.assertIn("refused: %s: shape 'head': radius must be" % bad, err)


def json_position(args):
    return yaml.safe_load(args)['position']


if __name__ == '__main__':
    rospy.init_node('test_replay_sim')
    rostest.rosrun('robopuppet', 'replay_sim', ReplaySimTest)
