#!/usr/bin/python3
"""rostest: record episodes of the simulated system with button 4, cameras included; start and
stop quickly without leaking subscriptions; survive a kill -9."""
import math
import os
import signal
import time
import unittest
import xmlrpc.client

import rosbag
import rosgraph
import rosnode
import rospkg
import rospy
import rostest
import yaml

from robopuppet import interface
from robopuppet.cameras import sim_cameras
from robopuppet.episodes import recording
from robopuppet_msgs.msg import RecordingState
from robopuppet_msgs.srv import Record
from hand_pose import HAND_POSE
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

EPISODES = os.path.join(rospkg.get_ros_home(), 'robopuppet', 'episodes')
RATE_HZ = interface.DEFAULT_COMM_RATE_HZ
CAMERAS = interface.SIM_CAMERAS   # what main_sim renders and records
CAMERA_RATE_HZ = sim_cameras.DEFAULTS['rate']
PROMPT_S = 1.0     # a 100 Hz topic's first message is written at most this long after the start


def first_delays(bag, start_stamp_s):
    """Return {topic: s from the episode's start to its first message} of a bag."""
    delays = {}
    for topic, _, stamp in bag.read_messages():
        delays.setdefault(topic, stamp.to_sec() - start_stamp_s)
    return delays


def warm_up_cameras():
    """Watch each camera until it delivers a frame: the simulated cameras load OpenGL when first
    watched (seconds on a busy machine), as the GUI's Cameras tab would have made them do."""
    frames = set()
    watchers = [rospy.Subscriber(interface.camera_topic(c, interface.CAMERA_COMPRESSED),
                                 rospy.AnyMsg, lambda _, camera: frames.add(camera),
                                 callback_args=c)
                for c in CAMERAS]
    try:
        wait_for(lambda: frames == set(CAMERAS), 30, 'a frame of every camera')
    finally:
        for watcher in watchers:
            watcher.unregister()


def recorder_inputs():
    """Return the topics the recorder subscribes to, as the master and its connections say."""
    master = rosgraph.Master(rospy.get_name())
    _, subscribers, _ = master.getSystemState()
    registered = {topic for topic, nodes in subscribers if '/recorder' in nodes}
    api = xmlrpc.client.ServerProxy(rosnode.get_api_uri(master, '/recorder'))
    _, _, bus = api.getBusInfo(rospy.get_name())
    connected = {info[4] for info in bus if info[2] == 'i'}  # inbound connections
    return registered, connected


class EpisodesSimTest(unittest.TestCase):
    """An operator records a demonstration with button 4; then the recorder is killed."""

    def setUp(self):
        self.status = None
        rospy.Subscriber(interface.RECORDING_TOPIC, RecordingState, self._on_status)

    def _on_status(self, msg):
        self.status = msg

    def test_1_a_button_4_episode_holds_every_topic(self):
        puppet, baxter = PuppetArm('R'), Baxter()
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, HAND_POSE)
        wait_for(lambda: puppet.state() == interface.READY, 10, 'ready')
        wait_for(lambda: self.status is not None, 10, 'the recorder status')
        warm_up_cameras()

        puppet.press(interface.BUTTON_RECORD)
        wait_for(lambda: self.status.recording, 5, 'recording after button 4')
        started = time.monotonic()
        puppet.press(interface.BUTTON_RIGHT)
        wait_for(lambda: puppet.state() == interface.FOLLOWING, 5, 'following')
        for k in range(30):  # 3 s of a scripted hand trajectory at 10 Hz
            pose = list(HAND_POSE)
            pose[0] = HAND_POSE[0] + 0.3 * math.sin(k / 30 * 2 * math.pi)
            puppet.hand(pose)
            puppet.wait_sets(1)
        wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.02, 20, 'Baxter on')
        puppet.end_piece(True)
        wait_for(lambda: baxter.gripper['right'].position < 5, 10, 'right gripper closed')
        puppet.end_piece(False)
        for button in (interface.BUTTON_RIGHT, interface.BUTTON_OPMODE, interface.BUTTON_OPMODE,
                       interface.BUTTON_OPMODE):
            puppet.press(button)  # stop following; hold; feel; limp (three opmodes)
        wait_for(lambda: puppet.teleop.opmode == interface.LIMP, 5, 'limp again')
        sets = puppet.sets_since(started)
        puppet.press(interface.BUTTON_RECORD)
        wait_for(lambda: not self.status.recording and self.status.episode.endswith('.bag'), 5,
                 'stopped after the second press of button 4')
        duration_s = time.monotonic() - started
        self.assertEqual(self.status.problem, '')

        path = self.status.episode
        self.assertEqual(os.path.dirname(path), EPISODES)
        meta = yaml.safe_load(open(path[:-len('.bag')] + '.yaml'))
        with rosbag.Bag(path) as bag:
            info = bag.get_type_and_topic_info().topics
            counts = {t: i.message_count for t, i in info.items()}
            delays = first_delays(bag, meta['start_stamp'])
        figures = 'in %.1f s; first message after the start: %s' % (duration_s, ', '.join(
            '%s %.0f ms (%d)' % (t, 1000 * d, counts[t])
            for t, d in sorted(delays.items(), key=lambda x: x[1])))
        print(figures, flush=True)
        self.assertLess(delays['/robot/joint_states'], PROMPT_S, figures)  # 100 Hz
        ns = interface.puppet_ns('R')
        for topic in recording.recorded_topics(('R',), CAMERAS):
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
        for camera in CAMERAS:  # rendered because the episode subscribes; nice +10 on a busy CPU
            topic = interface.camera_topic(camera, interface.CAMERA_COMPRESSED)
            self.assertEqual(info[topic].msg_type, 'sensor_msgs/CompressedImage')
            frames = CAMERA_RATE_HZ * (meta['duration_s'] - delays[topic])
            self.assertGreater(counts[topic], 0.2 * frames, figures)
            self.assertLess(counts[topic], 1.1 * frames + 3, figures)
        self.assertEqual(meta['cameras'], list(CAMERAS))
        self.assertEqual(meta['topics'], counts)
        self.assertTrue(meta['ended_cleanly'] and meta['sim'])
        self.assertEqual((meta['sides'], meta['comm_rate_hz'], meta['format_version']),
                         (['R'], RATE_HZ, 1))
        self.assertEqual(len(meta['ini_fingerprints']['R']), 64)
        self.assertAlmostEqual(meta['duration_s'], duration_s, delta=1.0)

    def test_2_quick_starts_and_stops_leave_only_the_buttons_subscribed(self):
        record = rospy.ServiceProxy(interface.RECORD_SERVICE, Record)
        record.wait_for_service(10)
        buttons = set(recording.button_topics(('R',)))
        self.assertEqual(recorder_inputs(), (buttons, buttons))  # idle
        answers = [record(k % 2 == 0, 'quick %d' % k, '') for k in range(20)]  # ten episodes
        self.assertEqual([a.error for a in answers if not a.ok], [])
        self.assertEqual(len({a.episode for a in answers}), 10)
        time.sleep(1.0)  # connections that were still being made when their episode stopped
        self.assertEqual(recorder_inputs(), (buttons, buttons))
        record(True, 'after the quick ones', '')  # and the next episode subscribes them all again
        episode_topics = set(recording.episode_topics(('R',), CAMERAS))
        wait_for(lambda: recorder_inputs()[0] == buttons | episode_topics, 5, 'subscriptions')
        self.assertTrue(record(False, '', '').ok)
        self.assertEqual(recorder_inputs(), (buttons, buttons))

    def test_3_a_kill_mid_episode_loses_at_most_a_second(self):
        record = rospy.ServiceProxy(interface.RECORD_SERVICE, Record)
        record.wait_for_service(10)
        answer = record(True, 'to be killed', '')
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
