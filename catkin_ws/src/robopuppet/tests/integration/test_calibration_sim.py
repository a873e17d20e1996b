#!/usr/bin/python3
"""The calibration wizard on the simulated arm R, started from a deliberately wrong ini: the
test moves the virtual puppet's hand through the wizard's poses, captures (the GUI's Capture and
the end-piece button), applies, and then the puppet reports the hand's angles; the ini holds
the new values; Undo gives back the old file byte for byte."""
import math
import time
import unittest

import rospy
import rostest

from calibration_testing import CalibrationWindow
from robopuppet import settings
from robopuppet.calibration import procedure
from robopuppet.config import config_store

TOLERANCE_RAD = 0.01
# The simulated hand holds a joint through a spring, so gravity bends the shoulder (joint 1) up
# to 0.04 rad away from the hand's angle: a pose counts as reached when every reported angle is
# this close to the expected one and has stopped moving.
REACHED_RAD = 0.06
STEADY_RAD, STEADY_S = 0.002, 0.5


def firmware_report(q, cfg):
    """What the 2020 firmware reports at mechanical angle q (docs/serial.md), unclamped."""
    x = q - cfg['sign_angle'] * cfg['home_angle']
    return cfg['sign_angle'] * math.atan2(math.sin(x), math.cos(x))


class CalibrationSimTest(CalibrationWindow, unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('calibration_sim_test')
        cls.open_window()
        cls.window.tabs.setCurrentWidget(cls.tab)


    def angles(self):
        return [j.angle_rad for j in self.client.state.snapshot().joints]

    def hand(self, pose, stored):
        """Move the hand to pose; wait until the puppet reports it under `stored`, at rest."""
        self.sim.set_hand(pose)
        expected = [firmware_report(q, stored[j]) for j, q in enumerate(pose)]
        last = [None, None]  # angles, time s

        def reached_and_steady():
            angles, now_s = self.angles(), time.monotonic()
            if not all(abs(a - e) < REACHED_RAD for a, e in zip(angles, expected)):
                last[:] = [None, None]
                return False
            if last[0] is None or any(abs(a - b) > STEADY_RAD for a, b in zip(angles, last[0])):
                last[:] = [angles, now_s]
                return False
            return now_s - last[1] >= STEADY_S
        self.assertTrue(self.until(reached_and_steady), 'pose %s: reported %s, expected %s'
                        % (pose, self.angles(), expected))
        return self.angles()

    def test_wizard_calibrates_applies_and_undoes(self):
        self.assertTrue(self.until(lambda: self.sim.connected()
                                   and self.client.stored_settings() is not None))
        wrong = self.client.stored_settings()
        self.assertEqual(wrong[1]['sign_angle'], -1.0)  # the wrong seed is in force
        with open(self.ini_path, 'rb') as ini:
            original = ini.read()
        self.tab.start()
        for angle in (-0.3, 0.3, 0.0):  # the quadrature joints pass their index mark
            self.sim.set_hand([angle] * settings.NUM_JOINTS)
            self.until(lambda: not procedure.joints_to_turn(
                [(j.status, j.angle_rad) for j in self.client.state.snapshot().joints]), 5.0)
        self.assertTrue(self.until(lambda: self.tab.step == 'pose'), self.tab.instruction.text())
        for k, pose in enumerate(procedure.POSES):
            self.hand(pose.angles_rad, wrong)
            if k == 1:  # the end-piece button captures as the GUI's Capture does
                self.sim.set_grippers([0.0, 0.0, 0.0, 0.0])
                self.assertTrue(self.until(lambda: len(self.tab.session.raws) == k + 1, 5.0))
                self.sim.set_grippers([0.0, 0.0, 0.0, 1.0])
            else:
                self.tab.buttons['Capture'].click()
            self.assertEqual(len(self.tab.session.raws), k + 1, self.tab.message.text())
        self.assertEqual(self.tab.step, 'review')
        for change in self.tab.changes:
            rospy.loginfo('joint %d: %s -> %s residual %.4f rad %s', change.joint, change.old,
                          change.new, change.fit.residual_rad, change.fit.problem)
        self.assertEqual([c.fit.problem for c in self.tab.changes], [''] * settings.NUM_JOINTS)
        self.tab.buttons['Apply'].click()
        self.assertTrue(self.until(lambda: not self.tab._task.busy(), 30.0))
        self.assertIn('stored the new values', self.tab.message.text())
        self.assertTrue(self.until(lambda: self.client.stored_settings() != wrong))
        new = self.client.stored_settings()
        self.assertEqual([new[j]['sign_angle'] for j in settings.JOINTS], [1.0] * 7)
        # The puppet now reports the hand's angles (home 0, sign +1 is the simulator's truth).
        truth = {j: dict(new[j], home_angle=0.0, sign_angle=1.0) for j in settings.JOINTS}
        for pose in [p.angles_rad for p in procedure.POSES] + [(0.2, -0.3, 0.4, 0.6, -0.2,
                                                                0.3, -0.4)]:
            reported = self.hand(pose, truth)
            rospy.loginfo('pose %s: reported - hand %s', pose,
                          ['%+.4f' % (a - q) for a, q in zip(reported, pose)])
            for joint, (angle, q) in enumerate(zip(reported, pose)):
                self.assertLess(abs(angle - q), TOLERANCE_RAD, 'joint %d, pose %s' % (joint, pose))
        with open(self.ini_path) as ini:
            on_disk, problems = config_store.parse(ini.read())
        self.assertEqual(problems, [])
        for joint in settings.JOINTS:
            for name in procedure.CALIBRATED:
                self.assertEqual(on_disk[joint][name], new[joint][name])
        self.tab.buttons['Undo'].click()
        self.assertTrue(self.until(lambda: not self.tab._task.busy(), 30.0))
        self.assertIn('stored the old values', self.tab.message.text())
        with open(self.ini_path, 'rb') as ini:
            self.assertEqual(ini.read(), original)
        self.assertTrue(self.until(lambda: self.client.stored_settings() == wrong))


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'calibration_sim', CalibrationSimTest)
