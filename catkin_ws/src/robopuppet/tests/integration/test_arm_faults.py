#!/usr/bin/python3
"""rostest: the arm controller under faults, on main_sim.launch headless.

Garbage on /robot/joint_states, a hold while the puppet is away from 0 rad, feel's setpoints at
the state rate, and a frozen puppet (SIGSTOP of puppet_sim_R, found by its pid): the controller
keeps its command stream, never sends the puppet a setpoint it did not mean, stops Baxter where
it is, and does not follow again without a new press.
"""
import os
import signal
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32

from robopuppet import baxter_description, interface
from hand_pose import HAND_POSE
from teleop_harness import (Baxter, PuppetArm, calibrate, max_error, node_pid,
                            swinging_hand, wait_for)

AWAY_FROM_ZERO_RAD = 0.1
STREAM_COMMANDS = 100   # commands over which the stream's rate is measured


class Recorder:
    """What the simulated firmware does in hold: (setpoints, reported angles) per control tick."""

    def __init__(self):
        self.ticks = []
        self.setpoints_t = []   # reception times of joint_0's setpoints (arm_R sends all seven)
        rospy.Subscriber('%s/%s' % (interface.sim_ns('R'), interface.SIM_CONTROL), JointState,
                         self._on_tick, queue_size=500)
        rospy.Subscriber(interface.joint_topic('R', 0, 'setpoint'), Float32,
                         lambda m: self.setpoints_t.append(time.monotonic()), queue_size=500)

    def _on_tick(self, msg):
        self.ticks.append((list(msg.position), list(msg.velocity)))

    def setpoints_since(self, t):
        """Return how many joint_0 setpoints arrived after monotonic time t."""
        return sum(1 for seen in list(self.setpoints_t) if seen > t)

    def zero_setpoint_ticks(self):
        """Return the control ticks with a 0 rad setpoint on a joint away from 0 rad."""
        return [tick for tick in self.ticks
                if any(s == 0.0 and abs(a) > AWAY_FROM_ZERO_RAD for s, a in zip(*tick))]


class ArmFaultsTest(unittest.TestCase):

    def test_garbage_hold_and_freeze(self):
        puppet, baxter, recorder = PuppetArm('R'), Baxter(), Recorder()
        garbage = rospy.Publisher(interface.ROBOT_JOINT_STATES, JointState, queue_size=10)
        names = baxter_description.arm_joint_names('right')
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, HAND_POSE)
        wait_for(lambda: puppet.state() == interface.READY, 5, 'ready')
        puppet.press(interface.BUTTON_RIGHT)
        # On the puppet's angles: the simulated hand holds the puppet near HAND_POSE, not on it.
        wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.02, 20,
                 'right arm on the puppet pose')

        # Garbage from "Baxter" (1e39 cannot be packed as a Float32 setpoint) until arm_R has
        # counted some, then button 1.
        def garbage_counted():
            garbage.publish(JointState(name=names, position=[1e39] * 7))
            return int(puppet.diag.get('ignored_robot_poses', 0)) > 0
        wait_for(garbage_counted, 10, 'arm_R counting the garbage poses (%s)' % puppet.diag)
        wait_for(lambda: max_error(baxter.arm('right'), HAND_POSE) < 0.1, 5,
                 'the stand-in reporting Baxter again after the garbage')
        robot = baxter.arm('right')
        puppet.press(interface.BUTTON_OPMODE)
        wait_for(lambda: puppet.teleop.opmode == interface.HOLD, 5, 'opmode hold')
        wait_for(lambda: len(recorder.ticks) > 25, 5, 'control ticks in hold')
        self.assertEqual(recorder.zero_setpoint_ticks(), [],
                         'hold drove a joint away from 0 rad toward 0')
        for setpoints, _ in recorder.ticks:
            self.assertLess(max_error(setpoints, robot), 0.05, 'hold setpoints are not Baxter')
        self.assertEqual(puppet.diag.get('callback_errors'), '0', puppet.diag)
        start = time.monotonic()
        wait_for(lambda: len(baxter.commands_since('right', start)) >= STREAM_COMMANDS, 10,
                 '%d more commands' % STREAM_COMMANDS)
        stream = baxter.commands_since('right', start)[:STREAM_COMMANDS]
        rate_hz = (len(stream) - 1) / (stream[-1][0] - stream[0][0])
        self.assertGreater(rate_hz, 80, 'the command stream stays at ~100 Hz')

        # Button 1 again: feel, whose setpoints go out once per puppet sample (the state rate),
        # not at the command rate; once more: limp.
        puppet.press(interface.BUTTON_OPMODE)
        wait_for(lambda: puppet.teleop.opmode == interface.FEEL, 5, 'opmode feel')
        puppet.wait_sets(2)
        start = time.monotonic()
        puppet.wait_sets(20)
        sets, setpoints = puppet.sets_since(start), recorder.setpoints_since(start)
        self.assertLess(abs(setpoints - sets), 4, '%d setpoints in feel for %d puppet samples'
                        % (setpoints, sets))
        puppet.press(interface.BUTTON_OPMODE)
        wait_for(lambda: puppet.teleop.opmode == interface.LIMP, 5, 'opmode limp')

        # The puppet freezes while the hand moves: fault, Baxter told to stay where it is, and
        # no following after the puppet is back until a new press.
        self.assertEqual(puppet.state(), interface.FOLLOWING)
        pid = node_pid('/puppet_sim_R')
        with swinging_hand(puppet, HAND_POSE):
            puppet.wait_sets(15)  # Baxter follows the swinging hand
            os.kill(pid, signal.SIGSTOP)
            try:
                wait_for(lambda: puppet.state() == interface.FAULT, 3, 'fault on a frozen puppet')
                at_fault = baxter.arm('right')
                self.assertIn('joint states', puppet.teleop.detail)
                last_data_t = puppet.states_t[-1]
                wait_for(lambda: baxter.commands_since('right', last_data_t) and max_error(
                    baxter.commands_since('right', last_data_t)[-1][2], baxter.arm('right'))
                    < 0.02, 5, 'Baxter standing at its last command')
                self.assertLess(max_error(baxter.arm('right'), at_fault), 0.05,
                                'Baxter went on after the fault: %s, at the fault %s'
                                % (baxter.arm('right'), at_fault))
                # Frozen long enough that the heartbeat is missed too, as the controller shows.
                wait_for(lambda: puppet.teleop.heartbeat_age > interface.HEARTBEAT_TIMEOUT_S, 5,
                         'arm_R seeing no heartbeat for %.1f s' % interface.HEARTBEAT_TIMEOUT_S)
            finally:
                os.kill(pid, signal.SIGCONT)
        wait_for(lambda: puppet.state() == interface.READY, 15, 'ready once the puppet is back')
        count, back_t = len(baxter.commands['right']), time.monotonic()
        # arm_R has stepped on fresh data (10 sets) and reported since: still ready.
        puppet.wait_sets(10)
        fresh_t = puppet.states_t[-1]
        wait_for(lambda: puppet.reports_since(fresh_t), 5, 'a teleop_state after fresh data')
        self.assertEqual([m.state for m in puppet.reports_since(back_t)],
                         [interface.READY] * len(puppet.reports_since(back_t)),
                         'following without a press')
        self.assertEqual(len(baxter.commands['right']), count, 'commands without a press')
        self.assertEqual(puppet.teleop.opmode, interface.LIMP)


if __name__ == '__main__':
    rospy.init_node('test_arm_faults')
    rostest.rosrun('robopuppet', 'arm_faults', ArmFaultsTest)
