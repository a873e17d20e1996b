#!/usr/bin/python3
"""rostest: the stand-in's digital IO, navigators, analog IO, head and IK service, as the Rethink
SDK 1.2 tools wait for and use them. Names, types and timeouts are the SDK's, spelled out."""
import time
import unittest

import rospy
import rostest
from baxter_core_msgs.msg import (AnalogIOState, AnalogOutputCommand, AssemblyState,
                                  DigitalIOState, DigitalOutputCommand, HeadPanCommand,
                                  HeadState, NavigatorState)
from baxter_core_msgs.srv import SolvePositionIK, SolvePositionIKRequest
from geometry_msgs.msg import Point, Pose, PoseStamped, Quaternion
from baxter_core_msgs.msg import EndEffectorProperties, EndEffectorState, JointCommand
from baxter_core_msgs.msg import CollisionAvoidanceState
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty, Header, UInt16
from trajectory_msgs.msg import JointTrajectoryPoint

from baxter_sim_testing import Latest, publisher, warned, warnings
from waiting import wait_for
from robopuppet import baxter_description as bd

NAVIGATORS = ('left', 'right', 'torso_left', 'torso_right')
# Every state topic the stand-in publishes beyond the arms', and its type: Rethink's names.
TOPICS = dict(
    [('/robot/digital_io/%s_%s/state' % (side, name), DigitalIOState)
     for side in ('left', 'right')
     for name in ('lower_cuff', 'upper_button', 'lower_button', 'shoulder_button')]
    + [('/robot/digital_io/%s_%s_light/state' % (nav, light), DigitalIOState)
       for nav in NAVIGATORS for light in ('inner', 'outer')]
    + [('/robot/navigators/%s_navigator/state' % nav, NavigatorState) for nav in NAVIGATORS]
    + [('/robot/analog_io/%s_hand_range/state' % side, AnalogIOState)
       for side in ('left', 'right')]
    + [('/robot/analog_io/torso_fan/state', AnalogIOState)]
    + [('/robot/head/head_state', HeadState)]
    + [('/robot/limb/%s/collision_avoidance_state' % side, CollisionAvoidanceState)
       for side in ('left', 'right')])
RATE_HZ = 100.0     # Rethink's simulator publishes these at 100 Hz, like joint_states


def first_message(topic, msg_type, timeout_s):
    """Wait like baxter_dataflow.wait_for in an SDK constructor: a message within timeout_s."""
    latest = Latest(topic, msg_type)
    wait_for(lambda: latest.msg is not None, timeout_s, 'the first message on ' + topic)
    return latest.msg


def lit(navigator_state, light):
    """Return whether a navigator's light is on, found by name as the SDK 1.2's Navigator does."""
    return navigator_state.lights[navigator_state.light_names.index(light)]


def joint_states_rate_hz(joints, count):
    """Return the rate (Hz, from header stamps: the node's loop, not this machine's load on
    the delivery) of the next `count` joint states."""
    joints.record()
    wait_for(lambda: len(joints.recorded()) >= count, 30.0, '%d joint states' % count)
    stamps = [msg.header.stamp.to_sec() for _, msg in joints.stop_recording()]
    return (len(stamps) - 1) / (stamps[-1] - stamps[0])


class RateAndRefusalTests:
    """Tests of BaxterSimSdkTest: /robot/joint_state_publish_rate as the SDK's wobbler and
    trajectory server send it, and the feed-forward and custom gripper topics the stand-in
    refuses, each with its log line."""

    def test_the_joint_state_rate_asked_is_published_up_to_the_loop_rate(self):
        joints = Latest('/robot/joint_states', JointState)
        rosout = self.rosout
        rosout.record()
        rate = publisher('/robot/joint_state_publish_rate', UInt16)
        try:
            rate.publish(UInt16(500))   # the wobbler's: more than the stand-in's loop
            wait_for(lambda: warned(rosout, '500 Hz asked', 'at 100 Hz'), 10.0,
                     'the 500 Hz line')
            self.assertTrue(50.0 < joint_states_rate_hz(joints, 150) < 130.0)
            rate.publish(UInt16(20))
            wait_for(lambda: any('now published at 20 Hz' in m.msg
                                 for _, m in rosout.recorded()), 10.0, 'the 20 Hz line')
            self.assertTrue(12.0 < joint_states_rate_hz(joints, 40) < 26.0)
        finally:
            rate.publish(UInt16(100))
        wait_for(lambda: any('now published at 100 Hz' in m.msg for _, m in rosout.recorded()),
                 10.0, 'the rate back at 100 Hz')
        self.assertTrue(50.0 < joint_states_rate_hz(joints, 150) < 130.0)

    def test_feed_forward_and_custom_gripper_messages_are_refused_with_a_line(self):
        rosout = self.rosout
        rosout.record()
        publisher('/robot/limb/left/inverse_dynamics_command', JointTrajectoryPoint).publish(
            JointTrajectoryPoint(positions=[0.0] * 7, velocities=[0.0] * 7))
        gripper = '/robot/end_effector/right_gripper/rsdk/'
        publisher(gripper + 'set_properties', EndEffectorProperties).publish(
            EndEffectorProperties(id=131073, ui_type=EndEffectorProperties.PASSIVE_GRIPPER))
        publisher(gripper + 'set_state', EndEffectorState).publish(EndEffectorState(id=131073))
        wanted = [('inverse_dynamics_command', 'kinematic'),
                  ('set_properties', 'custom gripper'), ('set_state', 'custom gripper')]
        wait_for(lambda: all(warned(rosout, *words) for words in wanted), 10.0,
                 'a warning for each of %s' % wanted)
        self.assertEqual(len(warnings(rosout.stop_recording())), 3)


class BaxterSimSdkTest(RateAndRefusalTests, unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.state = Latest('/robot/state', AssemblyState)
        cls.head = Latest('/robot/head/head_state', HeadState)
        cls.rosout = Latest('/rosout', Log)
        wait_for(lambda: cls.state.msg and cls.head.msg, 20.0, 'the stand-in to publish')

    def test_every_topic_at_the_rate_with_its_type(self):
        latest = {topic: Latest(topic, kind) for topic, kind in TOPICS.items()}
        wait_for(lambda: all(l.msg for l in latest.values()), 10.0, 'every IO topic')
        for l in latest.values():
            l.record()
        time.sleep(2.0)
        for topic, l in latest.items():
            log = l.stop_recording()
            rate_hz = (len(log) - 1) / (log[-1][0] - log[0][0])
            self.assertTrue(0.7 * RATE_HZ < rate_hz < 1.3 * RATE_HZ, (topic, rate_hz))
            self.assertIsInstance(log[-1][1], TOPICS[topic])

    def test_a_digital_io_command_switches_a_light(self):
        pub = publisher('/robot/digital_io/command', DigitalOutputCommand)
        light = Latest('/robot/digital_io/left_inner_light/state', DigitalIOState)
        nav = Latest('/robot/navigators/left_navigator/state', NavigatorState)
        wait_for(lambda: light.msg and nav.msg, 5.0, 'the light state')
        self.assertEqual((light.msg.state, light.msg.isInputOnly), (DigitalIOState.OFF, False))
        for value, state in ((True, DigitalIOState.ON), (False, DigitalIOState.OFF)):
            pub.publish(DigitalOutputCommand('left_inner_light', value))
            wait_for(lambda: light.msg.state == state and lit(nav.msg, 'inner') == value, 2.0,
                     'the light to switch to %s' % value)

    def test_the_torso_fan_ramps_as_analog_io_rampup_sets_it(self):
        # baxter_interface.AnalogIO('torso_fan'): its state within 2 s, an output (not input
        # only); set_output publishes the command and waits up to 2 s for the state to match.
        fan = Latest('/robot/analog_io/torso_fan/state', AnalogIOState)
        wait_for(lambda: fan.msg, 2.0, 'the torso fan state')
        self.assertFalse(fan.msg.isInputOnly)
        pub = publisher('/robot/analog_io/command', AnalogOutputCommand)
        for value in (0, 50, 100, 0):
            pub.publish(AnalogOutputCommand('torso_fan', value))
            wait_for(lambda: fan.msg.value == value, 2.0, 'the fan at %d' % value)

    def test_a_simulated_cuff_squeeze_presses_the_cuff(self):
        pub = publisher('/baxter_sim/digital_input', DigitalOutputCommand)
        cuff = Latest('/robot/digital_io/right_lower_cuff/state', DigitalIOState)
        wait_for(lambda: cuff.msg, 5.0, 'the cuff state')
        self.assertTrue(cuff.msg.isInputOnly)
        for value, state in ((True, DigitalIOState.PRESSED), (False, DigitalIOState.UNPRESSED)):
            pub.publish(DigitalOutputCommand('right_lower_cuff', value))
            wait_for(lambda: cuff.msg.state == state, 2.0, 'the cuff squeeze %s' % value)

    def test_the_head_pans_at_the_commanded_speed(self):
        enable = publisher('/robot/set_super_enable', Bool)
        pan = publisher('/robot/head/command_head_pan', HeadPanCommand)
        enable.publish(True)
        wait_for(lambda: self.state.msg.enabled, 5.0, 'the robot enabled')
        ratio, target = 0.4, 1.0
        speed = ratio * bd.load().limit(bd.HEAD_PAN).velocity
        self.head.record()
        pan.publish(HeadPanCommand(target, ratio, HeadPanCommand.REQUEST_PAN_VOID))
        wait_for(lambda: abs(self.head.msg.pan - target) < 1e-6, 10.0, 'the head at its target')
        moving = [(t, m.pan) for t, m in self.head.stop_recording() if m.isTurning]
        (t0, p0), (t1, p1) = moving[len(moving) // 4], moving[3 * len(moving) // 4]
        self.assertAlmostEqual((p1 - p0) / (t1 - t0), speed, delta=0.15 * speed)
        self.assertFalse(self.head.msg.isTurning)

    def test_each_sdk_tool_would_start(self):
        # tuck_arms.py and head_wobbler.py: baxter_interface.Head() waits 5 s for head_state.
        first_message('/robot/head/head_state', HeadState, 5.0)
        # joint_trajectory_action_server.py: DigitalIO('<side>_lower_cuff'), 2 s each.
        # gripper_cuff_control.py: the cuff and both its buttons, 2 s each.
        for side in ('left', 'right'):
            for name in ('lower_cuff', 'upper_button', 'lower_button'):
                first_message('/robot/digital_io/%s_%s/state' % (side, name), DigitalIOState, 2.0)
        # joint_recorder.py: Navigator('left') and ('right'): both lights (DigitalIO, 2 s each),
        # then the navigator state within baxter_dataflow.wait_for's default 1 s.
        for nav in ('left', 'right'):
            for light in ('inner', 'outer'):
                msg = first_message('/robot/digital_io/%s_%s_light/state' % (nav, light),
                                    DigitalIOState, 2.0)
                self.assertFalse(msg.isInputOnly)
            msg = first_message('/robot/navigators/%s_navigator/state' % nav, NavigatorState, 1.0)
            self.assertEqual((len(msg.buttons), len(msg.lights)), (3, 2))
            self.assertEqual((msg.button_names, msg.light_names),
                             (['ok', 'back', 'show'], ['inner', 'outer']))
        # ik_service_client.py: wait_for_service 5 s, one pose in base; result_type[0] valid.
        for side in ('left', 'right'):
            name = '/ExternalTools/%s/PositionKinematicsNode/IKService' % side
            rospy.wait_for_service(name, 5.0)
            xyz, (qx, qy, qz, qw) = bd.load().pose(bd.neutral_pose(side), bd.gripper_link(side))
            request = SolvePositionIKRequest()
            request.pose_stamp.append(PoseStamped(Header(stamp=rospy.Time.now(), frame_id='base'),
                                                  Pose(Point(*xyz), Quaternion(qx, qy, qz, qw))))
            request.pose_stamp.append(PoseStamped(Header(frame_id='base'),
                                                  Pose(Point(3.0, 0, 0), Quaternion(0, 0, 0, 1))))
            answer = rospy.ServiceProxy(name, SolvePositionIK)(request)
            self.assertEqual(list(answer.isValid), [True, False])
            self.assertNotEqual(answer.result_type[0], answer.RESULT_INVALID)
            self.assertEqual(answer.result_type[1], answer.RESULT_INVALID)
            solved = dict(zip(answer.joints[0].name, answer.joints[0].position))
            reached, _ = bd.load().pose(solved, bd.gripper_link(side))
            self.assertLess(sum((a - b) ** 2 for a, b in zip(reached, xyz)) ** 0.5, 1e-3)

    def test_a_cuff_squeeze_gives_zero_g_unless_cuff_interaction_is_suppressed(self):
        # The SDK wiki's Zero-G Mode: the squeeze lets the arm go; suppress_cuff_interaction
        # (std_msgs/Empty) faster than 5 Hz keeps it under command.
        rosout = Latest('/rosout', Log)
        rosout.record()
        joints = Latest('/robot/joint_states', JointState)
        enable = publisher('/robot/set_super_enable', Bool)
        squeeze = publisher('/baxter_sim/digital_input', DigitalOutputCommand)
        command = publisher('/robot/limb/right/joint_command', JointCommand)
        suppress = publisher('/robot/limb/right/suppress_cuff_interaction', Empty)
        enable.publish(True)
        wait_for(lambda: self.state.msg.enabled and joints.msg, 5.0, 'the robot enabled')

        def said(words, count=1):
            return count <= sum(words in m.msg for _, m in rosout.recorded()
                                if m.name == '/baxter_sim')

        def s0():
            return joints.msg.position[joints.msg.name.index('right_s0')]

        def commanding(done, suppressed=False):
            def step():
                command.publish(JointCommand(JointCommand.POSITION_MODE, [start + 0.5],
                                             ['right_s0']))
                if suppressed:
                    suppress.publish(Empty())
                return done()
            return step
        squeeze.publish(DigitalOutputCommand('right_lower_cuff', True))
        wait_for(lambda: said('right arm: zero-g: cuff squeezed'), 5.0, 'zero-g logged')
        start = s0()
        wait_for(commanding(lambda: warned(rosout, 'zero-g', 'right/joint_command')), 5.0,
                 'the command refused')
        self.assertAlmostEqual(s0(), start, delta=1e-9)
        wait_for(commanding(lambda: s0() > start + 0.2, suppressed=True), 5.0,
                 'the squeezed arm commanded while suppressed')
        self.assertTrue(said('right arm: cuff interaction suppressed') and said('zero-g ended'))
        wait_for(lambda: said('right arm: zero-g: cuff squeezed', 2), 5.0,
                 'zero-g again 0.2 s after the last suppress message')
        self.assertTrue(said('right arm: cuff interaction suppression lapsed'))
        squeeze.publish(DigitalOutputCommand('right_lower_cuff', False))
        wait_for(lambda: said('right arm: zero-g ended', 2), 5.0, 'zero-g ended on release')
        enable.publish(False)    # as found: a later enable must not come to an enabled robot
        wait_for(lambda: not self.state.msg.enabled, 5.0, 'the robot disabled again')


if __name__ == '__main__':
    rospy.init_node('test_baxter_sim_sdk')
    rostest.rosrun('robopuppet', 'test_baxter_sim_sdk', BaxterSimSdkTest)
