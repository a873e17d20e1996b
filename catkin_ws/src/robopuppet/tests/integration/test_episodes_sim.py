#!/usr/bin/python3
"""rostest: record episodes of the simulated system with button 4; survive a kill -9."""
import math
import os
import signal
import time
import unittest
import xmlrpc.client

import rosbag
import rosgraph
import rospkg
import rospy
import rostest
import yaml

from robopuppet import interface
from robopuppet.episodes import recording
from robopuppet_msgs.msg import RecordingState
from robopuppet_msgs.srv import Record
from teleop_harness import Baxter, PuppetArm, calibrate, max_error, wait_for

POSE = [0.2, 0.4, 0.3, 1.0, -0.3, 0.6, 0.25]
EPISODES = os.path.join(rospkg.get_ros_home(), 'robopuppet', 'episodes')
RATE_HZ = interface.DEFAULT_COMM_RATE_HZ


class EpisodesSimTest(unittest.TestCase):
    """An operator records a demonstration with button 4; then the recorder is killed."""

    def setUp(self):
        self.status = None
        rospy.Subscriber(recording.RECORDING_TOPIC, RecordingState, self._on_status)

    def _on_status(self, msg):
        self.status = msg

    def test_1_a_button_4_episode_holds_every_topic(self):
        puppet, baxter = PuppetArm('R'), Baxter()
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, POSE)
        wait_for(lambda: puppet.state() == interface.READY, 10, 'ready')
        wait_for(lambda: self.status is not None, 10, 'the recorder status')

        puppet.press(recording.RECORD_BUTTON)
        wait_for(lambda: self.status.recording, 5, 'recording after button 4')
        started = time.monotonic()
        puppet.press(interface.BUTTON_RIGHT)
        wait_for(lambda: puppet.state() == interface.FOLLOWING, 5, 'following')
        for k in range(30):  # 3 s of a scripted hand trajectory at 10 Hz
            pose = list(POSE)
            pose[0] = POSE[0] + 0.3 * math.sin(k / 30 * 2 * math.pi)
            puppet.hand(pose)
            puppet.wait_sets(1)
        wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.02, 20, 'Baxter on')
        puppet.end_piece(True)
        wait_for(lambda: baxter.gripper['right'].position < 5, 10, 'right gripper closed')
        puppet.end_piece(False)
        for button in (interface.BUTTON_RIGHT, interface.BUTTON_HOLD, interface.BUTTON_HOLD):
            puppet.press(button)  # stop following; hold; limp (two opmodes)
        wait_for(lambda: puppet.teleop.opmode == interface.LIMP, 5, 'limp again')
        sets = puppet.sets_since(started)
        puppet.press(recording.RECORD_BUTTON)
        wait_for(lambda: not self.status.recording and self.status.episode.endswith('.bag'), 5,
                 'stopped after the second press of button 4')
        duration_s = time.monotonic() - started
        self.assertEqual(self.status.problem, '')

        path = self.status.episode
        self.assertEqual(os.path.dirname(path), EPISODES)
        with rosbag.Bag(path) as bag:
            counts = {t: i.message_count
                      for t, i in bag.get_type_and_topic_info().topics.items()}
        ns = interface.puppet_ns('R')
        for topic in recording.recorded_topics(('R',)):
            if 'left' not in topic or 'state' in topic:  # Baxter's left arm is not commanded
                self.assertGreater(counts.get(topic, 0), 0, topic)
        self.assertEqual(counts[ns + '/stored_settings'], 1)
        self.assertGreaterEqual(counts[ns + '/teleop_state'], 1)
        self.assertGreaterEqual(counts[ns + '/opmode'], 2)
        self.assertGreaterEqual(counts[ns + '/user_btn'], 8)  # 4 presses, each down and up
        self.assertAlmostEqual(counts[ns + '/joint_states'], sets, delta=0.15 * sets + 3)
        self.assertAlmostEqual(counts[ns + '/joint_states'], duration_s * RATE_HZ,
                               delta=0.2 * duration_s * RATE_HZ)
        self.assertGreater(counts['/robot/limb/right/joint_command'], 50 * duration_s)
        meta = yaml.safe_load(open(path[:-len('.bag')] + '.yaml'))
        self.assertEqual(meta['topics'], counts)
        self.assertTrue(meta['ended_cleanly'] and meta['sim'])
        self.assertEqual((meta['sides'], meta['comm_rate_hz'], meta['format_version']),
                         (['R'], RATE_HZ, 1))
        self.assertEqual(len(meta['ini_fingerprints']['R']), 64)
        self.assertAlmostEqual(meta['duration_s'], duration_s, delta=1.0)

    def test_2_a_kill_mid_episode_loses_at_most_a_second(self):
        record = rospy.ServiceProxy(recording.RECORD_SERVICE, Record)
        record.wait_for_service(10)
        answer = record(True, 'to be killed')
        self.assertTrue(answer.ok, answer.error)
        time.sleep(2.0)  # an episode of a few seconds; what the kill keeps is checked below
        api = rosgraph.Master(rospy.get_name()).lookupNode('/recorder')
        _, _, pid = xmlrpc.client.ServerProxy(api).getPid(rospy.get_name())
        killed_t = rospy.get_time()
        os.kill(pid, signal.SIGKILL)
        active = answer.episode + '.active'
        self.assertTrue(os.path.exists(active))
        wait_for(lambda: not os.path.exists(active), 30,
                 'the respawned recorder repairing %s' % active)
        with rosbag.Bag(answer.episode) as bag:
            self.assertGreater(bag.get_end_time(), killed_t - 1.2)
            self.assertGreater(bag.get_message_count(), 0)
        meta = yaml.safe_load(open(answer.episode[:-len('.bag')] + '.yaml'))
        self.assertFalse(meta['ended_cleanly'])
        self.assertEqual(meta['notes'], 'to be killed')


if __name__ == '__main__':
    rospy.init_node('test_episodes_sim')
    rostest.rosrun('robopuppet', 'episodes_sim', EpisodesSimTest)
