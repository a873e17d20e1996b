#!/usr/bin/python3
"""rostest: simulated participants through every task and every device (study.launch).

The test starts each study (the ~pairs: one participant per device:task pair, or all: one
participant, every task with every device) through the study node's service, keeps each trial's window (from
StudyState) and the gripper tip's path it measures itself on /robot/joint_states, waits for
DONE and checks the results: one row per (participant, device, task), each a success, its completion time
the trial's window and its path the measured one (within tolerances), one questionnaire row per
device; and that every trial began with both arms measured at their start (Baxter's neutral
pose, where the runner brings them).
"""
import csv
import os
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import JointState

from robopuppet import baxter_description as bd, interface
from robopuppet.study import results
from robopuppet_msgs.msg import StudyState
from robopuppet_msgs.srv import StudyStart
from waiting import wait_for

STUDY_S = 840.0       # a whole study (every trial, input restarts, questionnaires)
WINDOW_S, WINDOW_SHARE = 1.0, 0.02   # completion agrees with the window seen, within these
PATH_SHARE, PATH_M = 0.15, 0.03   # and its path with the measured one, within share + m
AT_START_RAD = 0.03   # the arms this near Baxter's neutral pose when a trial begins
NEUTRAL = {name: value for side in interface.BAXTER_SIDES
           for name, value in bd.neutral_pose(side).items()}


def rows(path):
    with open(path, newline='') as handle:
        return list(csv.DictReader(handle))


class Watch:
    """StudyState's trial windows and the gripper tips measured on /robot/joint_states."""

    def __init__(self):
        self.description = bd.load()
        self.lock = threading.Lock()
        self.last, self.windows, self.tips, self.at_start = None, {}, [], {}
        rospy.Subscriber(interface.STUDY_STATE, StudyState, self.on_state, queue_size=100)
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self.on_joints,
                         queue_size=100)

    def on_state(self, msg):
        now = rospy.get_time()
        with self.lock:
            self.last = msg
            if msg.phase == StudyState.TRIAL:
                key = (msg.participant, msg.device, msg.task)
                start, _ = self.windows.get(key, (now, now))
                self.windows[key] = (start, now)
                if key not in self.at_start and self.tips:   # the arms when it began
                    measured = self.tips[-1][1]
                    self.at_start[key] = max(abs(measured.get(n, np.inf) - v)
                                             for n, v in NEUTRAL.items())

    def on_joints(self, msg):
        with self.lock:   # the tips are worked out afterwards: no load on the running study
            self.tips.append((rospy.get_time(), dict(zip(msg.name, msg.position))))

    def phase(self):
        with self.lock:
            return None if self.last is None else self.last.phase

    def ended(self, participant):
        """Return whether the study of this participant is done or stopped."""
        with self.lock:
            return self.last is not None and self.last.participant == participant and \
                self.last.phase in (StudyState.DONE, StudyState.STOPPED)

    def path_m(self, start, end, arms):
        """Return the tips' path (m) between two times, the arms summed."""
        with self.lock:
            kept = [positions for t, positions in self.tips if start <= t <= end]
        path = 0.0
        for arm in arms if len(kept) > 1 else ():
            tips = [self.description.transform(k, bd.gripper_link(arm))[:3, 3] for k in kept]
            path += float(np.sum(np.linalg.norm(np.diff(tips, axis=0), axis=1)))
        return path


def studies():
    """Return [(participant, devices, tasks)] to run, from the ~pairs parameter."""
    pairs = rospy.get_param('~pairs')
    if pairs == 'all':
        return [('P01', rospy.get_param('~devices').split(','),
                 rospy.get_param('~tasks').split(','))]
    return [('P%02d' % (n + 1), [pair.split(':')[0]], [pair.split(':')[1]])
            for n, pair in enumerate(pairs.split(','))]


class StudySimTest(unittest.TestCase):
    """Whole studies, one after the other, into one study folder."""

    def test_every_task_and_every_device(self):
        watch = Watch()
        rospy.wait_for_service(interface.STUDY_START, 120.0)
        start = rospy.ServiceProxy(interface.STUDY_START, StudyStart)
        wanted, devices_of = [], {}
        for participant, devices, tasks in studies():
            began = time.monotonic()
            answer = start(start=True, participant=participant, devices=devices, tasks=tasks)
            self.assertTrue(answer.ok, answer.error)
            wait_for(lambda: watch.ended(participant), STUDY_S, "%s's study to end" % participant)
            print('study_sim: %s (%s; %s) took %.0f s' % (
                participant, ', '.join(devices), ', '.join(tasks), time.monotonic() - began))
            self.assertEqual(watch.phase(), StudyState.DONE, watch.last.detail)
            wanted += [(participant, d, t) for d in devices for t in tasks]
            devices_of[participant] = devices
        trials = rows(answer.results)
        self.assertEqual(sorted((r['participant'], r['device'], r['task']) for r in trials),
                         sorted(wanted))
        problems = []
        for row in trials:
            key = (row['device'], row['task'])
            arms = interface.BAXTER_SIDES if row['task'] == 'bimanual' else ('right',)
            start_t, end_t = watch.windows[(row['participant'],) + key]
            seen_m = watch.path_m(start_t, end_t, arms)
            print('study_sim: %-10s %-10s success %-5s completion %6s s (window %5.1f s) '
                  'path %6s m (measured %.2f m)' % (key + (row['success'], row['completion_s'],
                                                         end_t - start_t, row['path_m'], seen_m)))
            if watch.at_start[(row['participant'],) + key] > AT_START_RAD:
                problems.append('%s with %s: began %.3f rad off the start pose' % (
                    key[::-1] + (watch.at_start[(row['participant'],) + key],)))
            if row['success'].lower() != 'true':
                problems.append('%s with %s failed' % key[::-1])
                continue
            window = end_t - start_t
            if abs(float(row['completion_s']) - window) > WINDOW_S + WINDOW_SHARE * window:
                problems.append('%s with %s: completion %s s, window %.1f s' % (
                    key[::-1] + (row['completion_s'], window)))
            if abs(float(row['path_m']) - seen_m) > PATH_SHARE * seen_m + PATH_M:
                problems.append('%s with %s: path %s m, measured %.2f m' % (
                    key[::-1] + (row['path_m'], seen_m)))
        answers = rows(os.path.join(os.path.dirname(answer.results), results.QUESTIONNAIRE_CSV))
        self.assertEqual(sorted((r['participant'], r['device']) for r in answers),
                         sorted((p, d) for p, devices in devices_of.items() for d in devices))
        self.assertEqual(problems, [])

if __name__ == '__main__':
    rospy.init_node('test_study_sim')
    rostest.rosrun('robopuppet', 'study_sim', StudySimTest)
