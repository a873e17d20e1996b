#!/usr/bin/python3
"""The terminal command `rosrun robopuppet calibrate --side R --yes` end to end on the simulated
arm R, started from a deliberately wrong ini: the test plays the operator, posing the virtual
puppet's hand at each pose the command publishes as its calibration target and pressing Enter
once the puppet is there; the command exits 0, the ini holds the new values, and the puppet then
reports the hand's angles."""
import math
import os
import shutil
import subprocess
import threading
import time
import unittest

import rospy
import rostest
from sensor_msgs.msg import JointState

from robopuppet import baxter_description, interface, settings
from robopuppet.calibration import procedure
from robopuppet.config import config_store
from teleop_harness import PuppetArm, calibrate, max_error
from waiting import wait_for

TOLERANCE_RAD = 0.01
STILL_S, STILL_RAD = 0.5, 0.002  # posed: near the pose, moving less than this for this long
NEAR_RAD = 0.06  # gravity bends the simulated shoulder up to 0.04 rad away from the hand


def firmware_report(q, cfg):
    """What the 2020 firmware reports at mechanical angle q (docs/serial.md), unclamped."""
    x = q - cfg['sign_angle'] * cfg['home_angle']
    return cfg['sign_angle'] * math.atan2(math.sin(x), math.cos(x))


class Target:
    """The newest calibration target the command publishes, and when it came."""

    def __init__(self):
        self._lock, self.names, self.angles = threading.Lock(), None, None
        rospy.Subscriber('%s/%s' % (interface.puppet_ns('R'), interface.CALIBRATION_TARGET),
                         JointState, self._on_target, queue_size=10)

    def _on_target(self, msg):
        with self._lock:
            self.names, self.angles = list(msg.name), list(msg.position)

    def shows(self, pose):
        with self._lock:
            return self.angles is not None and max_error(self.angles, pose) < 1e-6


def stored(ini_path):
    with open(ini_path) as ini:
        values, problems = config_store.parse(ini.read())
    assert problems == [], problems
    return values


class CalibrationCommandTest(unittest.TestCase):

    def posed(self, puppet, pose, cfg):
        """Move the hand to pose; wait until the puppet reports it under cfg and keeps still."""
        puppet.hand(pose)
        expected = [firmware_report(q, cfg[j]) for j, q in enumerate(pose)]
        last = [None, 0.0]  # angles, when they were taken (monotonic s)

        def near_and_still():
            angles, now_s = puppet.angles, time.monotonic()
            if angles is None or max_error(angles, expected) > NEAR_RAD:
                return False
            if last[0] is None or max_error(angles, last[0]) > STILL_RAD:
                last[:] = [angles, now_s]
                return False
            return now_s - last[1] >= STILL_S
        wait_for(near_and_still, 20, 'puppet still at %s (reports %s)'
                 % (expected, puppet.angles))
        return list(puppet.angles)

    def test_the_command_calibrates_the_wrong_arm_and_stores_it(self):
        ini_path = rospy.get_param('~ini_path')
        self.addCleanup(shutil.rmtree, os.path.dirname(ini_path), True)
        puppet, target = PuppetArm('R'), Target()
        wait_for(lambda: os.path.exists(ini_path), 30, 'config_R writing %s' % ini_path)
        wrong = stored(ini_path)
        self.assertEqual(wrong[1]['sign_angle'], -1.0)
        calibrate(puppet, [0.0] * settings.NUM_JOINTS)  # quadrature joints through 0 rad
        command = subprocess.Popen(
            ['rosrun', 'robopuppet', 'calibrate', '--side', 'R', '--yes'],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.addCleanup(command.kill)
        for pose in procedure.POSES:
            wait_for(lambda: target.shows(pose.angles_rad), 20,
                     'the command awaiting %s (target %s)' % (pose.name, target.angles))
            self.assertEqual(target.names, baxter_description.arm_joint_names('right'))
            self.posed(puppet, pose.angles_rad, wrong)
            command.stdin.write('\n')
            command.stdin.flush()
        output = command.communicate(timeout=60)[0]
        rospy.loginfo('calibrate said:\n%s', output)
        self.assertEqual(command.returncode, 0, output)
        self.assertIn('stored joints [0, 1, 2, 3, 4, 5, 6]', output)
        new = stored(ini_path)
        self.assertEqual([new[j]['sign_angle'] for j in settings.JOINTS], [1.0] * 7)
        for joint in settings.JOINTS:  # only the calibrated settings changed
            self.assertEqual({n: v for n, v in new[joint].items()
                              if n not in procedure.CALIBRATED},
                             {n: v for n, v in wrong[joint].items()
                              if n not in procedure.CALIBRATED})
        # The puppet now reports the hand's angles (home 0, sign +1 is the simulator's truth).
        truth = {j: dict(new[j], home_angle=0.0, sign_angle=1.0) for j in settings.JOINTS}
        pose = (0.2, -0.3, 0.4, 0.6, -0.2, 0.3, -0.4)
        for joint, (angle, q) in enumerate(zip(self.posed(puppet, pose, truth), pose)):
            self.assertLess(abs(angle - q), TOLERANCE_RAD, 'joint %d' % joint)


if __name__ == '__main__':
    rospy.init_node('calibration_command_test')
    rostest.rosrun('robopuppet', 'calibration_command', CalibrationCommandTest)
