#!/usr/bin/python3
"""rostest, end to end: main_sim.launch headless with the simulated puppet, operated by hand."""
import math
import time
import unittest

import rosnode
import rospy
import rostest

from robopuppet import interface
from robopuppet.arm.joint_motion import mirror
from hand_pose import HAND_POSE
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for


class MainSimTest(unittest.TestCase):
    """One operator session on the right puppet, in the order an operator works."""

    def test_operator_session(self):
        puppet, baxter = PuppetArm('R'), Baxter()
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30,
                 'arm_R calibrating with Baxter enabled (now %s)' % puppet.state())
        self.assertTrue(all(not c for c in baxter.commands.values()),
                        'no joint command before calibration')
        puppet.end_piece(False)

        calibrate(puppet, HAND_POSE)
        wait_for(lambda: puppet.state() == interface.READY, 5, 'ready')

        # Button 3: Baxter's right arm follows, approaching slowly, then tracks the hand.
        puppet.press(interface.BUTTON_RIGHT)
        wait_for(lambda: puppet.teleop.follow_right and puppet.state() == interface.FOLLOWING, 5,
                 'following right')
        for k in range(40):  # a slow hand trajectory: a step per state set, 4 s at 10 Hz
            pose = list(HAND_POSE)
            pose[0] = HAND_POSE[0] + 0.3 * math.sin(k / 40 * 2 * math.pi)
            pose[3] = HAND_POSE[3] + 0.2 * math.sin(k / 40 * 2 * math.pi)
            puppet.hand(pose)
            puppet.wait_sets(1)
        wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.01, 20,
                 'right arm on the puppet pose')
        self.assert_commands_safe(baxter, 'right')

        # Button 2: the left arm mirrors the puppet.
        puppet.press(interface.BUTTON_LEFT)
        wait_for(lambda: max_error(baxter.arm('left'), mirror(puppet.angles)) < 0.01, 20,
                 'left arm on the mirrored puppet pose')
        self.assertTrue(puppet.teleop.follow_left and puppet.teleop.follow_right)

        # The end-piece button closes and opens both following grippers.
        puppet.end_piece(True)
        wait_for(lambda: all(baxter.gripper[s].position < 5 for s in interface.BAXTER_SIDES), 10,
                 'both grippers closed')
        puppet.end_piece(False)
        wait_for(lambda: all(baxter.gripper[s].position > 95 for s in interface.BAXTER_SIDES), 10,
                 'both grippers open')

        # Stop following, move the puppet away, let go and press 1: hold drives the puppet to
        # Baxter's right arm.
        puppet.press(interface.BUTTON_LEFT)
        puppet.press(interface.BUTTON_RIGHT)
        wait_for(lambda: puppet.state() == interface.READY, 5, 'ready again')
        robot = baxter.arm('right')
        away = [a + (0.3 if j in (0, 3) else 0.0) for j, a in enumerate(HAND_POSE)]
        puppet.hand(away)
        wait_for(lambda: max_error(puppet.angles, away) < 0.05, 10, 'puppet moved away')
        puppet.hand([math.nan] * 7)
        puppet.press(interface.BUTTON_OPMODE)
        wait_for(lambda: puppet.teleop.opmode == interface.HOLD, 5, 'opmode hold')
        wait_for(lambda: max_error(puppet.angles, robot) < 0.05, 15,
                 'puppet at Baxter pose %s (now %s)' % (robot, puppet.angles))
        # Button 1 again: feel; a limp set on <ns>/opmode by another node (as the GUI does) is
        # arm_R's opmode too.
        puppet.press(interface.BUTTON_OPMODE)
        wait_for(lambda: puppet.teleop.opmode == interface.FEEL, 5, 'opmode feel')
        puppet.wait_sets(5)
        puppet.set_opmode(interface.LIMP)
        wait_for(lambda: puppet.teleop.opmode == interface.LIMP, 5, 'opmode limp adopted')

        # Follow again, then the puppet dies: commands stop within 0.5 s of its last data.
        puppet.hand(puppet.angles)
        puppet.press(interface.BUTTON_RIGHT)
        wait_for(lambda: puppet.state() == interface.FOLLOWING, 5, 'following again')
        wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.02, 20,
                 'right arm on the puppet pose again')
        rosnode.kill_nodes(['/puppet_sim_R'])
        wait_for(lambda: puppet.state() == interface.FAULT, 5, 'fault after the puppet died')
        self.assertIn('joint states', puppet.teleop.detail)
        # arm_R reports again (at least every 0.5 s) after it stopped: it has had its say.
        fault_t = time.monotonic()
        wait_for(lambda: puppet.reports_since(fault_t), 5, 'a teleop_state after the fault')
        last_data = puppet.states_t[-1]
        last_command = baxter.commands['right'][-1][0]
        self.assertLess(last_command - last_data, interface.STOP_WITHIN_S)

    def assert_commands_safe(self, baxter, side):
        """Every command names the arm's joints, stays in limits and never jumps."""
        commands = baxter.commands[side]
        self.assertGreater(len(commands), 100)
        previous = None
        for t, names, command in commands:
            self.assertEqual(names, baxter.names[side])
            for angle, limit in zip(command, baxter.limits[side]):
                self.assertTrue(limit.lower <= angle <= limit.upper, (angle, limit))
            if previous is not None:
                dt = max(t - previous[0], 0.0) + 0.02  # reception jitter
                for a, b, limit in zip(command, previous[1], baxter.limits[side]):
                    self.assertLessEqual(abs(a - b), limit.velocity * dt + 1e-6)
            previous = (t, command)
        rates = len(commands) / (commands[-1][0] - commands[0][0])
        self.assertGreaterEqual(rates, 90, 'Baxter needs a steady command stream')


if __name__ == '__main__':
    rospy.init_node('test_main_sim')
    rostest.rosrun('robopuppet', 'main_sim', MainSimTest)
