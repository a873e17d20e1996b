#!/usr/bin/python3
"""rostest: a second recorder beside a recording one (same episodes folder, or its own folder
on the same master) refuses to start and touches nothing; a killed recorder's respawn takes its
folder and /puppet/record over; an episode's task comes from the service, else from the
recorder's ~task, and `episodes set-task` changes it once the episode has stopped."""
import os
import signal
import subprocess
import tempfile
import unittest
import xmlrpc.client

import rosbag
import rosgraph
import rospkg
import rospy
import rostest
import yaml
from sensor_msgs.msg import JointState

from robopuppet import interface
from robopuppet.episodes import recording
from robopuppet_msgs.msg import RecordingState
from robopuppet_msgs.srv import Record
from waiting import wait_for

EPISODES = os.path.join(rospkg.get_ros_home(), 'robopuppet', 'episodes')
SECOND_S = 30.0   # a refusing recorder exits within this (rosrun and imports included)


def size(path):
    return os.path.getsize(path) if os.path.exists(path) else 0


def pid_of(node):
    master = rosgraph.Master(rospy.get_name())
    return xmlrpc.client.ServerProxy(master.lookupNode(node)).getPid(rospy.get_name())[2]


def providers():
    """Return the nodes the master lists as serving /puppet/record."""
    _, _, services = rosgraph.Master(rospy.get_name()).getSystemState()
    return [nodes for name, nodes in services if name == interface.RECORD_SERVICE]


def nodes():
    """Return every node the master knows of."""
    return {node for kind in rosgraph.Master(rospy.get_name()).getSystemState()
            for _, names in kind for node in names}


def second_recorder(*args):
    """Run `rosrun robopuppet recorder` with args to its end; return (exit code, stderr)."""
    proc = subprocess.run(['rosrun', 'robopuppet', 'recorder'] + list(args), text=True,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=SECOND_S)
    print('second recorder %s: exit %d: %s' % (args, proc.returncode, proc.stderr), flush=True)
    return proc.returncode, proc.stderr


class RecorderSecondTest(unittest.TestCase):
    """A tester starts a second recorder while the first records."""

    @classmethod
    def setUpClass(cls):
        publisher = rospy.Publisher('/robot/joint_states', JointState, queue_size=10)
        cls.timer = rospy.Timer(rospy.Duration(0.01), lambda _: publisher.publish(
            JointState(name=['right_s0'], position=[0.0])))  # something to record, 100 Hz
        cls.status = None
        rospy.Subscriber(interface.RECORDING_TOPIC, RecordingState,
                         lambda msg: setattr(cls, 'status', msg))
        cls.record = rospy.ServiceProxy(interface.RECORD_SERVICE, Record)
        cls.record.wait_for_service(20)

    def serving(self):
        """Return True when /puppet/record answers (a stop while idle: 'not recording')."""
        try:
            return not self.record(False, '', '').ok
        except rospy.ServiceException:
            return False

    def start_episode(self, notes, task=''):
        answer = self.record(True, notes, task)
        self.assertTrue(answer.ok, answer.error)
        # A status while recording, but for the start's, follows a flush (the 0.5 s loop).
        wait_for(lambda: self.status.recording and self.status.episode == answer.episode
                 and self.status.duration_s > 0.4, 10, 'the episode flushed')
        return answer.episode, answer.episode + '.active'

    def stop_episode(self, episode):
        answer = self.record(False, '', '')
        self.assertTrue(answer.ok, answer.error)
        self.assertEqual(answer.episode, episode)
        with rosbag.Bag(episode) as bag:  # whole: opens without a reindex
            self.assertGreater(bag.get_message_count('/robot/joint_states'), 10)
        meta = yaml.safe_load(open(episode[:-len('.bag')] + '.yaml'))
        self.assertTrue(meta['ended_cleanly'])
        return meta

    def test_1_a_second_recorder_on_the_same_folder_refuses_and_touches_nothing(self):
        episode, active = self.start_episode('the live one')
        meta_path = episode[:-len('.bag')] + '.yaml'
        meta = open(meta_path).read()
        first = pid_of('/recorder')

        code, said = second_recorder('__name:=recorder2', '_sides:=R')  # as the tester did
        at_exit = size(active)
        self.assertEqual(code, 2)
        self.assertIn('episodes folder %s is in use by another recorder (pid %d /recorder)' % (
            EPISODES, first), said)
        self.assertEqual(providers(), [['/recorder']])
        self.assertNotIn('/recorder2', nodes())  # it registered nothing
        self.assertFalse(os.path.exists(episode))  # not "repaired" under the live recorder
        self.assertEqual(open(meta_path).read(), meta)
        wait_for(lambda: size(active) > at_exit, 5, 'the live episode growing on')
        self.assertEqual(self.stop_episode(episode)['notes'], 'the live one')

    def test_2_a_recorder_in_another_folder_does_not_steal_the_service(self):
        episode, _ = self.start_episode('the live one')
        first = pid_of('/recorder')
        with tempfile.TemporaryDirectory() as other:
            code, said = second_recorder('__name:=recorder3', '_sides:=R',
                                         '_episodes_dir:=%s' % other)
            self.assertEqual(code, 2)
            self.assertIn('%s is served already by /recorder (pid %d)' % (
                interface.RECORD_SERVICE, first), said)
            self.assertEqual(os.listdir(other), [recording.LOCK_FILE])  # no episode, no repair
        self.assertEqual(providers(), [['/recorder']])
        self.assertNotIn('/recorder3', nodes())
        self.stop_episode(episode)

    def test_3_a_killed_recorders_respawn_takes_its_folder_and_service_over(self):
        episode, active = self.start_episode('to be killed')
        killed = pid_of('/recorder')
        os.kill(killed, signal.SIGKILL)  # recorder.launch respawns it 1 s later
        wait_for(lambda: os.path.exists(episode) and not os.path.exists(active), 30,
                 'the respawned recorder repairing %s' % active)
        with rosbag.Bag(episode) as bag:
            self.assertGreater(bag.get_message_count(), 0)
        self.assertFalse(yaml.safe_load(open(episode[:-len('.bag')] + '.yaml'))['ended_cleanly'])
        wait_for(self.serving, 10, 'the respawned recorder serving %s' % interface.RECORD_SERVICE)
        respawned = pid_of('/recorder')
        self.assertNotEqual(respawned, killed)
        code, said = second_recorder('__name:=recorder2', '_sides:=R')  # the folder is its
        self.assertEqual(code, 2)
        self.assertIn('(pid %d /recorder)' % respawned, said)
        episode, _ = self.start_episode('after the respawn')
        self.stop_episode(episode)

    def test_4_the_task_given_else_the_recorders_lands_in_the_metadata(self):
        episode, _ = self.start_episode('own task', '  pick up the cup  ')
        code, said = set_task(episode, 'changed while recording')
        self.assertEqual(code, 1)
        self.assertIn('is still being recorded', said)
        self.assertEqual(self.stop_episode(episode)['task'], 'pick up the cup')
        self.assertEqual(set_task(episode, 'pick up the mug'), (0, ''))
        meta = yaml.safe_load(open(episode[:-len('.bag')] + '.yaml'))
        self.assertEqual((meta['task'], meta['notes'], meta['ended_cleanly']),
                         ('pick up the mug', 'own task', True))
        episode, _ = self.start_episode('default task')  # recorder_second.test's ~task
        self.assertEqual(self.stop_episode(episode)['task'], 'hand the cup to the patient')
        for task, why in (('pick up\nthe cup', 'one line'), ('x' * 501, 'at most 500'),
                          ('bell\a', 'printable')):
            answer = self.record(True, '', task)
            self.assertFalse(answer.ok)
            self.assertIn(why, answer.error)
            self.assertEqual(answer.episode, '')
            wait_for(lambda: self.status is not None and why in self.status.problem, 5,
                     'the status saying %s' % why)
            self.assertFalse(self.status.recording)
        self.assertFalse(self.record(False, '', '').ok)  # nothing was started


def set_task(episode, task):
    """Run `rosrun robopuppet episodes set-task episode --task task`; return (exit, stderr)."""
    proc = subprocess.run(['rosrun', 'robopuppet', 'episodes', 'set-task', episode, '--task',
                           task], text=True, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          timeout=SECOND_S)
    return proc.returncode, proc.stderr


if __name__ == '__main__':
    rospy.init_node('test_recorder_second')
    rostest.rosrun('robopuppet', 'recorder_second', RecorderSecondTest)
