#!/usr/bin/python3
"""rostest: Rethink SDK 1.2.0's tuck_arms.py -t against the stand-in, its sequence written out in
our code: the same topics, types, rates, goals, tolerances and checks (the SDK is not vendored).

tuck_arms.py -t: wait for /robot/state and the head; pan the head to 0 (20 Hz, enabling the robot
and, if it started disabled, suppressing collision avoidance, then disabling it again); move each
arm whose s1 is above the "peak" (-1.6 rad) to the untuck pose until all seven joints are within
0.2 rad of it ("untuck" stage); then, suppressing collision avoidance on both arms at 20 Hz, command
the tuck pose until s0 and s1 are within 0.2 rad of it ("tuck" stage); disable the robot if any arm
reports a collision object. It returns there: the rest of the motion is the robot's.
"""
import time
import unittest

import rospy
import rostest
from baxter_core_msgs.msg import (AssemblyState, CollisionAvoidanceState, HeadPanCommand,
                                  HeadState, JointCommand)
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty

from baxter_sim_testing import Latest, publisher
from waiting import wait_for

SIDES = ('left', 'right')
JOINTS = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
RATE_HZ = 20.0                      # tuck_arms' _tuck_rate
THRESHOLD_RAD = 0.2                 # its _tuck_threshold
PEAK_RAD = -1.6                     # its _peak_angle: s1 at or below it is "flipped"
HEAD_PAN_TOLERANCE_RAD = 0.1396263401   # baxter_interface settings.HEAD_PAN_ANGLE_TOLERANCE
MOVES = {                           # its _joint_moves, s0 ... w2
    'tuck': {'left': [-1.0, -2.07, 3.0, 2.55, 0.0, 0.01, 0.0],
             'right': [1.0, -2.07, -3.0, 2.55, -0.0, 0.01, 0.0]},
    'untuck': {'left': [-0.08, -1.0, -1.19, 1.94, 0.67, 1.03, -0.50],
               'right': [0.08, -1.0, 1.19, 1.94, -0.67, 1.03, 0.50]}}
STAGE_TIMEOUT_S = 20.0              # ours: tuck_arms waits for ever
COLLISION_RATE_HZ = 100.0


def names(side):
    return ['%s_%s' % (side, joint) for joint in JOINTS]


class TuckArms:
    """tuck_arms.py -t's Tuck: its subscriptions, publishers and checks."""

    def __init__(self):
        self.collide = dict.fromkeys(SIDES, False)
        self.collisions = {side: Latest('/robot/limb/%s/collision_avoidance_state' % side,
                                        CollisionAvoidanceState) for side in SIDES}
        for latest in self.collisions.values():
            latest.record()
        self.suppress = {side: publisher('/robot/limb/%s/suppress_collision_avoidance' % side,
                                         Empty) for side in SIDES}
        self.enable = publisher('/robot/set_super_enable', Bool)
        self.commands = {side: publisher('/robot/limb/%s/joint_command' % side, JointCommand)
                         for side in SIDES}
        self.pan = publisher('/robot/head/command_head_pan', HeadPanCommand)
        self.state = Latest('/robot/state', AssemblyState)
        self.head = Latest('/robot/head/head_state', HeadState)
        self.joints = Latest('/robot/joint_states', JointState)
        wait_for(lambda: self.state.msg and self.head.msg and self.joints.msg, 10.0,
                 'the robot state, head and joint states')
        self.rate = rospy.Rate(RATE_HZ)

    def angles(self, side):
        position = dict(zip(self.joints.msg.name, self.joints.msg.position))
        return [position[name] for name in names(side)]

    def arm_state(self, side):
        """Return tuck_arms' _check_arm_state of an arm: its stage ('untuck', 'tuck' or 'none',
        the tuck goal checking s0 and s1 only) and whether it is flipped."""
        angles = self.angles(side)
        near = [abs(a - b) <= THRESHOLD_RAD for a, b in zip(angles, MOVES['untuck'][side])]
        stage = 'none'
        if all(near):
            stage = 'untuck'
        elif all(abs(a - b) <= THRESHOLD_RAD for a, b in zip(angles[:2], MOVES['tuck'][side])):
            stage = 'tuck'
        return stage, angles[1] <= PEAK_RAD

    def prepare(self):
        """_prepare_to_tuck: the head to 0, the robot enabled meanwhile."""
        start_disabled = not self.state.msg.enabled
        self.loop(lambda: abs(self.head.msg.pan) <= HEAD_PAN_TOLERANCE_RAD, 'the head at 0',
                  lambda: self.head_step(start_disabled))
        if start_disabled:
            self.loop(lambda: not self.state.msg.enabled, 'the robot disabled again',
                      self.disable_step)

    def head_step(self, start_disabled):
        if start_disabled:
            self.suppress_all()
        if not self.state.msg.enabled:
            self.enable.publish(True)
        self.pan.publish(HeadPanCommand(0.0, 0.5, True))

    def disable_step(self):
        self.suppress_all()
        self.enable.publish(False)

    def suppress_all(self):
        for pub in self.suppress.values():
            pub.publish(Empty())

    def move_to(self, goals, disabled):
        """_move_to: command each goal's pose at 20 Hz until every arm is in its goal stage;
        then disable the robot if any arm reports a collision object."""
        if any(disabled.values()):
            self.suppress_all()

        def step():
            if not self.state.msg.enabled:
                self.enable.publish(True)
            for side in SIDES:
                if disabled[side]:
                    self.suppress[side].publish(Empty())
                if side in goals:
                    self.commands[side].publish(JointCommand(
                        JointCommand.POSITION_MODE, MOVES[goals[side]][side], names(side)))
        self.loop(lambda: all(self.arm_state(side)[0] == goal for side, goal in goals.items()),
                  'the %s stage' % sorted(set(goals.values())), step)
        for side, latest in self.collisions.items():
            self.collide[side] = len(latest.msg.collision_object) > 0
        if any(self.collide.values()):
            self.enable.publish(False)

    def loop(self, done, what, step):
        deadline = time.monotonic() + STAGE_TIMEOUT_S
        while not done():
            self.assert_before(deadline, what)
            step()
            self.rate.sleep()

    @staticmethod
    def assert_before(deadline, what):
        if time.monotonic() > deadline or rospy.is_shutdown():
            raise AssertionError('tuck_arms -t: %s not reached in %g s' % (what,
                                                                             STAGE_TIMEOUT_S))

    def tuck(self):
        """supervised_tuck with -t; return {stage: {side: angles at its end}}."""
        self.prepare()
        ends = {}
        goals, disabled = {}, {'left': True, 'right': True}
        for side in SIDES:
            if not self.arm_state(side)[1]:
                goals[side], disabled[side] = 'untuck', False
        self.move_to(goals, disabled)
        ends['untuck'] = {side: self.angles(side) for side in goals}
        self.move_to({'left': 'tuck', 'right': 'tuck'}, {'left': True, 'right': True})
        ends['tuck'] = {side: self.angles(side) for side in SIDES}
        return ends


class BaxterSimTuckTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.rosout = Latest('/rosout', Log)
        cls.rosout.record()
        cls.tucker = TuckArms()
        cls.started_disabled = not cls.tucker.state.msg.enabled
        cls.ends = cls.tucker.tuck()

    def info(self, *words):
        return any(all(w in m.msg for w in words) for _, m in self.rosout.recorded()
                   if m.name == '/baxter_sim' and m.level == Log.INFO)

    def test_a_each_stage_ends_where_tuck_arms_checks(self):
        self.assertTrue(self.started_disabled)      # the stand-in starts disabled, as Baxter
        self.assertEqual(sorted(self.ends['untuck']), list(SIDES))   # neither arm flipped
        for side in SIDES:
            for angle, goal in zip(self.ends['untuck'][side], MOVES['untuck'][side]):
                self.assertLessEqual(abs(angle - goal), THRESHOLD_RAD, side)
            for angle, goal in zip(self.ends['tuck'][side][:2], MOVES['tuck'][side][:2]):
                self.assertLessEqual(abs(angle - goal), THRESHOLD_RAD, side)
            self.assertLessEqual(self.ends['tuck'][side][1], PEAK_RAD)   # flipped now

    def test_b_collision_avoidance_state_is_published_and_names_nothing(self):
        # Nothing avoided (no self-collision modelled), so tuck_arms leaves the robot enabled.
        self.assertEqual(self.tucker.collide, {'left': False, 'right': False})
        self.assertTrue(self.tucker.state.msg.enabled)
        for side, latest in self.tucker.collisions.items():
            log = latest.stop_recording()
            rate_hz = (len(log) - 1) / (log[-1][0] - log[0][0])
            self.assertTrue(0.7 * COLLISION_RATE_HZ < rate_hz < 1.3 * COLLISION_RATE_HZ,
                            (side, rate_hz))
            self.assertTrue(all(not m.other_arm and not m.collision_object for _, m in log))
            self.assertTrue(all(m.header.stamp.to_sec() > 0 for _, m in log))

    def test_c_the_suppression_is_logged_while_it_lasts(self):
        for side in SIDES:
            wait_for(lambda: self.info('%s arm: collision avoidance suppressed' % side), 5.0,
                     'the %s arm\'s suppression logged' % side)
            wait_for(lambda: self.info('%s arm: collision avoidance suppression lapsed' % side),
                     5.0, 'the %s arm\'s suppression lapsing 0.2 s after tuck_arms' % side)

    def test_d_every_joint_reaches_the_tucked_pose(self):
        """What a real Baxter ends with: tuck_arms returns once s0 and s1 are near, and the
        robot takes the rest of the way to its last position command (mode 1 has no command
        timeout: docs/baxter_sim.md, "How the arms move")."""
        def worst():
            return max((abs(a - b), n) for side in SIDES for a, b, n in zip(
                self.tucker.angles(side), MOVES['tuck'][side], names(side)))
        tucked = wait_for(lambda: worst()[0] <= THRESHOLD_RAD, 15.0)
        self.assertTrue(tucked, '%s is %.2f rad from the tucked pose' % worst()[::-1])


if __name__ == '__main__':
    rospy.init_node('test_baxter_sim_tuck')
    rostest.rosrun('robopuppet', 'test_baxter_sim_tuck', BaxterSimTuckTest)
