#!/usr/bin/python3
"""rostest: baxter_sim with a table obstacle stops the right arm at contact when commanded down
through it (every link, from /robot/joint_states, outside the table), reports the blocked
shoulder's effort rising with how far the command lies past contact, and lets the arm move up
again with the effort gone (efforts here: beyond the gravity torques the stand-in adds)."""
import os
import time
import unittest

import numpy as np
import rospkg
import rospy
import rostest
from baxter_core_msgs.msg import AssemblyState, JointCommand
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool

from baxter_sim_testing import Latest, publisher
from waiting import wait_for
from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_statics import ArmStatics
from robopuppet.world import obstacles
from robopuppet.world.arm_capsules import ArmCapsules
from robopuppet.world.clearance import ShapeSet

PACKAGE = rospkg.RosPack().get_path('robopuppet')
TABLE = obstacles.load_obstacles(os.path.join(PACKAGE, 'tests', 'integration', 'fixtures',
                                              'table.yaml'))
URDF = open(bd.urdf_path(PACKAGE)).read()
RIGHT = bd.arm_joint_names('right')
S1 = 'right_s1'   # positive lowers the arm onto the table
S1_EFFORT_N_M = 100.0


class BaxterSimContactTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.state = Latest('/robot/state', AssemblyState)
        cls.joints = Latest('/robot/joint_states', JointState)
        cls.command_pub = publisher('/robot/limb/right/joint_command', JointCommand)
        enable = publisher('/robot/set_super_enable', Bool)
        wait_for(lambda: cls.state.msg and cls.joints.msg, 20.0, 'the stand-in to publish')
        enable.publish(Bool(True))
        wait_for(lambda: cls.state.msg.enabled, 5.0, 'the robot enabled')
        cls.capsules = ArmCapsules(bd.Description(URDF), URDF, 'right')
        cls.table = ShapeSet(TABLE)

    def joint(self, msg, name, field='position'):
        if field == 'effort':   # the press: the effort beyond the arm's gravity torque
            gravity = ArmStatics(bd.load(), 'right').gravity([self.joint(msg, n) for n in RIGHT])
            return msg.effort[msg.name.index(name)] - gravity[RIGHT.index(name)]
        return getattr(msg, field)[msg.name.index(name)]

    def clearance(self, msg):
        """The least clearance (m) of the right arm's capsules from the table in msg's pose."""
        angles = np.array([[self.joint(msg, n) for n in RIGHT]])
        return self.table.clearance(self.capsules.segments(angles), self.capsules.half_lengths,
                                    self.capsules.radii, np.inf).min()

    def command_for(self, s1_rad, duration_s, done=lambda: False):
        """Send s1's target (others neutral, mode 1) at 50 Hz for duration_s or until done()."""
        targets = dict(bd.neutral_pose('right'), right_s1=s1_rad)
        msg = JointCommand(mode=JointCommand.POSITION_MODE, names=RIGHT,
                           command=[targets[n] for n in RIGHT])
        end = time.monotonic() + duration_s
        while time.monotonic() < end and not done() and not rospy.is_shutdown():
            self.command_pub.publish(msg)
            time.sleep(0.02)

    def test_pressing_down_through_the_table_stops_at_contact_and_lifting_moves_again(self):
        self.joints.record()
        pressed = lambda: self.joint(self.joints.msg, S1, 'effort') > 0.0  # noqa: E731
        self.command_for(0.6, 10.0, pressed)
        self.assertTrue(pressed(), 'the arm never met the table')
        self.command_for(0.6, 0.5)
        contact = self.joint(self.joints.msg, S1)
        self.assertLess(contact, 0.0)      # stopped well before the 0.6 rad commanded
        self.assertAlmostEqual(self.joint(self.joints.msg, S1, 'effort'), S1_EFFORT_N_M, places=9)
        # Pressing less, then more, past contact: the arm stays, the effort follows the push.
        efforts = []
        for past in (0.05, 0.15):
            self.command_for(contact + past, 1.0)
            msg = self.joints.msg
            # It may settle within the contact margin (1 mm at the gripper is 1.3 mrad of s1).
            self.assertAlmostEqual(self.joint(msg, S1), contact, delta=0.002)
            efforts.append(self.joint(msg, S1, 'effort'))
        self.assertLess(0.0, efforts[0])
        self.assertLess(efforts[0], efforts[1])
        self.assertLess(efforts[1], S1_EFFORT_N_M)
        pushing = self.joints.stop_recording()
        clearances = [self.clearance(m) for _, m in pushing]
        self.assertGreater(min(clearances), 0.0)    # outside the table in every joint state
        self.assertLess(clearances[-1], 0.005)   # ... and at it: the guard stops 2-4 mm short
        # Lift: the arm moves up, the effort falls to zero.
        self.command_for(contact - 0.3, 5.0,
                         lambda: self.joint(self.joints.msg, S1) < contact - 0.29)
        msg = self.joints.msg
        self.assertLess(self.joint(msg, S1), contact - 0.29)
        self.assertAlmostEqual(self.joint(msg, S1, 'effort'), 0.0, places=9)
        self.assertGreater(self.clearance(msg), 0.05)


if __name__ == '__main__':
    rospy.init_node('test_baxter_sim_contact')
    rostest.rosrun('robopuppet', 'baxter_sim_contact', BaxterSimContactTest)
