#!/usr/bin/python3
"""Benchmark baxter_sim: /robot/joint_states rate and jitter while both arms are commanded at 100 Hz.

Usage (after `. tools/env.sh`): bench_baxter_sim.py [DURATION_S]  (default 20)
Starts its own roscore on a free port (ROS_HOME and logs in a temporary directory, removed at
the end) and the baxter_sim node, enables the robot, sends mode-1 joint commands to both arms at
100 Hz, and prints the joint_states rate, the inter-message jitter (|interval - 10 ms|, from
header stamps = the node's loop, and from arrival times = what a subscriber sees; both taken by
a subscriber in a process of its own, like a subscriber node) and the node's CPU share (% of one
core). For comparison another process runs a bare Python 100 Hz sleep loop in the same window:
the floor that the machine's load (other users of its cores) allows at that time.
"""
import math
import multiprocessing
import os
import subprocess
import sys
import threading
import time

import psutil

from bench_support import percentile, private_roscore
from robopuppet import baxter_description as bd, interface
from robopuppet.interface import BAXTER_SIDES

NODE = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), 'nodes',
                    'baxter_sim')
NOMINAL_S = 0.01


def command_loop(rospy, publishers, stop):
    """Send both arms a slow sine wave in position mode at 100 Hz."""
    from baxter_core_msgs.msg import JointCommand
    rate = rospy.Rate(100)
    start = time.monotonic()
    while not stop.is_set() and not rospy.is_shutdown():
        phase = 0.5 * math.sin(time.monotonic() - start)
        for side, pub in publishers.items():
            names = bd.arm_joint_names(side)
            targets = [bd.NEUTRAL_POSE[n.split('_')[1]] + phase for n in names]
            pub.publish(JointCommand(mode=JointCommand.POSITION_MODE, names=names,
                                     command=targets))
        rate.sleep()


def sleep_loop_intervals(start, end):
    """Return the intervals of a bare Python 100 Hz sleep loop from start to end (monotonic s):
    the jitter floor that the machine's load allows."""
    time.sleep(max(0.0, start - time.monotonic()))
    wakes = []
    deadline = time.monotonic()
    while deadline < end:
        deadline += NOMINAL_S
        time.sleep(max(0.0, deadline - time.monotonic()))
        wakes.append(time.monotonic())
    return [b - a for a, b in zip(wakes, wakes[1:])]


def listen(start, end):
    """Subscribe to /robot/joint_states in a process of its own, like a subscriber node, and
    return (header stamps, arrival times) of the messages that arrive from start to end."""
    import rospy
    from sensor_msgs.msg import JointState
    stamps, arrivals = [], []

    def on_joint_states(msg):
        now = time.monotonic()
        if start <= now < end:
            arrivals.append(now)
            stamps.append(msg.header.stamp.to_sec())

    rospy.init_node('bench_baxter_sim_listener', disable_signals=True)
    rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, on_joint_states, queue_size=100)
    time.sleep(max(0.0, end - time.monotonic()) + 0.1)
    rospy.signal_shutdown('benchmark done')
    return stamps, arrivals


def report(name, intervals_s):
    jitter_ms = [abs(i - NOMINAL_S) * 1000.0 for i in intervals_s]
    print('  %-8s interval mean %.3f ms, p50 %.3f ms, max %.3f ms; jitter p99 %.3f ms, max %.3f ms'
          % (name, 1000.0 * sum(intervals_s) / len(intervals_s),
             1000.0 * percentile(intervals_s, 0.5), 1000.0 * max(intervals_s),
             percentile(jitter_ms, 0.99), max(jitter_ms)))


def main():
    duration_s = float(sys.argv[1]) if len(sys.argv) > 1 else 20.0
    node = None
    with private_roscore('bench_baxter_sim_'):
        try:
            node = subprocess.Popen([NODE], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            import rospy
            from baxter_core_msgs.msg import JointCommand
            from sensor_msgs.msg import JointState
            from std_msgs.msg import Bool
            rospy.init_node('bench_baxter_sim', disable_signals=True)
            rospy.wait_for_message(interface.ROBOT_JOINT_STATES, JointState, timeout=20.0)
            enable = rospy.Publisher(interface.SET_SUPER_ENABLE, Bool, queue_size=1, latch=True)
            enable.publish(Bool(True))
            publishers = {side: rospy.Publisher(interface.limb_topic(side, 'joint_command'),
                                                JointCommand, queue_size=10)
                          for side in BAXTER_SIDES}
            stop = threading.Event()
            commander = threading.Thread(target=command_loop, args=(rospy, publishers, stop))
            commander.start()
            process = psutil.Process(node.pid)
            # One window for all measurements, after the listener has connected and the arms move.
            start = time.monotonic() + 3.0
            end = start + duration_s
            with multiprocessing.get_context('spawn').Pool(2) as pool:
                floor = pool.apply_async(sleep_loop_intervals, (start, end))
                listened = pool.apply_async(listen, (start, end))
                time.sleep(start - time.monotonic())
                cpu_before, wall_before = process.cpu_times(), time.monotonic()
                time.sleep(end - time.monotonic())
                cpu_after, wall_after = process.cpu_times(), time.monotonic()
                floor = floor.get(timeout=10.0)
                stamps, arrivals = listened.get(timeout=10.0)
            stop.set()
            commander.join()
            cpu_s = (cpu_after.user + cpu_after.system) - (cpu_before.user + cpu_before.system)
            print('baxter_sim benchmark: %.0f s, both arms commanded at 100 Hz (mode 1)' % duration_s)
            print('  /robot/joint_states: %d messages, %.1f Hz (stamps), %.1f Hz (arrivals)'
                  % (len(stamps), (len(stamps) - 1) / (stamps[-1] - stamps[0]),
                     (len(arrivals) - 1) / (arrivals[-1] - arrivals[0])))
            report('stamps', [b - a for a, b in zip(stamps, stamps[1:])])
            report('arrivals', [b - a for a, b in zip(arrivals, arrivals[1:])])
            report('floor', floor)
            print('  (stamps and arrivals: a subscriber in a process of its own; floor: a bare Python'
                  ' 100 Hz\n   time.sleep loop in another process, same window)')
            print('  node CPU: %.1f %% of one core (%d cores on this machine)'
                  % (100.0 * cpu_s / (wall_after - wall_before), psutil.cpu_count()))
            rospy.signal_shutdown('benchmark done')
        finally:
            if node is not None:
                node.terminate()
                node.wait(timeout=10)


if __name__ == '__main__':
    main()
