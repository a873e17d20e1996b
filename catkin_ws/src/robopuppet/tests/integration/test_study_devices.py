#!/usr/bin/python3
"""rostest: each study device drives arm_R as the puppet does (study_devices.test).

For keyboard, gamepad and SpaceMouse (evdev records written to a FIFO) and the RViz marker
(feedback published on its server): input.launch starts the device; a follow press makes Baxter's
right arm follow, the input moves the MEASURED arm the asked way (keyboard: joint s0 up; the
others: the tool point forward, +x), the grip control closes the gripper (and opens it again), and
the device node frozen (SIGSTOP) stops arm_R following and the measured arm.
"""
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import numpy as np
import rospy
import rostest
from evdev import ecodes as e
from baxter_core_msgs.msg import JointCommand
from geometry_msgs.msg import Pose
from sensor_msgs.msg import JointState
from visualization_msgs.msg import InteractiveMarkerFeedback as Feedback

from robopuppet import baxter_description, interface
from robopuppet.study import input_events
from robopuppet.study.cartesian import CartesianArm
from robopuppet_msgs.msg import LinkPing
from teleop_harness import Baxter, PuppetArm, node_pid
from waiting import wait_for

MOVED_RAD, MOVED_M = 0.1, 0.03
BENT = [0.3, -0.3, 0.0, 1.6, 0.0, 0.3, 0.0]   # the tool point at (0.52, -0.50, -0.31) m
STILL_RAD = 2e-3


class FifoDevice:
    """A keyboard, gamepad or SpaceMouse: evdev records written to its FIFO."""

    def __init__(self, path, follow, grip, move, stop):
        os.mkfifo(path)
        self.path, self._fd = path, os.open(path, os.O_RDWR)   # never blocks, keeps it open
        self._follow, self._grip, self._move, self._stop = follow, grip, move, stop

    def _write(self, *events):
        t = time.time()
        os.write(self._fd, b''.join(input_events.encode(input_events.InputEvent(t, *x))
                                    for x in events + (input_events.sync(t)[1:],)))

    def follow(self, down):
        self._write((e.EV_KEY, self._follow, int(down)))

    def grip(self, down):
        self._write((e.EV_KEY, self._grip, int(down)))

    def move(self, on):
        self._write(self._move if on else self._stop)


class MarkerDevice:
    """The marker: InteractiveMarkerFeedback as RViz sends it."""

    def __init__(self, arm, baxter):
        self.path, self._arm, self._baxter = '', arm, baxter
        self._pub = rospy.Publisher(interface.marker_server('R') + '/feedback', Feedback,
                                    queue_size=10)
        self._down = False

    def _send(self, kind, **fields):
        msg = Feedback(client_id='/test', marker_name='gripper', event_type=kind, **fields)
        msg.header.frame_id = 'base'
        self._pub.publish(msg)

    def follow(self, down):
        if down:
            self._send(Feedback.MENU_SELECT, menu_entry_id=1)

    def grip(self, down):
        if down:
            self._down = not self._down
            self._send(Feedback.MENU_SELECT, menu_entry_id=2 if self._down else 3)

    def move(self, on):
        if on:   # the marker dragged 8 cm forward of the measured tool point
            xyz, rotation = self._arm.tip(self._baxter.arm('right'))
            pose = Pose()
            pose.position.x, pose.position.y, pose.position.z = xyz + [0.08, 0.0, 0.0]
            (pose.orientation.x, pose.orientation.y, pose.orientation.z,
             pose.orientation.w) = baxter_description.matrix_quaternion(rotation)
            self._send(Feedback.POSE_UPDATE, pose=pose)


class StudyDevicesTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.init_node('test_study_devices')
        cls.puppet, cls.baxter, cls.arm = PuppetArm('R'), Baxter(), CartesianArm('right')
        cls.dir = tempfile.mkdtemp(prefix='study_devices_')
        cls.robot_states, cls.echoes = 0, []
        rospy.Subscriber(interface.puppet_ns('R') + '/' + interface.LINK_ECHO, LinkPing,
                         lambda m: cls.echoes.append(time.monotonic()), queue_size=100)
        cls.command = rospy.Publisher(interface.limb_topic('right', 'joint_command'), JointCommand,
                                      queue_size=10)
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, cls._on_robot, queue_size=100)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir, ignore_errors=True)

    @classmethod
    def _on_robot(cls, msg):
        cls.robot_states += 1

    def pose_arm(self):
        """Command Baxter's right arm (not following) to BENT, with room all round the tip."""
        names = baxter_description.arm_joint_names('right')

        def there():
            self.command.publish(JointCommand(mode=JointCommand.POSITION_MODE, names=names,
                                              command=BENT))
            return np.max(np.abs(np.array(self.baxter.arm('right')) - BENT)) < 0.01
        wait_for(there, 20, 'the right arm in the start pose')

    def run_device(self, name, device, joint_space):
        baxter, puppet = self.baxter, self.puppet
        args = ['roslaunch', 'robopuppet', 'input.launch', 'device:=' + name, 'arm_side:=R']
        self.pose_arm()
        launch = subprocess.Popen(args + (['events:=' + device.path] if device.path else []))
        try:
            since = time.monotonic()
            wait_for(lambda: puppet.states_t and puppet.states_t[-1] > since + 0.2, 30,
                     '%s: joint_states' % name)
            # arm_R trusts the new node's clock once its pings come back (link_echo)
            wait_for(lambda: sum(t > since for t in self.echoes) >= 5, 10, '%s: echoes' % name)
            echoed = [t for t in self.echoes if t > since][4]
            wait_for(lambda: puppet.teleop_log[-1][0] > echoed
                     and puppet.teleop.state == interface.READY, 10,
                     '%s: arm_R ready (%s)' % (name, puppet.teleop))
            device.follow(True)
            wait_for(lambda: puppet.teleop.follow_right, 10, '%s: arm_R following' % name)
            device.follow(False)
            start = np.array(baxter.arm('right'))
            tip0 = self.arm.tip(start)[0]
            device.move(True)
            if joint_space:
                wait_for(lambda: baxter.arm('right')[0] - start[0] > MOVED_RAD, 10,
                         '%s: s0 up' % name)
            else:
                wait_for(lambda: self.arm.tip(baxter.arm('right'))[0][0] - tip0[0] > MOVED_M, 10,
                         '%s: tool point forward' % name)
                moved = self.arm.tip(baxter.arm('right'))[0] - tip0
                self.assertLess(np.hypot(moved[1], moved[2]), moved[0], name)
            if not isinstance(device, MarkerDevice):
                device.move(False)
            for closed in (True, False):
                device.grip(True)
                device.grip(False)
                wait_for(lambda: (baxter.gripper['right'].position < 5) == closed, 10,
                         '%s: gripper %s' % (name, 'closed' if closed else 'open'))
            device.move(True)   # moving when the device node freezes
            pid = node_pid('/input_R')
            os.kill(pid, signal.SIGSTOP)
            try:
                wait_for(lambda: not puppet.teleop.follow_right, 5, '%s: following stopped'
                         % name)
                # Still over 20 of Baxter's reports, not over a poll interval: under load two
                # polls can read one stale report and call a moving arm still.
                last = [np.array(baxter.arm('right')), self.robot_states]

                def still():
                    if self.robot_states < last[1] + 20:
                        return False
                    now = np.array(baxter.arm('right'))
                    moved, last[:] = np.max(np.abs(now - last[0])), [now, self.robot_states]
                    return moved < STILL_RAD / 5
                wait_for(still, 5, '%s: the measured arm still' % name, step_s=0.05)
                stopped, seen = np.array(baxter.arm('right')), self.robot_states
                wait_for(lambda: self.robot_states > seen + 50, 5, 'Baxter reporting')
                self.assertLess(np.max(np.abs(np.array(baxter.arm('right')) - stopped)),
                                STILL_RAD, '%s: the arm moved on after it stopped' % name)
            finally:
                os.kill(pid, signal.SIGCONT)
        finally:
            launch.send_signal(signal.SIGINT)
            launch.wait(20)

    def fifo(self, name, *codes):
        return FifoDevice(os.path.join(self.dir, name + '_R'), *codes)

    def test_1_keyboard(self):
        self.run_device('keyboard', self.fifo('keyboard', e.KEY_F3, e.KEY_SPACE,
                                               (e.EV_KEY, e.KEY_A, 1), (e.EV_KEY, e.KEY_A, 0)),
                        joint_space=True)

    def test_2_gamepad(self):
        self.run_device('gamepad', self.fifo('gamepad', e.BTN_EAST, e.BTN_SOUTH,
                                              (e.EV_ABS, e.ABS_RY, -32768),
                                              (e.EV_ABS, e.ABS_RY, 0)),
                        joint_space=False)

    def test_3_spacemouse(self):
        self.run_device('spacemouse', self.fifo('spacemouse', e.BTN_0, e.BTN_1,
                                                 (e.EV_REL, e.REL_Y, -350), (e.EV_REL, e.REL_Y, 0)),
                        joint_space=False)

    def test_4_marker(self):
        self.run_device('marker', MarkerDevice(self.arm, self.baxter), joint_space=False)


if __name__ == '__main__':
    rostest.rosrun('robopuppet', 'study_devices', StudyDevicesTest)
