#!/usr/bin/python3
"""rostest: garbage on every topic baxter_sim subscribes never kills it nor makes it publish
a non-finite or out-of-limit state, and each kind of refusal gets its own log line."""
import json
import math
import random
import time
import unittest

import rospy
import rostest
from baxter_core_msgs.msg import (AssemblyState, EndEffectorCommand, EndEffectorProperties,
                                  EndEffectorState, EndpointState, JointCommand)
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty, Float64, UInt16
from trajectory_msgs.msg import JointTrajectoryPoint

from baxter_sim_testing import Latest, publisher, warned, warnings
from waiting import wait_for
from robopuppet import baxter_description as bd
from robopuppet.interface import BAXTER_SIDES

GRIPPER_ID = 65538
RATE_HZ = 100.0
SEED = 14
BAD_FLOATS = [math.nan, math.inf, -math.inf, 1e39, -1e39, 1e308, -1e308, 5e-324, 0.0, -1.0]
HUGE_NAMES = 100000
# Joint state rates that all leave /robot/joint_states at 100 Hz (0 is refused, more is cut to
# the loop's 100 Hz), so the rate check below still holds; lower rates: baxter_sim_sdk.
PUBLISH_RATES = (0, 100, 500, 1000, 65535)


# The joint-command refusals test_1 sends, by the words of their log lines.
KINDS = (('left_s0', 'must be finite'), ('right_s0', 'must be finite'), ('right_s0', 'left arm'),
         ('twice', 'left'))


class Garbage:
    """Seeded garbage for each kind of message the stand-in subscribes."""

    def __init__(self, seed):
        self.rng = random.Random(seed)

    def number(self):
        rng = self.rng
        return rng.choice(BAD_FLOATS) if rng.random() < 0.6 else rng.uniform(-10.0, 10.0)

    def text(self):
        rng = self.rng
        return rng.choice(['', 'left_s0', 'x' * 5000, ''.join(
            chr(rng.randrange(1, 0xd7ff)) for _ in range(rng.randrange(1, 40)))])

    def joint_command(self, side):
        rng = self.rng
        names = bd.arm_joint_names(side)
        other = bd.arm_joint_names('left' if side == 'right' else 'right')
        choice = rng.randrange(8)
        if choice == 0:
            chosen = []
        elif choice == 1:
            chosen = rng.sample(other, rng.randrange(1, 8))
        elif choice == 2:
            chosen = [self.text() for _ in range(rng.randrange(1, 5))]
        elif choice == 3:
            chosen = [rng.choice(names) for _ in range(rng.randrange(2, 12))]   # repeats
        else:
            chosen = rng.sample(names, rng.randrange(1, 8))
        count = len(chosen) if rng.random() < 0.7 else rng.randrange(0, 10)
        mode = rng.choice([1, 4, 1, 4, 2, 3, 0, -1, 5, 2 ** 31 - 1, -2 ** 31])
        return JointCommand(mode=mode, names=chosen, command=[self.number() for _ in range(count)])

    def feed_forward(self):
        rng = self.rng
        return JointTrajectoryPoint(**{field: [self.number() for _ in range(rng.choice(
            [0, 7, 7, rng.randrange(0, 50)]))] for field in ('positions', 'velocities',
                                                             'accelerations')})

    def custom_gripper(self):
        rng = self.rng
        kind = rng.choice([EndEffectorProperties, EndEffectorState])
        return kind(id=rng.choice([GRIPPER_ID, 131073, rng.randrange(2 ** 32)]))

    def gripper_command(self):
        rng = self.rng
        args = rng.choice([
            '', '{"position": 1e999}', '{"position": NaN}', '{"position": -Infinity}',
            '[' * 4000, '{"position": ' + '[' * 3000, '{"position": 1' + '0' * 400 + '}',
            '{"velocity": -1e39, "dead_zone": 1e39}', '{"velocity": "fast"}', '{"position": 50}',
            '{"position": ' + json.dumps(self.number()) + '}', 'x' * 200000, '{', '"a"',
            json.dumps({'position': [1] * 1000})])
        command = rng.choice(['go', 'go', 'configure', 'calibrate', 'stop', 'reset', 'no_op',
                              'grip', '', 'x' * 10000])
        return EndEffectorCommand(id=GRIPPER_ID if rng.random() < 0.8 else rng.randrange(2 ** 32),
                                  command=command, args=args,
                                  sender=rng.choice(['fuzz', '', 'x' * 100000]),
                                  sequence=rng.randrange(2 ** 32))


class BaxterSimGarbageTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.limits = {lim.name: lim for side in BAXTER_SIDES for lim in bd.arm_limits(side)}
        cls.fingers = {name: bd.load().limit(name) for side in BAXTER_SIDES
                       for name in bd.gripper_finger_joints(side)}
        cls.joints = Latest('/robot/joint_states', JointState)
        cls.state = Latest('/robot/state', AssemblyState)
        cls.endpoint = {s: Latest('/robot/limb/%s/endpoint_state' % s, EndpointState)
                        for s in BAXTER_SIDES}
        cls.gripper = {s: Latest('/robot/end_effector/%s_gripper/state' % s, EndEffectorState)
                       for s in BAXTER_SIDES}
        cls.rosout = Latest('/rosout', Log)
        cls.enable_pub = publisher('/robot/set_super_enable', Bool)
        cls.stop_pub = publisher('/robot/set_super_stop', Empty)
        cls.reset_pub = publisher('/robot/set_super_reset', Empty)
        cls.cmd_pub, cls.ratio_pub, cls.timeout_pub, cls.gripper_pub = {}, {}, {}, {}
        cls.rate_pub = publisher('/robot/joint_state_publish_rate', UInt16)
        cls.feed_forward_pub, cls.custom_pub = {}, {}
        for side in BAXTER_SIDES:
            limb = '/robot/limb/%s/' % side
            cls.feed_forward_pub[side] = publisher(limb + 'inverse_dynamics_command',
                                                   JointTrajectoryPoint)
            rsdk = '/robot/end_effector/%s_gripper/rsdk/' % side
            cls.custom_pub[side] = {
                EndEffectorProperties: publisher(rsdk + 'set_properties', EndEffectorProperties),
                EndEffectorState: publisher(rsdk + 'set_state', EndEffectorState)}
            cls.cmd_pub[side] = publisher(limb + 'joint_command', JointCommand)
            cls.ratio_pub[side] = publisher(limb + 'set_speed_ratio', Float64)
            cls.timeout_pub[side] = publisher(limb + 'joint_command_timeout', Float64)
            cls.gripper_pub[side] = publisher('/robot/end_effector/%s_gripper/command' % side,
                                              EndEffectorCommand)
        wait_for(lambda: cls.state.msg and cls.joints.msg, 20.0, 'the stand-in to publish')

    def enable(self):
        """Reset the robot if it is stopped, then enable it (the state may lag: ask again)."""
        def enabled():
            state = self.state.msg
            if state.stopped:
                self.reset_pub.publish(Empty())
            elif not state.enabled:
                self.enable_pub.publish(Bool(True))
            return state.enabled and not state.stopped
        wait_for(enabled, 10.0, 'the robot to be enabled')

    def test_1_each_kind_of_refusal_is_logged(self):
        # The first test on a fresh stand-in: nothing was refused before, so no kind of refusal
        # is within its throttle interval.
        self.enable()
        self.rosout.record()
        # Within 2 s of a velocity refusal: a torque refusal on the other arm and an unknown
        # joint on the same arm each get their line.
        # Each kind is sent after the line of the one before: a burst of all of them would
        # overflow the stand-in's subscriber queue (10), which drops the oldest.
        for (side, mode, names, value), words in zip([
                ('left', JointCommand.VELOCITY_MODE, ['left_s0'], math.nan),
                ('right', JointCommand.TORQUE_MODE, ['right_s0'], math.inf),
                ('left', JointCommand.POSITION_MODE, ['right_s0'], 0.1),
                ('left', JointCommand.POSITION_MODE, ['left_s0'] * 2, 0.1)], KINDS):
            for _ in range(5):   # repeats of one kind are logged once
                self.cmd_pub[side].publish(JointCommand(mode=mode, names=names, command=[value]
                                                        * len(names)))
            wait_for(lambda: warned(self.rosout, *words), 5.0, 'a warning with %s' % (words,))
        self.gripper_pub['right'].publish(EndEffectorCommand(
            id=GRIPPER_ID, command='go', args='{"position": ' + '[' * 4000, sender='t',
            sequence=1))
        # Last on each topic, so handled after the repeats: a kind of refusal of its own.
        for side in BAXTER_SIDES:
            self.cmd_pub[side].publish(JointCommand(mode=1, names=['%s_s0' % side], command=[]))
            self.gripper_pub[side].publish(EndEffectorCommand(
                id=GRIPPER_ID, command='grip', args='', sender='t', sequence=2))
        wanted = list(KINDS) + [('nested too deeply', 'right_gripper')]
        last = [('1 names but 0 values', 'left arm'), ('1 names but 0 values', 'right arm'),
                ("'grip' is not supported", 'left_gripper'),
                ("'grip' is not supported", 'right_gripper')]
        wait_for(lambda: all(warned(self.rosout, *words) for words in wanted + last), 5.0,
                 'a warning for each of %s' % (wanted + last))
        lines = warnings(self.rosout.stop_recording())
        self.assertEqual(len(lines), len(wanted + last), lines)

    def test_2_garbage_on_every_topic(self):
        self.enable()
        rng = Garbage(SEED)
        for recorder in [self.joints, *self.endpoint.values(), *self.gripper.values()]:
            recorder.record()
        start = time.monotonic()
        sent = 0
        stop_s, end_s = start + 3.0, start + 5.0    # last 2 s: enable, stop and reset too
        while time.monotonic() < end_s:
            for side in BAXTER_SIDES:
                self.cmd_pub[side].publish(rng.joint_command(side))
                self.cmd_pub[side].publish(JointCommand(   # and valid motion in between
                    mode=rng.rng.choice([1, 4]), names=bd.arm_joint_names(side),
                    command=[rng.rng.uniform(-3.0, 3.0) for _ in range(7)]))
                self.ratio_pub[side].publish(Float64(rng.number()))
                self.timeout_pub[side].publish(Float64(rng.number()))
                self.gripper_pub[side].publish(rng.gripper_command())
                self.feed_forward_pub[side].publish(rng.feed_forward())
                custom = rng.custom_gripper()
                self.custom_pub[side][type(custom)].publish(custom)
                sent += 7
            self.rate_pub.publish(UInt16(rng.rng.choice(PUBLISH_RATES)))
            sent += 1
            if sent % 500 < 10:   # now and then a huge one
                self.cmd_pub['left'].publish(JointCommand(
                    mode=1, names=['left_s0'] * HUGE_NAMES, command=[1e39] * HUGE_NAMES))
            if time.monotonic() > stop_s:
                self.stop_pub.publish(Empty())
                self.reset_pub.publish(Empty())
                self.enable_pub.publish(Bool(rng.rng.random() < 0.5))
            time.sleep(0.002)
        duration_s = time.monotonic() - start
        wait_for(lambda: all(r.recorded() and r.recorded()[-1][0] > start + duration_s
                             for r in [self.joints, *self.endpoint.values(),
                                       *self.gripper.values()]),
                 5.0, 'states published after the garbage')
        joints = self.joints.stop_recording()
        endpoints = {s: r.stop_recording() for s, r in self.endpoint.items()}
        grippers = {s: r.stop_recording() for s, r in self.gripper.items()}
        rospy.loginfo('garbage: %d messages in %.1f s; %d joint states', sent, duration_s,
                      len(joints))

        # At its rate: a loaded 2-core machine may slow it, garbage must not stop it.
        self.assertGreater(len(joints), 0.5 * RATE_HZ * duration_s)
        stamps = [m.header.stamp.to_sec() for _, m in joints]
        self.assertLess(max(b - a for a, b in zip(stamps, stamps[1:])), 0.5)
        for _, msg in joints:
            self.assertEqual(len(msg.name), len(msg.position))
            self.assertEqual(len(msg.name), len(msg.velocity))
            for name, position, velocity in zip(msg.name, msg.position, msg.velocity):
                self.assertTrue(math.isfinite(position) and math.isfinite(velocity),
                                (name, position, velocity))
                limit = self.limits.get(name) or self.fingers.get(name)
                if limit is None:
                    self.assertEqual((position, velocity), (0.0, 0.0), name)   # head, torso
                    continue
                self.assertTrue(limit.lower - 1e-9 <= position <= limit.upper + 1e-9,
                                (name, position))
                self.assertLessEqual(abs(velocity), limit.velocity + 1e-6, name)
        for side in BAXTER_SIDES:
            self.assertGreater(len(endpoints[side]), 0.5 * RATE_HZ * duration_s)
            for _, msg in endpoints[side]:
                p, o = msg.pose.position, msg.pose.orientation
                self.assertTrue(all(math.isfinite(v) for v in (p.x, p.y, p.z, o.x, o.y, o.z,
                                                               o.w)))
            for _, msg in grippers[side]:
                self.assertTrue(0.0 <= msg.position <= 100.0, msg.position)
                self.assertLessEqual(len(msg.command_sender), 4096)

        # And it still obeys: a sane command is followed to its target. Garbage (enable,
        # disable, speed ratio, timeout) may still be in flight after the state reads enabled,
        # so the sane values are sent again with every command.
        targets = {'right_s0': -0.4, 'right_e1': 1.0}

        def reached():
            self.timeout_pub['right'].publish(Float64(0.2))
            self.ratio_pub['right'].publish(Float64(1.0))
            state = self.state.msg
            if state.stopped:
                self.reset_pub.publish(Empty())
            elif not state.enabled:
                self.enable_pub.publish(Bool(True))
            self.cmd_pub['right'].publish(JointCommand(mode=4, names=list(targets),
                                                       command=list(targets.values())))
            positions = dict(zip(self.joints.msg.name, self.joints.msg.position))
            return all(abs(positions[n] - v) < 1e-6 for n, v in targets.items())
        wait_for(reached, 15.0, 'the right arm to reach %s after the garbage' % targets)


if __name__ == '__main__':
    rospy.init_node('test_baxter_sim_garbage')
    rostest.rosrun('robopuppet', 'baxter_sim_garbage', BaxterSimGarbageTest)
