#!/usr/bin/python3
"""rostest: feel mode on main_sim with a table in the stand-in (feel_sim.test). The operator
pushes the simulated puppet's shoulder down so that Baxter's right gripper would go into the
table: Baxter stops at the table, the puppet's motors push the hand back harder the deeper the
puppet goes, within feel mode's voltage limit; lifting the hand, Baxter follows again and the
push is gone."""
import os
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import JointState

from feel_harness import Device, fell_silent, into_feel
from robopuppet import baxter_description as bd, interface, settings
from robopuppet.baxter_sim.baxter_statics import ArmStatics
from robopuppet.puppet_sim import puppet_arm
from robopuppet.world import arm_capsules, obstacles, zones
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

TABLE_FILE = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'fixtures', 'table.yaml')
# The SDK's neutral pose (in the puppet's angle limits): the right gripper 14 cm above the table.
START = [bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES]
PUSH = 1   # the shoulder's pitch (s1): a larger angle lowers the gripper
# How far past the angle at which Baxter meets the table the hand pushes the puppet's shoulder
# (rad): in gentle feel gains (pid_kp 20 x 0.25 = 5 V/rad) the first three ask for 0.5-1.5 V,
# the last for 3 V, beyond the 2 V voltage_limit.
DEPTHS_RAD = (0.1, 0.2, 0.3, 0.6)
VOLTAGE_LIMIT_V = settings.FEEL_DEFAULTS['voltage_limit']
# Coulomb friction holds a still joint against up to this much net torque, so a static reading
# of the hand's push is this uncertain (N m).
FRICTION_NM = puppet_arm.COULOMB_FRICTION_NM[PUSH]


def pushed(pose, angle):
    moved = list(pose)
    moved[PUSH] = angle
    return moved


class RightArm:
    """Baxter's right arm from every /robot/joint_states: angles and efforts (numpy rows)."""

    def __init__(self):
        self._names = bd.arm_joint_names('right')
        self._lock, self.angles, self.efforts = threading.Lock(), [], []
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on, queue_size=1000)

    def _on(self, msg):
        index = [msg.name.index(n) for n in self._names]
        with self._lock:
            self.angles.append([msg.position[i] for i in index])
            self.efforts.append([msg.effort[i] if msg.effort else 0.0 for i in index])

    def since(self, count):
        with self._lock:
            return np.array(self.angles[count:]), np.array(self.efforts[count:])


class FeelSimTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        with open(bd.URDF_PATH) as urdf:
            capsules = arm_capsules.ArmCapsules(bd.load(), urdf.read(), 'right')
        cls.table = zones.ZoneGuard(capsules, obstacles.load_obstacles(TABLE_FILE))

    def clearance(self, pose):
        """The right arm's least clearance (m) from the table in pose (Baxter's joint order)."""
        return self.table.clearance(pose).min()

    def contact_angle(self):
        """The shoulder angle (rad) at which the pushed START pose meets the table (bisection)."""
        low, high = START[PUSH], START[PUSH] + 0.5
        self.assertGreater(self.clearance(START), 0.1)
        self.assertLess(self.clearance(pushed(START, high)), 0.0)
        while high - low > 1e-4:
            middle = (low + high) / 2.0
            low, high = (middle, high) if self.clearance(pushed(START, middle)) > 0 else \
                (low, middle)
        return low

    def settle(self, puppet, baxter, device, pose, what):
        """Move the hand to pose and let puppet and Baxter come to rest in feel; return the mean
        (pushback, PID voltages) over a second and a half of rest, pushback being the hand's
        torque (N m) less the share that holds the puppet up against gravity, and the largest
        |PID voltage| (V) from the move on.

        A puppet that falls silent for arm_R's state timeout (a simulator starved of CPU on a
        loaded machine) faults the teleop and ends feel, as it must; then the operator follows
        and enters feel again (feel_harness.into_feel) and the step is repeated, at most twice.
        Any other end of feel fails the test."""
        for attempt in range(3):
            begun = time.monotonic()
            try:
                return self._settle(puppet, baxter, device, pose, what)
            except AssertionError:
                why = fell_silent(puppet, begun)
                if why is None or attempt == 2:
                    raise
                rospy.logwarn('feel ended at %s: %s; entering feel again', what, why)
            into_feel(puppet, baxter, device)

    def _settle(self, puppet, baxter, device, pose, what):
        begun, moved = time.monotonic(), device.mark()
        puppet.hand(pose)
        wait_for(lambda: max_error(puppet.angles, pose) < 0.05, 10,
                 'puppet at %s (now %s)' % (what, puppet.angles))
        still = []

        def at_rest():
            still.append(list(puppet.angles))
            return len(still) > 20 and max_error(still[-1], still[-20]) < 0.003
        try:
            wait_for(at_rest, 10, 'puppet still at %s' % what)
        except AssertionError as error:
            raise AssertionError('%s: moved %s' % (error, np.ptp(still[-20:], axis=0)))
        robot = baxter.arm('right')
        time.sleep(0.5)
        wait_for(lambda: max_error(baxter.arm('right'), robot) < 0.002, 10, 'Baxter still')
        mark = device.mark()
        time.sleep(1.5)
        torques, voltages = device.torques_since(mark), device.voltages_since(mark)
        self.assertGreater(len(torques), 5, 'hand torques at %s' % what)
        self.assertGreater(len(voltages), 30, 'control ticks at %s' % what)
        self.assertEqual([m.detail for m in puppet.reports_since(begun)
                          if m.opmode != interface.FEEL], [], 'feel ended at %s' % what)
        gravity = puppet_arm.ArmPhysics(puppet.angles).gravity_nm
        return (np.mean(torques, axis=0) + gravity, np.mean(voltages, axis=0),
                np.abs(device.voltages_since(moved)).max())

    def test_the_puppet_pushes_back_where_baxter_meets_the_table(self):
        contact = self.contact_angle()
        puppet, baxter, device, robot = PuppetArm('R'), Baxter(), Device('R'), RightArm()
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, START)
        wait_for(lambda: puppet.state() == interface.READY, 5, 'ready')
        into_feel(puppet, baxter, device)

        free, _, _ = self.settle(puppet, baxter, device, START, 'the start, 14 cm above the table')
        self.assertLess(abs(free[PUSH]), 2 * FRICTION_NM, 'the motors push on a free arm')

        start = len(robot.angles)
        steps, most_v = [], 0.0   # (depth rad, pushback N m, voltage V) per depth; |V| max
        for depth in DEPTHS_RAD:
            pose = pushed(START, contact + depth)
            what = 'the shoulder %.2f rad past the table (the gripper %.0f cm into it)' % (
                depth, -100 * self.clearance(pose))
            pushback, voltage, step_v = self.settle(puppet, baxter, device, pose, what)
            most_v = max(most_v, step_v)
            held = baxter.arm('right')
            self.assertLess(held[PUSH], contact + 0.005, 'Baxter went through the table')
            self.assertLess(self.clearance(held), 0.01, 'Baxter stopped short of the table')
            steps.append((puppet.angles[PUSH] - held[PUSH], pushback[PUSH], voltage[PUSH]))
        report = 'free %.2f N m; pushed (rad past Baxter: N m at V) %s' % (free[PUSH], ', '.join(
            '%.2f: %.2f at %.2f' % s for s in steps))
        rospy.loginfo('feel_sim: %s', report)
        angles, efforts = robot.since(start)
        self.assertGreater(min(self.clearance(q) for q in angles[::5]), 0.0,
                           'Baxter measured in the table')
        press = efforts[-1] - ArmStatics(bd.load(), 'right').gravity(angles[-1])   # beyond gravity
        self.assertGreater(press[PUSH], 0.0, 'Baxter reports no push on the table')

        # The hand feels the motors pull back toward Baxter (up): more the deeper it pushes,
        # up to what the voltage limit allows.
        most_nm = puppet_arm.STALL_TORQUE_NM[PUSH] * VOLTAGE_LIMIT_V / puppet_arm.NOMINAL_VOLTAGE_V
        self.assertGreater(steps[0][1], free[PUSH] + 0.05, report)
        for shallow, deep in zip(steps[:2], steps[1:3]):
            self.assertGreater(deep[1], shallow[1] + 0.08, report)
            self.assertLess(deep[2], shallow[2] - 0.2, report)   # the motor pushes up
        self.assertGreater(steps[3][1], steps[2][1] - FRICTION_NM, report)
        self.assertLess(steps[3][1], most_nm + 2 * FRICTION_NM, report)
        self.assertLess(steps[3][2], -0.95 * VOLTAGE_LIMIT_V, report)   # at the limit
        self.assertLessEqual(most_v, VOLTAGE_LIMIT_V + 1e-4,
                             'a PID voltage beyond the feel voltage_limit')

        # Lift: Baxter follows the puppet again, and the push is gone.
        lifted, _, _ = self.settle(puppet, baxter, device, START, 'the start again')
        wait_for(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.01, 20,
                 'Baxter back on the puppet')
        self.assertEqual(puppet.teleop.opmode, interface.FEEL)
        self.assertLess(abs(lifted[PUSH] - free[PUSH]), 2 * FRICTION_NM,
                        'free %.3f, lifted %.3f N m' % (free[PUSH], lifted[PUSH]))


if __name__ == '__main__':
    rospy.init_node('test_feel_sim')
    rostest.rosrun('robopuppet', 'feel_sim', FeelSimTest)
