#!/usr/bin/python3
"""rostest: the study runner started through its service with nobody driving: every trial times
out into a failed row, a questionnaire becomes a row, a stop stops, bad starts are refused."""
import csv
import os
import threading
import unittest

import rosnode
import rospy
import rostest

from robopuppet import interface
from robopuppet.study import results
from robopuppet_msgs.msg import Questionnaire, StudyState
from robopuppet_msgs.srv import StudyStart
from waiting import wait_for

TIMEOUT_S = 3.0  # the study node's ~trial_timeout in study_runner.test
START_S = 90.0   # roslaunch of the input, arm_R ready (the simulated system comes up meanwhile)


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
        self.states, self.lock = [], threading.Lock()
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
            self.states.append((rospy.get_time(), msg))

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

        answer = self.start(True, 'P01', [], [])
        self.assertTrue(answer.ok, answer.error)
        trials_csv = os.path.join(self.results, results.TRIALS_CSV)
        self.assertEqual(answer.results, trials_csv)
        wait_for(self.phase('trial', 'P01'), START_S, 'the first trial')
        wait_for(self.phase('questionnaire', 'P01'), START_S, 'the questionnaire')
        with self.lock:
            in_trial = [t for t, m in self.states if m.phase == 'trial' and m.trial == 2]
            targets = [len(m.targets) for _, m in self.states if m.phase == 'trial']
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
