#!/usr/bin/python3
"""rostest (calibration_follow.test): a change of what the puppet's angles mean never moves a
following Baxter arm.

Baxter's right arm follows the right puppet, the operator's hand still. (a) set_config of joint
0's home_angle, then of joint 2's sign_angle, on config_R: refused while the arm follows, the
error saying to press 3; Baxter stays. (b) config_X's refusal bypassed: the test publishes the
changed settings as config_R would (active_settings, which serial_R loads into the puppet, and
stored_settings, which arm_R watches), first in the worst order for arm_R (the puppet reports
with the new meaning before arm_R hears of the change: stored_settings goes out only when the
first such sample arrives), then in config_R's own order (stored first). Each time Baxter's
measured right arm stays within STAY_TOL_RAD and teleop_state leaves following with a detail
naming the joint and the setting; in between, a new press follows again, approaching slowly.
"""
import copy
import threading
import time
import unittest

import rosgraph
import rospy
import rostest
from sensor_msgs.msg import JointState

from hand_pose import HAND_POSE
from robopuppet import baxter_description, interface
from robopuppet_msgs.msg import ArmSettings
from robopuppet_msgs.srv import SetConfig
from teleop_harness import Baxter, PuppetArm, calibrate, max_error
from waiting import wait_for

SIDE = 'R'
STAY_TOL_RAD = 0.02      # Baxter "stays": no joint of its measured arm moves farther than this
AFTER_SETS = 15          # how long Baxter is watched after a change: this many puppet sets
HOME_STEP_RAD = 0.5      # the hostile tester's change of joint 0's home_angle
APPROACH_RAD_S = 0.5     # arm_R's ~approach_speed (arm.launch's default)
JUMP_RAD = 0.25          # a sample whose joint moved this far at once has the new meaning
ATTEMPTS = 3             # each change, when a fault of the loaded machine spoils it


def until(condition, timeout_s):
    """Return whether condition() came true within timeout_s (checked every 50 ms)."""
    try:
        wait_for(condition, timeout_s, '')
    except AssertionError:
        return False
    return True


class ArmMotion:
    """The farthest Baxter's measured right arm moved from where it was at start()."""

    def __init__(self):
        self._names = baxter_description.arm_joint_names('right')
        self._lock = threading.Lock()
        self._pose = self._reference = None
        self._moved = (0.0, None)
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on, queue_size=1000)

    def _on(self, msg):
        position = dict(zip(msg.name, msg.position))
        if not all(n in position for n in self._names):
            return
        pose = [position[n] for n in self._names]
        with self._lock:
            self._pose = pose
            if self._reference is not None:
                for name, a, b in zip(self._names, pose, self._reference):
                    if abs(a - b) > self._moved[0]:
                        self._moved = (abs(a - b), name)

    def start(self):
        with self._lock:
            self._reference, self._moved = list(self._pose), (0.0, None)

    def moved(self):
        """Return (rad, joint name) of the farthest move since start()."""
        with self._lock:
            return self._moved


class Settings:
    """config_R's stored settings, and publishers that bypass config_R as a race would."""

    def __init__(self):
        ns = interface.puppet_ns(SIDE)
        self._lock, self.stored = threading.Lock(), None
        self.topics = {name: '%s/%s' % (ns, name)
                       for name in (interface.STORED_SETTINGS, interface.ACTIVE_SETTINGS)}
        rospy.Subscriber(self.topics[interface.STORED_SETTINGS], ArmSettings, self._on,
                         queue_size=10)
        self.pubs = {name: rospy.Publisher(topic, ArmSettings, queue_size=1, latch=True)
                     for name, topic in self.topics.items()}
        self.set_config = rospy.ServiceProxy('%s/%s' % (ns, interface.SET_CONFIG), SetConfig)

    def _on(self, msg):
        if msg._connection_header.get('callerid') == '/config_%s' % SIDE:
            with self._lock:
                self.stored = msg

    def wait_connected(self):
        """Wait until every other subscriber of both topics takes the test's messages."""
        me = rospy.get_name()
        for name, topic in self.topics.items():
            def connected():
                _, subscribers, _ = rosgraph.Master(me).getSystemState()
                others = [n for t, nodes in subscribers if t == topic for n in nodes if n != me]
                return self.pubs[name].get_num_connections() >= len(others)
            wait_for(connected, 20, 'the subscribers of %s' % topic)

    def changed(self, base, joint, name, value):
        """Return a copy of ArmSettings base with one setting changed and the next revision."""
        msg = copy.deepcopy(base)
        msg.revision += 1
        setattr(msg.joints[joint], name, value)
        msg.header.stamp = rospy.Time.now()
        return msg


class NewMeaningTrigger:
    """Publish stored_settings the moment a puppet sample with the new meaning arrives."""

    def __init__(self, joint, before_rad, publish):
        self._joint, self._before, self._publish = joint, before_rad, publish
        self.fired = threading.Event()
        self._sub = rospy.Subscriber('%s/%s' % (interface.puppet_ns(SIDE), interface.JOINT_STATES),
                                     JointState, self._on, queue_size=100)

    def _on(self, msg):
        if not self.fired.is_set() and abs(msg.position[self._joint] - self._before) > JUMP_RAD:
            self.fired.set()
            self._publish()
            self._sub.unregister()


class CalibrationFollowTest(unittest.TestCase):

    def setUp(self):
        self.puppet, self.baxter = PuppetArm(SIDE), Baxter()
        self.motion, self.settings = ArmMotion(), Settings()
        self.latest = None   # the newest settings serial_R was given (config_R's or the test's)

    def test_angle_settings_while_following(self):
        puppet, baxter, config = self.puppet, self.baxter, self.settings
        wait_for(lambda: puppet.state() == interface.CALIBRATING, 30, 'arm_R calibrating')
        puppet.end_piece(False)
        calibrate(puppet, HAND_POSE)
        wait_for(lambda: config.stored is not None, 10, "config_R's stored_settings")
        config.wait_connected()

        # (a) Directly on config_R: refused while the arm follows.
        for joint, name in ((0, 'home_angle'), (2, 'sign_angle')):
            self.attempt('(a) set_config joint %d %s' % (joint, name),
                         lambda: self.direct(joint, name))

        # (b) Bypassed, worst order: the puppet reports the new home before arm_R hears of it.
        self.latest = config.stored
        self.attempt('(b) joint 0 home_angle, the device first',
                     lambda: self.bypass(0, 'home_angle', device_first=True))

        # A new press follows again, approaching the new pose slowly from where Baxter is.
        press_t, start = self.follow()
        took_s = time.monotonic() - press_t
        self.assertGreater(took_s, 0.8 * max_error(start, puppet.angles) / APPROACH_RAD_S)
        self.assert_slow(baxter.commands_since('right', press_t))

        # (b) Bypassed in config_R's own order: stored_settings first, then active_settings.
        self.attempt('(b) joint 2 sign_angle, stored_settings first',
                     lambda: self.bypass(2, 'sign_angle', device_first=False))

    def attempt(self, what, change):
        """Run change() while the right arm follows with the hand still; Baxter must stay.

        change() returns the check of what it did, run unless a fault spoiled the attempt (the
        shared machine delays the puppet's sets past arm_R's 0.4 s now and then; on a fault
        Baxter stays too): then the change is made again, up to ATTEMPTS times.
        """
        faults = []
        for _ in range(ATTEMPTS):
            self.follow()
            start = time.monotonic()
            self.motion.start()
            check = change()
            self.puppet.wait_sets(AFTER_SETS)
            moved, where = self.motion.moved()
            teleop = self.puppet.teleop
            faults = [m.detail for m in self.puppet.reports_since(start)
                      if m.state == interface.FAULT]
            rospy.loginfo('%s: Baxter moved %.3f rad (%s); teleop %s: %s%s', what, moved, where,
                          teleop.state, teleop.detail,
                          '; spoiled by a fault: %s' % faults[0] if faults else '')
            self.assertLessEqual(moved, STAY_TOL_RAD, '%s: %s moved %.3f rad' % (what, where,
                                                                                moved))
            if not faults:
                check()
                return
        self.fail('%s: every attempt spoiled by a fault: %s' % (what, faults))

    def direct(self, joint, name):
        """Ask config_R to change a setting; return the check that it refused."""
        old = getattr(self.settings.stored.joints[joint], name)
        value = old + HOME_STEP_RAD if name == 'home_angle' else -old
        answer = self.settings.set_config(joint=joint, names=[name], values=[value])
        rospy.loginfo('set_config joint %d %s = %g: stored %s (%r)', joint, name, value,
                      answer.stored, answer.error)

        def check():
            self.assertFalse(answer.stored, 'joint %d %s stored while following' % (joint, name))
            self.assertIn(name, answer.error)
            self.assertIn('stop following first: press 3', answer.error)
        return check

    def bypass(self, joint, name, device_first):
        """Change a setting past config_R; return the check that following stopped, naming it.

        device_first: active_settings first, stored_settings only when the first puppet sample
        with the new meaning arrives; else stored_settings first, as config_R publishes.
        """
        puppet, pubs, base = self.puppet, self.settings.pubs, self.latest
        old = getattr(base.joints[joint], name)
        value = (old + (HOME_STEP_RAD if old <= 0.0 else -HOME_STEP_RAD)
                 if name == 'home_angle' else -old)
        self.latest = msg = self.settings.changed(base, joint, name, value)
        before = puppet.angles[joint]
        if device_first:
            trigger = NewMeaningTrigger(joint, before,
                                        lambda: pubs[interface.STORED_SETTINGS].publish(msg))
            pubs[interface.ACTIVE_SETTINGS].publish(msg)
            wait_for(trigger.fired.is_set, 10, 'a puppet sample with the new %s' % name)
        else:
            pubs[interface.STORED_SETTINGS].publish(msg)
            pubs[interface.ACTIVE_SETTINGS].publish(msg)
            wait_for(lambda: abs(puppet.angles[joint] - before) > JUMP_RAD, 10,
                     'a puppet sample with the new %s' % name)
        left = until(lambda: puppet.state() != interface.FOLLOWING, 5)

        def check():
            self.assertTrue(left, 'joint %d %s: still following' % (joint, name))
            self.assertEqual(puppet.state(), interface.READY)
            self.assertFalse(puppet.teleop.follow_right)
            self.assertIn("joint %d's %s changed" % (joint, name), puppet.teleop.detail)
            self.assertIn('press 3 to follow again', puppet.teleop.detail)
        return check

    def follow(self, timeout_s=60.0):
        """Press 3 (again after a fault) until Baxter's right arm follows and is on the still
        puppet; return (time, Baxter's right arm pose) of the last press (None: no press)."""
        puppet, baxter = self.puppet, self.baxter
        deadline, pressed = time.monotonic() + timeout_s, (None, None)
        while True:
            left_s = deadline - time.monotonic()
            if not puppet.teleop.follow_right:
                wait_for(lambda: puppet.state() in (interface.READY, interface.FOLLOWING),
                         left_s, 'arm_R ready (%s)' % puppet.teleop)
                pressed = (time.monotonic(), baxter.arm('right'))
                puppet.press(interface.BUTTON_RIGHT)
            on_pose = until(lambda: puppet.teleop.follow_right and max_error(
                baxter.arm('right'), puppet.angles) < 0.01, min(left_s, 20))
            if on_pose:
                puppet.wait_sets(3)
                if until(lambda: max_error(baxter.arm('right'), puppet.angles) < 0.01, 1):
                    return pressed
            if time.monotonic() > deadline:
                raise AssertionError('Baxter\'s right arm not on the puppet after %.0f s (%s)'
                                     % (timeout_s, puppet.teleop))

    def assert_slow(self, commands):
        """Over every 0.2 s the commands move no joint faster than the approach speed (with
        0.02 rad for the sender's and the receiver's jitter); at the URDF's speed the shoulder
        would move 0.3 rad."""
        self.assertGreater(len(commands), 50)
        j = 0
        for t0, _, a in commands:
            while j < len(commands) and commands[j][0] < t0 + 0.2:
                j += 1
            if j == len(commands):
                break
            t1, _, b = commands[j]
            for x, y in zip(a, b):
                self.assertLessEqual(abs(y - x), APPROACH_RAD_S * (t1 - t0) + 0.02)

if __name__ == '__main__':
    rospy.init_node('test_calibration_follow')
    rostest.rosrun('robopuppet', 'calibration_follow', CalibrationFollowTest)
