#!/usr/bin/python3
"""rostest, the assist end to end: demonstrate, train, then one puppet carries the tray.

Both simulated puppets record carry_tray demonstrations with the demonstrator; train_assist
learns them; the assist node (waiting for the model file since launch) loads the model; puppet R
alone then plays a held-out execution of its arm's part with the assist driving Baxter's left
arm, and the tray's tilt and the hands' distance, from Baxter's MEASURED joint states, stay
within the task's bounds; an unfamiliar leader motion makes the assist hold the left arm, which
then stands still; puppet L takes the left arm over with its own button.
"""
import os
import subprocess
import threading
import time
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import JointState

from robopuppet import baxter_description, interface
from robopuppet.assist import demonstration, tasks
from robopuppet_msgs.msg import AssistState
from teleop_harness import PuppetArm, max_error
from waiting import wait_for

TASK = tasks.TASKS['carry_tray']
EPISODES = 6
DEMO_SEED, HELD_OUT_SEED = 1, 1000
PLAY_RATE_HZ = 50.0
MOVE_S = 3.0            # the leader's hand goes to the held-out start over this long
STILL_AFTER_HOLD_S = 0.5  # once holding, the held arm has stopped within this long
STILL_RAD = 0.01        # and then moves no joint further than this


def run(args, timeout_s):
    """Run a command as a user would; return its output; fail the test on a non-zero exit."""
    done = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          timeout=timeout_s, universal_newlines=True)
    assert done.returncode == 0, '%s exited %d:\n%s' % (args[:3], done.returncode, done.stdout)
    return done.stdout


class Measured:
    """Baxter's measured arm angles from /robot/joint_states, kept while `keeping`."""

    def __init__(self):
        self._lock = threading.Lock()
        self.names = {s: baxter_description.arm_joint_names(s) for s in interface.BAXTER_SIDES}
        self.now, self.kept, self.keeping = {}, [], False
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on, queue_size=100)

    def _on(self, msg):
        positions = dict(zip(msg.name, msg.position))
        arms = {s: [positions.get(n, np.nan) for n in names] for s, names in self.names.items()}
        with self._lock:
            self.now = arms
            if self.keeping:
                self.kept.append((time.monotonic(), arms['left'], arms['right']))

    def arm(self, side):
        with self._lock:
            return list(self.now.get(side, [np.nan] * 7))

    def keep(self):
        with self._lock:
            self.kept, self.keeping = [], True

    def stop(self):
        with self._lock:
            self.keeping = False
            return list(self.kept)


def play(puppet, times, poses):
    """Move the puppet's hand through poses at their times (s from now)."""
    start = time.monotonic()
    for t, pose in zip(times, poses):
        delay = start + t - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        puppet.hand(list(pose))


def move_hand(puppet, pose):
    """Bring the hand from where the puppet is to pose smoothly over MOVE_S."""
    start = np.array(puppet.angles)
    times = np.arange(0.0, MOVE_S, 1.0 / PLAY_RATE_HZ)
    s = demonstration.minimum_jerk(times / MOVE_S)
    play(puppet, times, [start + (np.array(pose) - start) * k for k in s] + [pose])


class AssistTest(unittest.TestCase):

    def test_demonstrate_train_assist_hold_take_over(self):
        model = rospy.get_param('~model')
        left, right, measured = PuppetArm('L'), PuppetArm('R'), Measured()
        assist, log = {}, []

        def on_assist(msg):
            assist['state'] = msg
            log.append((time.monotonic(), msg.state))
        rospy.Subscriber(interface.ASSIST_STATE, AssistState, on_assist, queue_size=10)
        wait_for(lambda: 'state' in assist, 60, 'the assist node')
        self.assertEqual(assist['state'].state, AssistState.OFF)   # no model yet
        self.assertIn('train_assist', assist['state'].detail)

        # Demonstrations, as a user records them with the demonstrator.
        out = run(['rosrun', 'robopuppet', 'demonstrate', '--task', TASK.key,
                   '--episodes', str(EPISODES), '--seed', str(DEMO_SEED)], 600)
        self.assertIn('episode %d' % EPISODES, out)
        folder = os.path.join(os.environ['ROS_HOME'], 'robopuppet', 'episodes')

        # Training, with a held-out evaluation printed.
        os.makedirs(os.path.dirname(model), exist_ok=True)
        out = run(['rosrun', 'robopuppet', 'train_assist', folder, '--out', model], 300)
        self.assertIn('p99', out)
        wait_for(lambda: assist['state'].state in (AssistState.READY, AssistState.HOLDING), 10,
                 'the assist node using the new model (now %r)' % (assist['state'],))
        self.assertEqual((assist['state'].leader, assist['state'].follower), ('right', 'left'))

        # Puppet L lets go of the left arm; puppet R (following the right arm) engages the
        # assist for it at the held-out execution's start.
        held_out = demonstration.demonstrate(TASK.key, HELD_OUT_SEED)
        if left.teleop.follow_left:
            left.press(interface.BUTTON_LEFT)
        wait_for(lambda: not left.teleop.follow_left, 5, 'puppet L letting go of the left arm')
        if not right.teleop.follow_right:
            right.press(interface.BUTTON_RIGHT)
        wait_for(lambda: right.teleop.follow_right, 5, 'puppet R following the right arm')
        move_hand(right, held_out.right[0])
        wait_for(lambda: assist['state'].state == AssistState.READY, 10,
                 'a confident prediction at the start (now %r)' % (assist['state'],))
        right.press(interface.BUTTON_LEFT)
        wait_for(lambda: right.teleop.assist_left and not right.teleop.follow_left, 5,
                 'arm_R driving the left arm from the assist')
        wait_for(lambda: assist['state'].state == AssistState.ASSISTING, 5, 'assisting')
        wait_for(lambda: max_error(measured.arm('left'), held_out.left[0]) < 0.1, 20,
                 'the left arm at the predicted start')

        # The held-out execution: the task metric holds on what Baxter did.
        measured.keep()
        play(right, held_out.t, held_out.right)
        kept = measured.stop()
        self.assertGreater(len(kept), 50 * held_out.t[-1])
        values = tasks.metrics(TASK.key, np.array([k[1] for k in kept]),
                               np.array([k[2] for k in kept]))
        for name, bound in TASK.bounds.items():
            self.assertLessEqual(values[name], bound, '%s: %r' % (name, values))
        self.assertTrue(right.teleop.assist_left)

        # An unfamiliar leader motion: the assist holds the left arm, which stands still.
        odd = demonstration.unfamiliar(TASK.key, HELD_OUT_SEED)
        move_hand(right, odd.right[0])
        measured.keep()
        player = threading.Thread(target=play, args=(right, odd.t, odd.right))
        player.start()
        wait_for(lambda: assist['state'].state == AssistState.HOLDING
                 and 'unfamiliar' in assist['state'].detail, odd.t[-1],
                 'the assist holding on an unfamiliar motion')
        held_t = time.monotonic()
        wait_for(lambda: 'assist holding' in right.teleop.detail, 2, "arm_R saying it holds")
        player.join()
        resumed_t = min([t for t, state in log if t > held_t and state != AssistState.HOLDING]
                        + [time.monotonic()])
        kept = [k for k in measured.stop() if held_t + STILL_AFTER_HOLD_S < k[0] < resumed_t]
        self.assertGreater(len(kept), 50)
        held = np.array([k[1] for k in kept])
        self.assertLess(np.max(np.abs(held - held[0])), STILL_RAD)

        # Puppet L takes the left arm over from the assist with its own button.
        left.press(interface.BUTTON_LEFT)
        wait_for(lambda: left.teleop.follow_left and not right.teleop.assist_left, 5,
                 'puppet L driving the left arm, the assist no longer')
        self.assertIn('took', right.teleop.detail)


if __name__ == '__main__':
    rospy.init_node('test_assist_sim')
    rostest.rosrun('robopuppet', 'assist_sim', AssistTest)
