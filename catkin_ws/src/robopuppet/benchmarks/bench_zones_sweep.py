#!/usr/bin/python3
"""Benchmark: Baxter's measured pose against the keep-out zones during a fast random sweep.

Usage: benchmarks/bench_zones_sweep.py [--seconds S] [--seed N] [--arm right|left|both]
(after `. tools/env.sh`; own roscore)

Runs main_sim.launch headless with its defaults (config/zones.yaml, the stand-in's bed). Puppet
R drives Baxter's right arm (button 3, as is), its left arm (button 2, mirrored) or both while
the operator's hand goes through seeded random poses across the puppet's whole range at the
simulated hand's top speed (tests/integration/sweep_harness.py, as test_zones_sweep.py does).
Every /robot/joint_states sample goes through the capsule model (world.zones.ZoneGuard with
world.arm_capsules.ArmCapsules, the zones as arm_X loads them). Printed per arm: tracking lag
p50 / p99 / max per joint, |Baxter measured - puppet target| (rad; the target: the newest puppet
pose, mirrored for the other side's arm, clamped to Baxter's limits), the arm's travel, the
share of samples inside a zone; then the minimum clearance (mm, zone, link), the sample count,
arm_R's faults (each resumed by pressing again) and arm_R's CPU share.
"""
import argparse
import os
import signal
import subprocess
import sys

import psutil
import rospy

from bench_support import private_roscore

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests',
                                'integration'))
from hand_pose import HAND_POSE  # noqa: E402
from sweep_harness import (ARM_SIDES, Recorder, keep_following,  # noqa: E402
                           package_guards, report, start_following, sweeping_hand)
from teleop_harness import PuppetArm, node_pid  # noqa: E402

from robopuppet import interface  # noqa: E402
from robopuppet.puppet_sim.puppet_arm import HAND_SPEED_RADPS  # noqa: E402


def sweep(seconds, seed, arm):
    """Follow with `arm`'s buttons, sweep the hand for `seconds`; print the figures."""
    arms = interface.BAXTER_SIDES if arm == 'both' else (arm,)
    guards, puppet, recorder = package_guards(), PuppetArm('R'), Recorder('R')
    start = start_following(puppet, recorder, arms, HAND_POSE)
    controller = psutil.Process(node_pid('/arm_R'))
    cpu = controller.cpu_times()
    load = os.getloadavg()[0]
    sweep_start = rospy.get_time()
    with sweeping_hand(puppet, seed) as poses:
        faults = keep_following(puppet, ARM_SIDES[arm], seconds)
    end = rospy.get_time()
    used = controller.cpu_times()
    busy = (used.user + used.system - cpu.user - cpu.system) / (end - sweep_start)
    found = report(guards, recorder, start, end, arms, sweep_start)
    print('zones sweep: puppet R drives %s, seed %d, %.0f s, %d poses at %.0f rad/s per joint'
          % (' and '.join('the %s arm' % a for a in arms), seed, seconds, len(poses),
             HAND_SPEED_RADPS))
    print('\n'.join(found.lines))
    print('arm_R faults: %d (%.1f s not following); arm_R CPU %.0f %% of a core; load average '
          '%.2f at start, %.2f at end' % (len(faults), sum(b - a for a, b in faults),
                                         100.0 * busy, load, os.getloadavg()[0]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--seconds', type=float, default=60.0, help='sweep duration (s)')
    parser.add_argument('--seed', type=int, default=1, help='seed of the random hand poses')
    parser.add_argument('--arm', choices=sorted(ARM_SIDES), default='both',
                        help="Baxter's arms that follow puppet R (left: mirrored)")
    args = parser.parse_args()
    with private_roscore('bench_zones_sweep_') as work:
        launch = subprocess.Popen(
            ['roslaunch', 'robopuppet', 'main_sim.launch', 'rviz:=false', 'gui:=false',
             'sim_link_prefix:=%s/pty' % work],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            rospy.init_node('bench_zones_sweep', disable_signals=True)
            sweep(args.seconds, args.seed, args.arm)
        finally:
            rospy.signal_shutdown('done')
            launch.send_signal(signal.SIGINT)
            launch.wait(30)


if __name__ == '__main__':
    main()
