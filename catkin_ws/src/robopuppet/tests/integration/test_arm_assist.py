#!/usr/bin/python3
"""rostest: arm_R drives Baxter's left arm from the assist's targets (a scripted assist here),
on main_sim.launch headless with both puppets.

Button 2 on puppet R engages the assist while targets come; the arm reaches the target, holds
where it is while the targets say hold or stop coming (the detail says why), moves on when they
come back, refuses a target for its own arm, and goes to puppet L when that one takes it over.
"""
import threading
import time
import unittest

import rospy
import rostest

from robopuppet import interface
from robopuppet.arm.joint_motion import mirror
from robopuppet_msgs.msg import AssistTarget
from hand_pose import HAND_POSE
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

# Baxter's left arm mirroring HAND_POSE, and joint 3 moved 0.3 rad: clear of config/zones.yaml
# on the way from neutral and around the pose (hand_pose.py).
TARGET = mirror(HAND_POSE)
MOVED = TARGET[:3] + [TARGET[3] + 0.3] + TARGET[4:]
UNFAMILIAR = 'assist holding: unfamiliar motion'
HELD_COMMANDS = 50   # commands to the held arm checked: half a second at 100 Hz


class ScriptedAssist:
    """Send AssistTargets for Baxter's left arm to arm_R at 100 Hz while `sending` is set."""

    def __init__(self):
        self.pub = rospy.Publisher('%s/%s' % (interface.puppet_ns('R'), interface.ASSIST_TARGET),
                                   AssistTarget, queue_size=10)
        self.side, self.position, self.hold, self.detail = 'left', TARGET, False, ''
        self.sending, self.stop = threading.Event(), threading.Event()
        self.sending.set()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        while not self.stop.is_set() and not rospy.is_shutdown():
            if self.sending.is_set():
                msg = AssistTarget(side=self.side, position=list(self.position),
                                   gripper_closed=False, confidence=0.9, hold=self.hold,
                                   detail=self.detail)
                msg.header.stamp = rospy.Time.now()
                self.pub.publish(msg)
            self.stop.wait(0.01)   # the assist's pace, not a wait for anything


class ArmAssistTest(unittest.TestCase):

    def test_engage_hold_resume_and_take_over(self):
        left, right, baxter = PuppetArm('L'), PuppetArm('R'), Baxter()
        for puppet in (left, right):
            wait_for(lambda: puppet.state() == interface.CALIBRATING, 30,
                     'arm_%s calibrating' % puppet.side)
            puppet.end_piece(False)
        calibrate(left, TARGET)
        calibrate(right, HAND_POSE)
        assist = ScriptedAssist()
        # The press engages the assist only once arm_R has a target: connected first (the
        # press then takes a state set, 0.1 s, to arrive; targets go every 10 ms).
        wait_for(lambda: assist.pub.get_num_connections() > 0, 10, 'arm_R taking assist targets')
        pressed = time.monotonic()
        right.press(interface.BUTTON_LEFT)
        wait_for(lambda: right.teleop.assist_left and right.state() == interface.FOLLOWING, 5,
                 'arm_R assisting the left arm')
        self.assertFalse(right.teleop.follow_left)
        # what arm_R said on engaging (a keep-out zone may hold the arm on its way at once)
        engaged = [m for m in right.reports_since(pressed) if m.assist_left]
        self.assertEqual(engaged[0].detail, "the assist drives Baxter's left arm")
        wait_for(lambda: max_error(baxter.arm('left'), TARGET) < 0.02, 20,
                 "Baxter's left arm on the assist's target")

        # Hold: the targets say hold and move on; the arm stays where it is.
        assist.position, assist.hold, assist.detail = MOVED, True, UNFAMILIAR
        wait_for(lambda: right.teleop.detail == UNFAMILIAR, 5, 'arm_R holding: %s' % UNFAMILIAR)
        held = baxter.arm('left')
        since = time.monotonic()
        wait_for(lambda: len(baxter.commands_since('left', since)) >= HELD_COMMANDS, 5,
                 '%d commands to the held arm' % HELD_COMMANDS)
        self.assertLess(max_error(baxter.arm('left'), held), 0.01)
        self.assertLess(max(max_error(c, held) for _, _, c in
                            baxter.commands_since('left', since)), 0.01)
        self.assertTrue(right.teleop.assist_left)

        # Moving targets again: the arm goes on to them.
        assist.hold, assist.detail = False, ''
        wait_for(lambda: max_error(baxter.arm('left'), MOVED) < 0.02, 20, 'the arm on MOVED')
        self.assertEqual(right.teleop.detail, "the assist drives Baxter's left arm")

        # No targets for 0.2 s: held, saying so; they come back: on to the target again.
        assist.sending.clear()
        wait_for(lambda: right.teleop.detail == 'assist holding: no prediction for 0.2 s', 5,
                 'arm_R holding without predictions')
        assist.position = TARGET
        assist.sending.set()
        wait_for(lambda: max_error(baxter.arm('left'), TARGET) < 0.02, 20, 'the arm on TARGET')

        # A target for arm_R's own arm is refused and counted.
        assist.side = 'right'
        wait_for(lambda: int(right.diag.get('refused_assist_targets', 0)) > 0, 5,
                 'arm_R counting refused targets (%s)' % right.diag)
        assist.side = 'left'

        # Puppet L takes its arm over: arm_R lets go (no "both let go"), L drives it.
        left.press(interface.BUTTON_LEFT)
        wait_for(lambda: left.teleop.follow_left and not right.teleop.assist_left, 5,
                 'puppet L driving the left arm, arm_R no longer assisting it')
        self.assertIn("puppet L took Baxter's left arm over from the assist",
                      right.teleop.detail)
        self.assertTrue(left.teleop.follow_left)
        wait_for(lambda: max_error(baxter.arm('left'), left.angles) < 0.02, 20,
                 "Baxter's left arm on puppet L's pose")
        assist.stop.set()


if __name__ == '__main__':
    rospy.init_node('test_arm_assist')
    rostest.rosrun('robopuppet', 'arm_assist', ArmAssistTest)
