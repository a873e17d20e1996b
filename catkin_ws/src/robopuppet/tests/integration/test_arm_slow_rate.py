#!/usr/bin/python3
"""rostest: arm_X at comm_rate 2 Hz (main_sim.launch headless, the simulated puppet at 2 Hz).

A state set every 0.5 s is normal at this rate: the controller reaches ready and stays there
(it used to flap between ready and fault with a timeout fixed for 10 Hz), says in /diagnostics
that a silent puppet stops Baxter later than 0.5 s at this rate, and still stops following when
the puppet goes silent (SIGSTOP of puppet_sim_R).
"""
import os
import signal
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticStatus

from robopuppet import interface
from hand_pose import HAND_POSE
from teleop_harness import Baxter, PuppetArm, calibrate, max_error, node_pid
from waiting import wait_for

STEADY_SETS = 12  # 6 s of state sets at 2 Hz


class SlowRateTest(unittest.TestCase):

    def test_ready_steady_and_stopped_by_silence_at_2_hz(self):
        puppet, baxter = PuppetArm('R'), Baxter()
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, HAND_POSE)
        wait_for(lambda: puppet.state() == interface.READY, 10, 'ready')

        # Steady: over 6 s of state sets, and a report after them, nothing but ready.
        ready_t = time.monotonic()
        puppet.wait_sets(STEADY_SETS, timeout_s=20)
        last_set_t = puppet.states_t[-1]
        wait_for(lambda: puppet.reports_since(last_set_t), 5, 'a teleop_state after the sets')
        self.assertEqual({m.state for m in puppet.reports_since(ready_t)}, {interface.READY})

        # The stop time at this rate, in /diagnostics.
        wait_for(lambda: puppet.diag_status is not None, 5, 'arm_R on /diagnostics')
        self.assertEqual(puppet.diag.get('comm_rate_hz'), '2')
        self.assertEqual(puppet.diag.get('stop_within_s'), '2.10')
        self.assertEqual(puppet.diag_status.level, DiagnosticStatus.WARN)
        self.assertIn('only after 2.10 s', puppet.diag_status.message)

        # Follow, then the puppet goes silent: fault, and Baxter is no longer commanded.
        puppet.press(interface.BUTTON_RIGHT)
        # On the puppet's angles: the simulated hand holds the puppet near HAND_POSE, not on it
        # (gravity bends joints 1 and 3 by 0.01-0.025 rad against the hand).
        wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.02, 20,
                 'right arm on the puppet pose')
        pid = node_pid('/puppet_sim_R')
        os.kill(pid, signal.SIGSTOP)
        try:
            wait_for(lambda: puppet.state() == interface.FAULT, 10, 'fault on a silent puppet')
            self.assertRegex(puppet.teleop.detail, 'no (joint states|heartbeat)')
            fault_t = time.monotonic()
            wait_for(lambda: puppet.reports_since(fault_t), 5, 'a teleop_state after the fault')
            count = len(baxter.commands['right'])
            later_t = time.monotonic()
            wait_for(lambda: puppet.reports_since(later_t), 5, 'another teleop_state')
            self.assertEqual(len(baxter.commands['right']), count, 'commands after the fault')
        finally:
            os.kill(pid, signal.SIGCONT)


if __name__ == '__main__':
    rospy.init_node('test_arm_slow_rate')
    rostest.rosrun('robopuppet', 'arm_slow_rate', SlowRateTest)
