#!/usr/bin/python3
"""rostest: the arm controller under faults, on main_sim.launch headless.

Garbage on /robot/joint_states, a hold while the puppet is away from 0 rad, and a frozen puppet
(SIGSTOP of puppet_sim_R, found by its pid): the controller keeps its command stream, never
sends the puppet a setpoint it did not mean, stops Baxter where it is, and does not follow again
without a new press.
"""
import os
import signal
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState

from robopuppet import baxter_description
from robopuppet.arm import teleop
from teleop_harness import (Baxter, PuppetArm, calibrate, max_error, node_pid,
                            swinging_hand, wait_for)

POSE_A = [0.2, 0.4, 0.3, 1.0, -0.3, 0.6, 0.25]
AWAY_FROM_ZERO_RAD = 0.1


class Recorder:
    """What the simulated firmware does in hold, and arm_R's diagnostics values."""

    def __init__(self):
        self.ticks = []  # (setpoints, reported angles) per control tick in hold
        self.diag = {}
        rospy.Subscriber('/puppet_sim/arm_R/control', JointState, self._on_tick, queue_size=500)
        rospy.Subscriber('/diagnostics', DiagnosticArray, self._on_diag, queue_size=100)

    def _on_tick(self, msg):
        self.ticks.append((list(msg.position), list(msg.velocity)))

    def _on_diag(self, msg):
        for status in msg.status:
            if status.name.startswith('arm_R'):
                self.diag = {kv.key: kv.value for kv in status.values}

    def zero_setpoint_ticks(self):
        """Return the control ticks with a 0 rad setpoint on a joint away from 0 rad."""
        return [tick for tick in self.ticks
                if any(s == 0.0 and abs(a) > AWAY_FROM_ZERO_RAD for s, a in zip(*tick))]


class ArmFaultsTest(unittest.TestCase):

    def test_garbage_hold_and_freeze(self):
        puppet, baxter, recorder = PuppetArm('R'), Baxter(), Recorder()
        garbage = rospy.Publisher('/robot/joint_states', JointState, queue_size=10)
        names = baxter_description.arm_joint_names('right')
        wait_for(lambda: puppet.state() == teleop.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, POSE_A)
        wait_for(lambda: puppet.state() == teleop.READY, 5, 'ready')
        puppet.press(3)
        wait_for(lambda: max_error(baxter.arm('right'), POSE_A) < 0.02, 20,
                 'right arm on the puppet pose')

        # Garbage from "Baxter" (1e39 cannot be packed as a Float32 setpoint), then button 1.
        for _ in range(20):
            garbage.publish(JointState(name=names, position=[1e39] * 7))
            time.sleep(0.01)
        robot = baxter.arm('right')
        puppet.press(1)
        wait_for(lambda: puppet.teleop.opmode == 'hold', 5, 'opmode hold')
        wait_for(lambda: len(recorder.ticks) > 25, 5, 'control ticks in hold')
        self.assertEqual(recorder.zero_setpoint_ticks(), [],
                         'hold drove a joint away from 0 rad toward 0')
        for setpoints, _ in recorder.ticks:
            self.assertLess(max_error(setpoints, robot), 0.05, 'hold setpoints are not Baxter')
        wait_for(lambda: int(recorder.diag.get('ignored_robot_poses', 0)) > 0, 5,
                 'arm_R counting the garbage poses (diagnostics %s)' % recorder.diag)
        self.assertEqual(recorder.diag.get('callback_errors'), '0', recorder.diag)
        count, start = len(baxter.commands['right']), time.monotonic()
        time.sleep(1.0)
        rate_hz = (len(baxter.commands['right']) - count) / (time.monotonic() - start)
        self.assertGreater(rate_hz, 80, 'the command stream stays at ~100 Hz')
        puppet.press(1)
        wait_for(lambda: puppet.teleop.opmode == 'limp', 5, 'opmode limp')

        # The puppet freezes for 3 s while the hand moves: fault, Baxter told to stay, and no
        # following after the puppet is back until a new press.
        self.assertEqual(puppet.state(), teleop.FOLLOWING)
        pid = node_pid('/puppet_sim_R')
        with swinging_hand(puppet, POSE_A):
            time.sleep(1.5)
            os.kill(pid, signal.SIGSTOP)
            try:
                wait_for(lambda: puppet.state() == teleop.FAULT, 3, 'fault on a frozen puppet')
                fault_t = time.monotonic()
                time.sleep(0.3)
                self.assertIn('joint states', puppet.teleop.detail)
                after = [c for c in baxter.commands['right'] if c[0] > puppet.states_t[-1]]
                self.assertTrue(after, 'no command after the last puppet data')
                stay = after[-1][2]
                self.assertLess(max_error(stay, baxter.arm('right')), 0.02,
                                'the last command is not where Baxter stands: %s vs %s'
                                % (stay, baxter.arm('right')))
                time.sleep(max(0.0, 3.0 - (time.monotonic() - fault_t)))
            finally:
                os.kill(pid, signal.SIGCONT)
        wait_for(lambda: puppet.state() == teleop.READY, 15, 'ready once the puppet is back')
        count = len(baxter.commands['right'])
        time.sleep(1.5)
        self.assertEqual(puppet.state(), teleop.READY, 'following without a press')
        self.assertEqual(len(baxter.commands['right']), count, 'commands without a press')
        self.assertEqual(puppet.teleop.opmode, 'limp')


if __name__ == '__main__':
    rospy.init_node('test_arm_faults')
    rostest.rosrun('robopuppet', 'arm_faults', ArmFaultsTest)
