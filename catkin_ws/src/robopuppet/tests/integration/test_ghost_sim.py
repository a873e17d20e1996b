#!/usr/bin/python3
"""rostest: the ghost Baxter shows the simulated puppet's pose, mapped as arm_R maps it; the
calibration target ghost shows the pose the calibrate command awaits, else the real robot."""
import subprocess
import threading
import unittest
import xml.etree.ElementTree as ET

import numpy as np
import rosnode
import rospy
import rostest
import tf2_ros
from sensor_msgs.msg import JointState

from robopuppet import baxter_description, interface
from robopuppet.calibration import procedure
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

# Joint 3 (e1) below Baxter's lower limit -0.05 rad: clamped on both arms.
POSE = [0.5, -0.6, 0.8, -0.3, 1.0, 1.2, -0.7]
SUFFIXES = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
MIRROR_SIGNS = (-1, 1, -1, 1, -1, 1, -1)  # the opposite arm negates s0, e0, w0, w2


def urdf_limits():
    """Return {joint: (lower, upper) rad} read straight from the URDF."""
    root = ET.parse(baxter_description.URDF_PATH).getroot()
    return {j.get('name'): (float(j.find('limit').get('lower')),
                            float(j.find('limit').get('upper')))
            for j in root.findall('joint') if j.find('limit') is not None}


def mapped(side, angles, mirrored, limits):
    """Return the 7 angles Baxter's arm `side` takes from the puppet's angles (rad)."""
    result = []
    for suffix, sign, angle in zip(SUFFIXES, MIRROR_SIGNS, angles):
        lower, upper = limits['%s_%s' % (side, suffix)]
        result.append(min(max(sign * angle if mirrored else angle, lower), upper))
    return result


class Ghost:
    """What a ghost node publishes on /<name>/joint_states (names without the prefix)."""

    def __init__(self, name='ghost'):
        self._lock, self.joints, self.prefix = threading.Lock(), {}, name + '/'
        rospy.Subscriber('/%s/joint_states' % name, JointState, self._on_states, queue_size=10)

    def _on_states(self, msg):
        with self._lock:
            self.joints = {n[len(self.prefix):]: p for n, p in zip(msg.name, msg.position)
                           if n.startswith(self.prefix)}

    def arm(self, side):
        with self._lock:
            names = ['%s_%s' % (side, s) for s in SUFFIXES]
            return [self.joints[n] for n in names] if all(n in self.joints for n in names) \
                else None


class GhostSimTest(unittest.TestCase):

    def test_the_ghost_shows_the_puppet_mapped_and_sinks_into_baxter_when_it_dies(self):
        puppet, baxter, ghost = PuppetArm('R'), Baxter(), Ghost()
        tf = tf2_ros.Buffer()
        tf2_ros.TransformListener(tf)
        limits = urdf_limits()
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, POSE)
        wait_for(lambda: puppet.angles[3] < -0.1, 10,
                 'the puppet elbow beyond Baxter e1 limit (puppet at %s)' % puppet.angles)

        def ghost_on_the_puppet():
            angles = puppet.angles
            right, left = ghost.arm('right'), ghost.arm('left')
            return right is not None and left is not None and \
                max_error(right, mapped('right', angles, False, limits)) < 1e-9 and \
                max_error(left, mapped('left', angles, True, limits)) < 1e-9
        wait_for(ghost_on_the_puppet, 15, 'ghost arms on the mapped puppet pose (ghost %s %s, '
                 'puppet %s)' % (ghost.arm('right'), ghost.arm('left'), puppet.angles))
        right = ghost.arm('right')
        self.assertAlmostEqual(right[3], -0.05, places=6)  # e1 clamped at its lower limit
        self.assertFalse(puppet.teleop.follow_left or puppet.teleop.follow_right)

        # Its tf frames: the root pinned on Baxter's base, the grippers where the ghost's
        # angles put them (forward kinematics of the URDF), away from the real grippers.
        pin = tf.lookup_transform('base', 'ghost/base', rospy.Time(0), rospy.Duration(10))
        self.assertEqual((pin.transform.translation.x, pin.transform.translation.y,
                          pin.transform.translation.z, pin.transform.rotation.w), (0, 0, 0, 1))
        description = baxter_description.load()
        for side in interface.BAXTER_SIDES:
            angles = dict(zip(baxter_description.arm_joint_names(side), ghost.arm(side)))
            want = description.transform(angles, '%s_gripper' % side)[:3, 3]

            def tool_point(frame):
                t = tf.lookup_transform('base', frame, rospy.Time(0),
                                        rospy.Duration(5)).transform.translation
                return np.array([t.x, t.y, t.z])
            wait_for(lambda: np.linalg.norm(tool_point('ghost/%s_gripper' % side) - want) < 1e-3,
                     10, 'ghost/%s_gripper at %s (tf %s)' % (
                         side, want, tool_point('ghost/%s_gripper' % side)))
            self.assertGreater(np.linalg.norm(tool_point('%s_gripper' % side) - want), 0.05,
                               'the real %s gripper is elsewhere' % side)

        self.check_the_calibration_target(baxter, tf, limits)

        # The puppet dies: the ghost stops pretending and takes the real arms' angles.
        rosnode.kill_nodes(['/puppet_sim_R'])
        for side in interface.BAXTER_SIDES:
            wait_for(lambda: max_error(ghost.arm(side), baxter.arm(side)) < 1e-3, 5,
                     'ghost %s arm on the real one' % side)

    def check_the_calibration_target(self, baxter, tf, limits):
        """The target ghost: on the real robot, then the pose the calibrate command awaits
        (pose A after a capture of the zero pose; the left arm mirrored), then the real robot
        again once the command quits."""
        target = Ghost('target')

        def target_on(want, what):
            wait_for(lambda: all(target.arm(s) is not None and
                                 max_error(target.arm(s), want[s]()) < 1e-6
                                 for s in interface.BAXTER_SIDES), 10,
                     'target arms on %s (target %s %s)' % (what, target.arm('right'),
                                                           target.arm('left')))
        real = {s: (lambda s=s: baxter.arm(s)) for s in interface.BAXTER_SIDES}
        target_on(real, 'the real robot')
        command = subprocess.Popen(['rosrun', 'robopuppet', 'calibrate', '--side', 'R'],
                                   stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True)
        self.addCleanup(command.kill)
        zero = {s: (lambda: [0.0] * 7) for s in interface.BAXTER_SIDES}
        target_on(zero, "Baxter's zero pose")
        command.stdin.write('\n')  # capture the zero pose: pose A is awaited next
        command.stdin.flush()
        pose_a = procedure.POSES[1].angles_rad
        target_on({'right': lambda: mapped('right', pose_a, False, limits),
                   'left': lambda: mapped('left', pose_a, True, limits)}, 'pose A')
        want = description_transform(target.arm('right'), 'right')

        def gripper():
            t = tf.lookup_transform('base', 'target/right_gripper', rospy.Time(0),
                                    rospy.Duration(5)).transform.translation
            return np.array([t.x, t.y, t.z])
        wait_for(lambda: np.linalg.norm(gripper() - want) < 1e-3, 10,
                 'target/right_gripper at %s (tf %s)' % (want, gripper()))
        output = command.communicate('q\n', timeout=20)[0]
        self.assertEqual(command.returncode, 1, output)
        target_on(real, 'the real robot after the command quit')


def description_transform(angles, side):
    """Return where the URDF puts side's gripper (m, in base) at these arm angles (rad)."""
    positions = dict(zip(baxter_description.arm_joint_names(side), angles))
    return baxter_description.load().transform(positions, '%s_gripper' % side)[:3, 3]


if __name__ == '__main__':
    rospy.init_node('test_ghost_sim')
    rostest.rosrun('robopuppet', 'ghost_sim', GhostSimTest)
