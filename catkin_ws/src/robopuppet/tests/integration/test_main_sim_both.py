#!/usr/bin/python3
"""rostest, end to end: both puppet arms at once, each driving Baxter's arm on its own side."""
import time
import unittest

import rospy
import rostest

from robopuppet import interface
from hand_pose import HAND_POSE
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

# The left arm as is (not mirrored), raised like HAND_POSE: on its way from neutral no nearer to
# config/zones.yaml than there (5.4 cm), 39 cm from them at the pose.
POSE_L = [0.3, -0.8, 0.4, 1.2, 0.2, 0.5, -0.2]
POSE_R = HAND_POSE


class BothArmsTest(unittest.TestCase):

    def test_each_puppet_drives_its_own_side(self):
        left, right, baxter = PuppetArm('L'), PuppetArm('R'), Baxter()
        for puppet in (left, right):
            wait_for(lambda: puppet.state() == interface.CALIBRATING, 30,
                     'arm_%s calibrating' % puppet.side)
            puppet.end_piece(False)
        calibrate(left, POSE_L)
        calibrate(right, POSE_R)
        left.press(interface.BUTTON_LEFT)
        right.press(interface.BUTTON_RIGHT)
        wait_for(lambda: left.teleop.follow_left and not left.teleop.follow_right, 5,
                 'L puppet drives the left arm only')
        wait_for(lambda: right.teleop.follow_right and not right.teleop.follow_left, 5,
                 'R puppet drives the right arm only')
        wait_for(lambda: max_error(baxter.arm('left'), left.angles) < 0.01
                 and max_error(baxter.arm('right'), right.angles) < 0.01, 20,
                 'each arm on its own puppet pose')
        # The right puppet cannot take the left arm from the left puppet.
        right.press(interface.BUTTON_LEFT)
        wait_for(lambda: 'other puppet' in right.teleop.detail, 5,
                 'the R puppet told that the other puppet drives the left arm')
        self.assertFalse(right.teleop.follow_left)
        # The two puppets differ, so neither arm can be following the other puppet.
        self.assertGreater(max_error(left.angles, right.angles), 0.3)
        # Each puppet talks to its own serial port: both report at their state rate.
        start = time.monotonic()
        wait_for(lambda: left.sets_since(start) > 15 and right.sets_since(start) > 15, 5,
                 'state sets from both puppets')


if __name__ == '__main__':
    rospy.init_node('test_main_sim_both')
    rostest.rosrun('robopuppet', 'main_sim_both', BothArmsTest)
