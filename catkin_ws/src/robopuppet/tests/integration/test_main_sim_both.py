#!/usr/bin/python3
"""rostest, end to end: both puppet arms at once, each driving Baxter's arm on its own side."""
import time
import unittest

import rospy
import rostest

from robopuppet.arm import teleop
from teleop_harness import Baxter, PuppetArm, calibrate, max_error, wait_for

POSE_L = [-0.3, 0.3, 0.4, 1.2, 0.2, 0.5, -0.2]
POSE_R = [0.25, 0.5, -0.3, 0.8, -0.25, 0.7, 0.3]


class BothArmsTest(unittest.TestCase):

    def test_each_puppet_drives_its_own_side(self):
        left, right, baxter = PuppetArm('L'), PuppetArm('R'), Baxter()
        for puppet in (left, right):
            wait_for(lambda: puppet.state() == teleop.CALIBRATING, 30,
                     'arm_%s calibrating' % puppet.side)
            puppet.end_piece(False)
        calibrate(left, POSE_L)
        calibrate(right, POSE_R)
        left.press(2)
        right.press(3)
        wait_for(lambda: left.teleop.follow_left and not left.teleop.follow_right, 5,
                 'L puppet drives the left arm only')
        wait_for(lambda: right.teleop.follow_right and not right.teleop.follow_left, 5,
                 'R puppet drives the right arm only')
        wait_for(lambda: max_error(baxter.arm('left'), left.angles) < 0.01
                 and max_error(baxter.arm('right'), right.angles) < 0.01, 20,
                 'each arm on its own puppet pose')
        # The right puppet cannot take the left arm from the left puppet.
        right.press(2)
        time.sleep(0.5)
        self.assertFalse(right.teleop.follow_left)
        self.assertIn('other puppet', right.teleop.detail)
        # The two puppets differ, so neither arm can be following the other puppet.
        self.assertGreater(max_error(left.angles, right.angles), 0.3)
        # Each puppet talks to its own serial port: both report at their state rate.
        count_l, count_r = len(left.states_t), len(right.states_t)
        time.sleep(2.0)
        self.assertGreater(len(left.states_t) - count_l, 15)
        self.assertGreater(len(right.states_t) - count_r, 15)


if __name__ == '__main__':
    rospy.init_node('test_main_sim_both')
    rostest.rosrun('robopuppet', 'main_sim_both', BothArmsTest)
