#!/usr/bin/python3
"""rostest: baxter_sim obeys Baxter's ROS API; its endpoint_state equals robot_state_publisher's
tf. Topic names are Rethink's, spelled out: the test checks the stand-in against them."""
import json
import math
import os
import subprocess
import time
import unittest

import rospkg
import rospy
import rostest
import tf2_ros
from baxter_core_msgs.msg import (AssemblyState, EndEffectorCommand, EndEffectorProperties,
                                  EndEffectorState, EndpointState, JointCommand)
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty

from baxter_sim_testing import Latest, publisher, warned
from waiting import wait_for
from robopuppet import baxter_description as bd
from robopuppet.interface import BAXTER_SIDES

URDF = os.path.join(rospkg.RosPack().get_path('robopuppet'), 'urdf', 'baxter.urdf')
DESC = bd.load(URDF)
TORSO_WARNING_S = 10.0   # robot_state_publisher's period of a warning about an unknown joint


class BaxterSimTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.state = Latest('/robot/state', AssemblyState)
        cls.joints = Latest('/robot/joint_states', JointState)
        cls.endpoint = {s: Latest('/robot/limb/%s/endpoint_state' % s, EndpointState)
                        for s in BAXTER_SIDES}
        cls.gripper = Latest('/robot/end_effector/left_gripper/state', EndEffectorState)
        cls.props = Latest('/robot/end_effector/left_gripper/properties', EndEffectorProperties)
        cls.rosout = Latest('/rosout', Log)
        cls.enable_pub = publisher('/robot/set_super_enable', Bool)
        cls.stop_pub = publisher('/robot/set_super_stop', Empty)
        cls.reset_pub = publisher('/robot/set_super_reset', Empty)
        cls.cmd_pub = {s: publisher('/robot/limb/%s/joint_command' % s, JointCommand)
                       for s in BAXTER_SIDES}
        cls.gripper_pub = publisher('/robot/end_effector/left_gripper/command',
                                    EndEffectorCommand)
        cls.tf_buffer = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf_buffer)
        wait_for(lambda: cls.state.msg and cls.joints.msg and cls.gripper.msg, 20.0,
                 'the stand-in to publish')

    def set_enabled(self, enable):
        self.enable_pub.publish(Bool(enable))
        wait_for(lambda: self.state.msg.enabled == enable, 5.0, 'enabled == %s' % enable)

    def positions(self):
        msg = self.joints.msg
        return dict(zip(msg.name, msg.position))

    def command_until(self, side, mode, targets, done, timeout_s, what, rate_hz=50.0):
        """Send one JointCommand repeatedly, as a controller does, until done() or timeout.

        Returns (first, last) monotonic publish times. Raises AssertionError on timeout.
        """
        names = list(targets)
        msg = JointCommand(mode=mode, names=names, command=[targets[n] for n in names])
        first = last = time.monotonic()
        end = first + timeout_s
        while not done():
            if time.monotonic() > end or rospy.is_shutdown():
                raise AssertionError('timed out after %.1f s waiting for %s' % (timeout_s, what))
            last = time.monotonic()
            self.cmd_pub[side].publish(msg)
            time.sleep(1.0 / rate_hz)
        return first, last

    def command_for(self, side, mode, targets, duration_s):
        """Send one JointCommand repeatedly for duration_s; return (first, last) publish times."""
        end = time.monotonic() + duration_s
        return self.command_until(side, mode, targets, lambda: time.monotonic() > end,
                                  duration_s + 1.0, 'the command period')

    def at_targets(self, targets):
        positions = self.positions()
        return all(abs(positions[name] - value) < 1e-7 for name, value in targets.items())

    def test_software_version_and_urdf(self):
        self.assertEqual(rospy.get_param('/rethink/software_version'), '1.2.0')
        result = subprocess.run(['check_urdf', URDF], stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, universal_newlines=True)
        self.assertEqual(result.returncode, 0, result.stdout)
        self.assertIn('Successfully Parsed XML', result.stdout)

    def test_joint_states_layout(self):
        msg = self.joints.msg
        movable = {n for n, j in DESC.joints.items() if j.type != 'fixed'}
        self.assertEqual(set(msg.name), movable | {'torso_t0'})
        self.assertEqual(len(msg.name), len(msg.position))
        self.assertEqual(len(msg.name), len(msg.velocity))
        self.assertEqual(len(msg.name), len(msg.effort))

    def test_robot_state_publisher_quiet_about_torso_t0(self):
        """torso_t0 is in the joint states and fixed in the URDF: Debian's robot_state_publisher
        warns of it every 10 s unless the launch file's rosconsole levels quiet it."""
        self.rosout.record()
        start = self.joints.msg.header.stamp.to_sec()
        wait_for(lambda: self.joints.msg.header.stamp.to_sec() - start > TORSO_WARNING_S + 1.0,
                 TORSO_WARNING_S + 10.0, 'the stand-in\'s clock to pass the warning\'s period')
        lines = [m.msg for _, m in self.rosout.stop_recording() if 'torso_t0' in m.msg]
        self.assertEqual(lines, [])

    def test_commands_ignored_while_disabled(self):
        self.set_enabled(False)
        before = self.positions()['right_s0']
        self.rosout.record()
        self.joints.record()
        # Until the stand-in says it refused them (it logs that at most every 2 s) and 30 joint
        # states came in while they were sent.
        self.command_until('right', JointCommand.RAW_POSITION_MODE, {'right_s0': before + 1.0},
                           lambda: (warned(self.rosout, '/robot/limb/right/joint_command',
                                           'robot disabled')
                                    and len(self.joints.recorded()) > 30),
                           10.0, 'the refusal of joint commands while disabled')
        self.rosout.stop_recording()
        for _, msg in self.joints.stop_recording():
            self.assertEqual(dict(zip(msg.name, msg.position))['right_s0'], before)

    def test_stop_latches_until_reset(self):
        self.set_enabled(True)
        self.stop_pub.publish(Empty())
        wait_for(lambda: self.state.msg.stopped and not self.state.msg.enabled, 5.0, 'stopped')
        self.rosout.record()

        def refused():
            self.enable_pub.publish(Bool(True))
            return warned(self.rosout, '/robot/set_super_enable', 'reset it first')
        wait_for(refused, 5.0, 'the stand-in to refuse enabling while stopped')
        self.rosout.stop_recording()
        self.state.record()   # /robot/state comes at 20 Hz
        wait_for(lambda: len(self.state.recorded()) >= 2, 5.0, 'two /robot/state messages')
        self.assertFalse(any(msg.enabled for _, msg in self.state.stop_recording()))
        self.reset_pub.publish(Empty())
        wait_for(lambda: not self.state.msg.stopped, 5.0, 'reset')
        self.set_enabled(True)

    def test_joint_commands_followed_within_limits(self):
        self.set_enabled(True)
        limits = {lim.name: lim for lim in bd.arm_limits('left', DESC)}
        beyond = {name: lim.upper + 1.0 for name, lim in limits.items()}
        start = self.positions()
        travel_s = max((lim.upper - start[n]) / lim.velocity for n, lim in limits.items())
        upper = {name: lim.upper for name, lim in limits.items()}
        self.joints.record()
        # Until every joint is at its upper limit (not beyond) and 200 joint states came in.
        self.command_until('left', JointCommand.RAW_POSITION_MODE, beyond,
                           lambda: self.at_targets(upper) and len(self.joints.log) > 200,
                           travel_s + 20.0, 'the left arm to reach its upper limits')
        log = [msg for _, msg in self.joints.stop_recording()]
        # The motion came in small steps: the slowest joint passed through many positions.
        slowest = max(limits, key=lambda n: (limits[n].upper - start[n]) / limits[n].velocity)
        passing = {dict(zip(m.name, m.position))[slowest] for m in log}
        self.assertGreater(len(passing), 50, slowest)
        for previous, msg in zip(log, log[1:]):
            dt = (msg.header.stamp - previous.header.stamp).to_sec()
            self.assertGreater(dt, 0.0)
            for name, old, new in zip(msg.name, previous.position, msg.position):
                if name in limits:
                    lim = limits[name]
                    self.assertTrue(lim.lower - 1e-9 <= new <= lim.upper + 1e-9, (name, new))
                    # 1e-7: the stamps are rounded to ns
                    self.assertLessEqual(abs(new - old), lim.velocity * dt + 1e-7, name)

    def test_arm_holds_when_commands_stop(self):
        self.set_enabled(True)
        start = self.positions()['right_e0']
        first, last = self.command_for('right', JointCommand.RAW_POSITION_MODE,
                                       {'right_e0': start + 3.0}, 0.5)
        e0 = self.joints.msg.name.index('right_e0')
        wait_for(lambda: (self.joints.msg.position[e0] - start > 0.1
                          and self.joints.msg.velocity[e0] == 0.0), 5.0, 'right_e0 to hold')
        held = self.positions()['right_e0']
        # Commands from first to last, then at most the 0.2 s timeout (plus 0.1 s for delivery)
        # at 1.5 rad/s; without the timeout it would go on to start + 3.0.
        self.assertGreater(held - start, 0.5)
        self.assertLess(held - start, 1.5 * (last - first + 0.2 + 0.1))
        self.joints.record()
        wait_for(lambda: len(self.joints.recorded()) >= 50, 5.0, '50 more joint states')
        for _, msg in self.joints.stop_recording():
            self.assertEqual(msg.position[e0], held)

    def test_endpoint_state_equals_robot_state_publisher_tf(self):
        self.set_enabled(True)
        poses = [{'s0': 0.4, 's1': -0.3, 'e0': 1.1, 'e1': 1.2, 'w0': -0.7, 'w1': 0.9, 'w2': 2.0},
                 {'s0': -0.9, 's1': 0.5, 'e0': -2.0, 'e1': 0.3, 'w0': 2.5, 'w1': -1.2, 'w2': -1.0}]
        for pose in poses:
            for side in BAXTER_SIDES:
                targets = {'%s_%s' % (side, k): v for k, v in pose.items()}
                self.command_until(side, JointCommand.RAW_POSITION_MODE, targets,
                                   lambda: self.at_targets(targets), 20.0, 'the pose %s' % targets)
                reached = self.joints.msg.header.stamp
                wait_for(lambda: self.endpoint[side].msg.header.stamp > reached, 5.0,
                         'an endpoint_state of the held pose')
                endpoint = self.endpoint[side].msg
                # lookup_transform waits up to 1 s for robot_state_publisher's tf at the stamp.
                tf = self.tf_buffer.lookup_transform('base', '%s_gripper' % side,
                                                     endpoint.header.stamp, rospy.Duration(1.0))
                p, t = endpoint.pose.position, tf.transform.translation
                for a, b in ((p.x, t.x), (p.y, t.y), (p.z, t.z)):
                    self.assertLess(abs(a - b), 1e-6)
                o, r = endpoint.pose.orientation, tf.transform.rotation
                dot = abs(o.x * r.x + o.y * r.y + o.z * r.z + o.w * r.w)
                self.assertLess(1.0 - dot, 1e-9)
                self.assertEqual(endpoint.header.frame_id, 'base')

    def gripper_command(self, command, sequence, args='', hardware_id=None):
        msg = EndEffectorCommand(id=self.props.msg.id if hardware_id is None else hardware_id,
                                 command=command, args=args, sender='itest_' + command,
                                 sequence=sequence)
        self.gripper_pub.publish(msg)

    def acknowledged(self, command, sequence):
        state = self.gripper.msg
        return state.command_sender == 'itest_' + command and state.command_sequence == sequence

    def test_gripper(self):
        wait_for(lambda: self.props.msg is not None, 5.0, 'gripper properties')
        props = self.props.msg
        self.assertEqual(props.ui_type, EndEffectorProperties.ELECTRIC_GRIPPER)
        self.assertEqual(props.id, self.gripper.msg.id)
        self.assertGreater(time.strptime(props.firmware_date, '%Y/%m/%d %H:%M:%S'),
                           time.strptime('2014/05/20 00:00:00', '%Y/%m/%d %H:%M:%S'))
        self.set_enabled(True)
        self.gripper_command('calibrate', 11)
        wait_for(lambda: self.acknowledged('calibrate', 11), 3.0, 'calibrate acknowledged')
        wait_for(lambda: self.gripper.msg.calibrated and self.gripper.msg.ready, 5.0,
                 'calibrated')
        self.gripper.record()
        # Not this gripper's id: ignored. The next command, on the same connection, is handled
        # after it, so its acknowledgement proves that this one was seen.
        self.gripper_command('go', 12, json.dumps({'position': 50.0}), hardware_id=props.id + 1)
        self.gripper_command('go', 13, json.dumps({'position': 0.0}))
        wait_for(lambda: self.acknowledged('go', 13), 3.0, 'go acknowledged')
        wait_for(lambda: self.gripper.msg.position == 0.0 and not self.gripper.msg.moving,
                 5.0, 'the gripper to close')
        log = [msg for _, msg in self.gripper.stop_recording()]
        self.assertNotIn(12, [m.command_sequence for m in log])
        during = [m.position for m in log if m.command_sequence == 13]
        self.assertTrue(any(0.0 < p < 100.0 for p in during), 'fingers jumped, not moved')
        wait_for(lambda: self.positions()['l_gripper_l_finger_joint'] == 0.0, 2.0,
                 'the finger joint to close')
        self.gripper_command('go', 14, json.dumps({'position': 100.0}))
        wait_for(lambda: self.gripper.msg.position == 100.0, 5.0, 'the gripper to open')
        wait_for(lambda: math.isclose(self.positions()['l_gripper_l_finger_joint'], 0.020833,
                                      rel_tol=1e-6), 2.0, 'the finger joint to open')


if __name__ == '__main__':
    rospy.init_node('test_baxter_sim')
    rostest.rosrun('robopuppet', 'baxter_sim_api', BaxterSimTest)
