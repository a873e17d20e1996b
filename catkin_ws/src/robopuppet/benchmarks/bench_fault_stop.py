#!/usr/bin/python3
"""Benchmark: how long Baxter keeps moving after the puppet's last sample when the puppet dies.

Usage: benchmarks/bench_fault_stop.py [--trials N] [--comm-rate HZ]   (after `. tools/env.sh`;
own roscore)

Runs main_sim.launch headless (simulated puppet at comm_rate, Baxter stand-in, real config,
serial and arm nodes). Each trial: button 3, Baxter's right arm follows a hand that swings joint
e1 at up to 1.25 rad/s, faster than the stand-in's default mode-1 speed (30 % of the limit), as a
hurried hand does; then the simulated puppet is frozen (SIGSTOP by its pid, as a dead USB link or
a hung controller looks to the host). Measured: the time from the puppet's last joint_states to
the last /robot/joint_states in which Baxter's right arm still moved (more than 1e-5 rad on any
joint, i.e. faster than 1 mrad/s), and how far any joint moved from 0.5 s after the last data
on. The safety target is at most 0.5 s in every trial (interface.STOP_WITHIN_S); below 10 Hz
arm_X's state timeout is longer, and the stop it promises (robopuppet.arm.timing) is printed.
The puppet is then resumed (SIGCONT) and the next trial starts with a new press.
"""
import argparse
import os
import signal
import subprocess
import sys
import threading
import time

import rospy
from sensor_msgs.msg import JointState

from bench_support import percentile, private_roscore

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests',
                                'integration'))
from hand_pose import HAND_POSE  # noqa: E402
from teleop_harness import (PuppetArm, calibrate, max_error, node_pid,  # noqa: E402
                            swinging_hand, wait_for)

from robopuppet import baxter_description, interface  # noqa: E402
from robopuppet.arm import timing  # noqa: E402

MOVED_RAD = 1e-5


class RightArm:
    """Baxter's right arm as /robot/joint_states reports it: (receive time, 7 angles)."""

    def __init__(self):
        self._names = baxter_description.arm_joint_names('right')
        self._lock = threading.Lock()
        self.samples = []
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_joints,
                         queue_size=100)

    def _on_joints(self, msg):
        position = dict(zip(msg.name, msg.position))
        if all(n in position for n in self._names):
            with self._lock:
                self.samples.append((time.monotonic(), [position[n] for n in self._names]))

    def last_motion_t(self):
        """Return the receive time of the newest sample that differs from the one before it."""
        with self._lock:
            samples = list(self.samples)
        last = None
        for (_, before), (t, after) in zip(samples, samples[1:]):
            if max_error(before, after) > MOVED_RAD:
                last = t
        return last

    def moved_since(self, start_t):
        """Return the largest distance (rad) of any joint from its pose at start_t, after it."""
        with self._lock:
            after = [pose for t, pose in self.samples if t >= start_t]
        return max(max_error(after[0], pose) for pose in after)

    def pose(self):
        with self._lock:
            return self.samples[-1][1]


def trial(puppet, arm, pid):
    """Follow a moving hand, freeze the puppet; return (seconds of motion after its last data,
    rad moved from 0.5 s after it on)."""
    puppet.press(interface.BUTTON_RIGHT)
    wait_for(lambda: puppet.state() == interface.FOLLOWING, 10, 'following')
    wait_for(lambda: max_error(arm.pose(), puppet.angles) < 0.02, 20, 'arm on the puppet')
    with swinging_hand(puppet, HAND_POSE):
        time.sleep(1.5)  # the arm follows the swinging hand for a while
        os.kill(pid, signal.SIGSTOP)
        try:
            wait_for(lambda: puppet.state() == interface.FAULT, 10, 'fault')
            time.sleep(1.0)  # samples of Baxter standing still
            last_data_t = puppet.states_t[-1]
            moved_s = arm.last_motion_t() - last_data_t
            late_rad = arm.moved_since(last_data_t + 0.5)
        finally:
            os.kill(pid, signal.SIGCONT)
    puppet.hand(HAND_POSE)
    wait_for(lambda: puppet.state() == interface.READY, 20, 'ready after the puppet is back')
    return moved_s, late_rad


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--trials', type=int, default=20)
    parser.add_argument('--comm-rate', type=float, default=interface.DEFAULT_COMM_RATE_HZ,
                        help='state-set rate of the simulated puppet (Hz)')
    args = parser.parse_args()
    promised = timing.state_timeout(args.comm_rate)
    with private_roscore('bench_fault_stop_') as work:
        launch = subprocess.Popen(
            ['roslaunch', 'robopuppet', 'main_sim.launch', 'rviz:=false', 'gui:=false',
             'sim_link_prefix:=%s/pty' % work, 'comm_rate:=%g' % args.comm_rate],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            rospy.init_node('bench_fault_stop', disable_signals=True)
            puppet, arm = PuppetArm('R'), RightArm()
            wait_for(lambda: puppet.state() == interface.CALIBRATING, 60, 'arm_R calibrating')
            puppet.end_piece(False)
            calibrate(puppet, HAND_POSE)
            wait_for(lambda: puppet.state() == interface.READY, 10, 'ready')
            pid = node_pid('/puppet_sim_R')
            delays, late = [], []
            for k in range(args.trials):
                moved_s, late_rad = trial(puppet, arm, pid)
                delays.append(moved_s)
                late.append(late_rad)
                print('trial %2d: Baxter moved for %.3f s after the last puppet data, %.2f mrad '
                      'after 0.5 s' % (k + 1, moved_s, late_rad * 1e3), flush=True)
            print('comm_rate %g Hz: motion after the last puppet sample over %d trials: p50 %.3f '
                  's, max %.3f s (target: max <= %.1f s; arm_X promises %.2f s at this rate); '
                  'moved after 0.5 s: max %.2f mrad'
                  % (args.comm_rate, len(delays), percentile(delays, 0.5), max(delays),
                     interface.STOP_WITHIN_S, promised.stop_s, max(late) * 1e3))
        finally:
            launch.send_signal(signal.SIGINT)
            launch.wait(30)


if __name__ == '__main__':
    main()
