#!/usr/bin/python3
"""The wizard's motor check on the simulated arm R whose ini has joint 5's sign_motor flipped:
the test holds the virtual puppet's hand on every joint but the one being checked (let go: NaN);
the check finds exactly joint 5, the PID never drives more than the safe voltage, the ini comes
back byte for byte, and Flip stores joint 5's corrected sign_motor."""
import math
import threading
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState

from calibration_testing import CalibrationWindow
from robopuppet import interface, settings
from robopuppet.calibration import motor_check

WRONG_JOINT = 5
# The arm hangs down (joint 1 pitches it down, joint 3 straightens the rest below): gravity
# hardly loads a joint, as the wizard asks; the safe 1.5 V could not lift the forearm.
POSE = (0.0, 1.3, 0.0, 0.27, 0.0, 0.0, 0.0)
SAFE_V = 1.5  # written out: the most the check may ever let a motor get (V)


class Control:
    """The simulated firmware's PID voltages in hold (every 50 Hz control tick): the largest."""

    def __init__(self, side):
        self._lock, self.max_v, self.ticks = threading.Lock(), 0.0, 0
        rospy.Subscriber('%s/%s' % (interface.sim_ns(side), interface.SIM_CONTROL), JointState,
                         self._on_tick, queue_size=1000)

    def _on_tick(self, msg):
        with self._lock:
            self.ticks += 1
            self.max_v = max([self.max_v] + [abs(v) for v in msg.effort if math.isfinite(v)])


class CalibrationMotorsTest(CalibrationWindow, unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('calibration_motors_test')
        cls.open_window()


    def statuses(self):
        return [j.status for j in self.client.state.snapshot().joints]

    def test_the_check_finds_the_flipped_motor_within_the_safe_voltage_and_restores(self):
        control = Control('R')
        self.assertTrue(self.until(lambda: self.sim.connected()
                                   and self.client.stored_settings() is not None, 30))
        before = self.client.stored_settings()
        self.assertEqual(before[WRONG_JOINT]['sign_motor'], -1.0)
        with open(self.ini_path, 'rb') as ini:
            original = ini.read()
        for angle in (-0.3, 0.3, POSE[0]):  # the quadrature joints pass their index mark
            self.sim.set_hand([angle, POSE[1], angle, POSE[3], angle, POSE[5], angle])
            self.until(lambda: False, 1.0)  # the hand's pace, not a wait for anything
        self.sim.set_hand(POSE)
        self.assertTrue(self.until(lambda: self.statuses() == [interface.WORKING] * 7, 10),
                        self.statuses())
        self.tab.buttons['Motors'].click()
        self.assertEqual(self.tab.step, 'motors')
        let_go = [None]

        def hand_follows_the_check():  # let go of the joint being checked only
            joint = self.tab.motors.joint()
            if joint != let_go[0]:
                let_go[0] = joint
                self.sim.set_hand([math.nan if j == joint else a for j, a in enumerate(POSE)])
            return self.tab.step != 'motors'
        self.assertTrue(self.until(hand_follows_the_check, 120), self.tab.instruction.text())
        self.sim.set_hand(POSE)
        motors = self.tab.motors
        rospy.loginfo('motor check: %s %s; the most voltage in hold %.3f V over %d ticks',
                      motors.results, motors.error, control.max_v, control.ticks)
        self.assertEqual(motors.error, '')
        self.assertEqual(motors.results, {j: motor_check.WRONG if j == WRONG_JOINT
                                          else motor_check.RIGHT for j in settings.JOINTS})
        self.assertGreater(control.ticks, 0)
        self.assertLessEqual(control.max_v, SAFE_V + 1e-6)
        self.assertTrue(self.until(lambda: self.client.stored_settings() == before, 10))
        with open(self.ini_path, 'rb') as ini:
            self.assertEqual(ini.read(), original)
        self.assertTrue(self.until(
            lambda: self.client.state.snapshot().opmode == interface.LIMP, 5))
        # Flip corrects exactly the joint found.
        self.assertTrue(self.tab.buttons['Flip'].isEnabled())
        self.tab.buttons['Flip'].click()
        self.assertTrue(self.until(lambda: not self.tab._task.busy(), 30))
        self.assertTrue(self.until(lambda: self.client.stored_settings() != before, 10))
        after = self.client.stored_settings()
        self.assertEqual([after[j]['sign_motor'] for j in settings.JOINTS], [1.0] * 7)
        for joint in settings.JOINTS:
            self.assertEqual({n: v for n, v in after[joint].items() if n != 'sign_motor'},
                             {n: v for n, v in before[joint].items() if n != 'sign_motor'})


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'calibration_motors', CalibrationMotorsTest)
