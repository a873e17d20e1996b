#!/usr/bin/python3
"""rostest: the study runner started through its service with nobody driving: the arms are
brought from where they were to their start (Baxter's neutral pose) before the first trial,
every trial times out into a failed row, a questionnaire becomes a row, a stop stops, bad
starts are refused."""
import csv
import os
import threading
import unittest

import numpy as np
import rosnode
import rospy
import rostest
from baxter_core_msgs.msg import JointCommand
from sensor_msgs.msg import JointState

from robopuppet import baxter_description as bd, interface
from robopuppet.study import results
from robopuppet_msgs.msg import Questionnaire, StudyState
from robopuppet_msgs.srv import StudyStart
from waiting import wait_for

TIMEOUT_S = 3.0  # the study node's ~trial_timeout in study_runner.test
START_S = 90.0   # roslaunch of the input, arm_R ready (the simulated system comes up meanwhile)
NEUTRAL = np.array([bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES])
AWAY = NEUTRAL + (-0.3, -0.2, 0.0, 0.3, 0.0, -0.2, 0.4)   # where a trial left it (clear)
AT_START_RAD = 0.03


def rows(path):
    with open(path, newline='') as handle:
        return list(csv.DictReader(handle))


class StudyRunnerTest(unittest.TestCase):
    """One study of two timed-out trials, its questionnaire; a second one stopped."""

    def setUp(self):
        folder = rospy.get_param('~study_dir')
        self.results = os.path.join(folder, 'results')
        os.makedirs(folder, exist_ok=True)
        fifo = os.path.join(folder, 'keyboard_R')
        if not os.path.exists(fifo):
            os.mkfifo(fifo)
        # held open, never written: the keyboard's reader sees no event and never an end
        self.fifo = os.open(fifo, os.O_RDWR | os.O_NONBLOCK)
        self.states, self.lock, self.arms = [], threading.Lock(), {}
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self.on_joints, queue_size=10)
        self.sub = rospy.Subscriber(interface.STUDY_STATE, StudyState, self.on_state,
                                    queue_size=100)
        rospy.wait_for_service(interface.STUDY_START, 60.0)
        self.start = rospy.ServiceProxy(interface.STUDY_START, StudyStart)
        self.answers = rospy.Publisher(interface.STUDY_QUESTIONNAIRE, Questionnaire,
                                       queue_size=4, latch=True)

    def tearDown(self):
        self.sub.unregister()
        os.close(self.fifo)

    def on_state(self, msg):
        with self.lock:
            arms = dict(self.arms)
            self.states.append((rospy.get_time(), msg, arms))

    def on_joints(self, msg):
        positions = dict(zip(msg.name, msg.position))
        with self.lock:
            for arm in interface.BAXTER_SIDES:
                names = bd.arm_joint_names(arm)
                if all(n in positions for n in names):
                    self.arms[arm] = np.array([positions[n] for n in names])

    def move_away(self):
        """Command both arms to AWAY (nothing follows) and wait until Baxter is there."""
        pubs = {arm: rospy.Publisher(interface.limb_topic(arm, 'joint_command'), JointCommand,
                                     queue_size=10) for arm in interface.BAXTER_SIDES}

        def there():
            for arm, pub in pubs.items():
                pub.publish(JointCommand(mode=JointCommand.POSITION_MODE,
                                         names=bd.arm_joint_names(arm), command=AWAY))
            with self.lock:
                arms = dict(self.arms)
            return len(arms) == 2 and all(np.abs(a - AWAY).max() < 0.01 for a in arms.values())
        wait_for(there, 30, 'both arms away from the start')
        for pub in pubs.values():
            pub.unregister()

    def phase(self, phase, participant):
        """Return a condition: the latest state is `phase` for `participant`."""
        def latest():
            with self.lock:
                last = self.states[-1][1] if self.states else None
            return last is not None and (last.phase, last.participant) == (phase, participant)
        return latest

    def test_a_study_without_a_driver_and_a_stopped_one(self):
        answer = self.start(True, 'bad id!', [], [])
        self.assertFalse(answer.ok)
        self.assertIn('participant', answer.error)
        answer = self.start(True, 'P01', ['gamepad'], [])
        self.assertFalse(answer.ok)
        self.assertIn('no event path for gamepad', answer.error)

        self.move_away()
        answer = self.start(True, 'P01', [], [])
        self.assertTrue(answer.ok, answer.error)
        trials_csv = os.path.join(self.results, results.TRIALS_CSV)
        self.assertEqual(answer.results, trials_csv)
        wait_for(self.phase('trial', 'P01'), START_S, 'the first trial')
        with self.lock:
            first = next(arms for _, m, arms in self.states if m.phase == 'trial')
            detail = [m.detail for _, m, _ in self.states if m.phase == 'device']
        self.assertTrue(any('bringing the arms to their start' in d for d in detail), detail)
        for arm, angles in first.items():   # measured when the trial began
            self.assertLess(np.abs(angles - NEUTRAL).max(), AT_START_RAD,
                            '%s arm not at its start: %s' % (arm, angles))
        wait_for(self.phase('questionnaire', 'P01'), START_S, 'the questionnaire')
        with self.lock:
            in_trial = [t for t, m, _ in self.states if m.phase == 'trial' and m.trial == 2]
            targets = [len(m.targets) for _, m, _ in self.states if m.phase == 'trial']
        gaps = [b - a for a, b in zip(in_trial, in_trial[1:])]
        self.assertGreater(len(in_trial), 20)
        self.assertLess(sorted(gaps)[len(gaps) // 2], 0.1, 'StudyState under 10 Hz in a trial')
        self.assertTrue(all(targets), 'a trial without targets')
        written = rows(trials_csv)
        self.assertEqual([(r['participant'], r['device'], r['success']) for r in written],
                         [('P01', 'keyboard', 'false')] * 2)
        for row in written:   # the time the trial took: its timeout
            self.assertAlmostEqual(float(row['completion_s']), TIMEOUT_S, delta=0.3)
            self.assertTrue(os.path.exists(row['episode']), 'no episode %r' % row['episode'])
        self.assertEqual(sorted(r['task'] for r in written), ['reach_hold', 'trace'])
        self.assertEqual([r['trial'] for r in written], ['1', '2'])
        self.assertTrue(all(r['study'] == 'runner_test' and r['started'] for r in written))

        self.answers.publish(Questionnaire(participant='P01', device='gamepad',
                                           tlx=[50.0] * 6, sus=bytes([3] * 10)))
        self.answers.publish(Questionnaire(participant='P01', device='keyboard',
                                           tlx=[10, 20, 30, 40, 50, 60], sus=bytes([5, 1] * 5)))
        wait_for(self.phase('done', 'P01'), 20.0, 'the study done')
        answered = rows(os.path.join(self.results, results.QUESTIONNAIRE_CSV))
        self.assertEqual([(r['device'], float(r['tlx']), float(r['sus'])) for r in answered],
                         [('keyboard', 35.0, 100.0)])
        wait_for(lambda: os.path.exists(os.path.join(self.results, 'summary.md')), 20.0,
                 'the summary')
        wait_for(lambda: '/input_R' not in rosnode.get_node_names(), 20.0,
                 'the keyboard input stopped at the end')

        answer = self.start(True, 'P02', [], [])
        self.assertTrue(answer.ok, answer.error)
        wait_for(self.phase('trial', 'P02'), START_S, "P02's first trial")
        self.assertTrue(self.start(False, '', [], []).ok)
        wait_for(self.phase('stopped', 'P02'), 20.0, 'the study stopped')
        wait_for(lambda: '/input_R' not in rosnode.get_node_names(), 20.0,
                 'the keyboard input stopped')
        self.assertEqual(len(rows(trials_csv)), 2, 'a stopped trial wrote a row')


if __name__ == '__main__':
    rospy.init_node('test_study_runner')
    rostest.rosrun('robopuppet', 'test_study_runner', StudyRunnerTest)
