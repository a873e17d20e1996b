#!/usr/bin/python3
"""Benchmark baxter_sim: /robot/joint_states rate and jitter while both arms are commanded at
100 Hz, without and with obstacles, and the model step's cost with obstacles.

Usage (after `. tools/env.sh`): bench_baxter_sim.py [DURATION_S]  (default 20, per node run)
First times BaxterModel.step alone (no ROS; both arms moving, 2000 steps of 10 ms) without
obstacles, with config/bed_obstacles.yaml (the bed) while the arms move clear of it, and with the
right arm pressed into the bed (every step cut at contact): the cost obstacles add per step.
Then, three times (no obstacles; the bed; the bed with the right arm pressed into it), starts
its own roscore on a free port (ROS_HOME and logs in a temporary directory, removed at the end)
and the baxter_sim node, enables the robot, sends mode-1 joint commands to both arms at 100 Hz,
and prints the joint_states rate, the inter-message jitter (|interval - 10 ms|, from
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
from robopuppet.baxter_sim.baxter_contact import arm_contacts
from robopuppet.baxter_sim.baxter_model import POSITION_MODE, BaxterModel
from robopuppet.interface import BAXTER_SIDES
from robopuppet.world import obstacles

PACKAGE = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NODE = os.path.join(PACKAGE, 'nodes', 'baxter_sim')
BED = os.path.join(PACKAGE, 'config', 'bed_obstacles.yaml')
NOMINAL_S = 0.01
PRESS = {'right_s1': 0.6}   # the right arm's shoulder down, through the bed: pressed at contact


def targets(side, elapsed_s, press):
    """Return the joint names and mode-1 targets of a side: a slow sine wave (±0.5 rad about the
    neutral pose, clear of the bed), or with press the right arm pressed into the bed."""
    names = bd.arm_joint_names(side)
    phase = 0.5 * math.sin(elapsed_s)
    values = [bd.NEUTRAL_POSE[n.split('_')[1]] + phase for n in names]
    if press and side == 'right':
        values = [PRESS.get(n, bd.NEUTRAL_POSE[n.split('_')[1]]) for n in names]
    return names, values


def command_loop(rospy, publishers, stop, press):
    """Send both arms their targets in position mode at 100 Hz."""
    from baxter_core_msgs.msg import JointCommand
    rate = rospy.Rate(100)
    start = time.monotonic()
    while not stop.is_set() and not rospy.is_shutdown():
        for side, pub in publishers.items():
            names, values = targets(side, time.monotonic() - start, press)
            pub.publish(JointCommand(mode=JointCommand.POSITION_MODE, names=names,
                                     command=values))
        rate.sleep()


def step_costs(shapes, press, steps=2000):
    """Return the wall times (ms) of BaxterModel.step with both arms commanded every step."""
    urdf = open(bd.URDF_PATH).read()
    description = bd.Description(urdf)
    model = BaxterModel(description, 0.0, contacts=arm_contacts(description, urdf, shapes))
    model.set_enabled(True)
    costs = []
    for i in range(steps):
        now_s = i * NOMINAL_S
        for side in BAXTER_SIDES:
            model.joint_command(side, POSITION_MODE, *targets(side, now_s, press), now_s)
        start = time.perf_counter()
        model.step(now_s + NOMINAL_S)
        costs.append(1000.0 * (time.perf_counter() - start))
    return costs[200:]   # from 2 s on: pressed by then


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


def run_node(duration_s, obstacles_file, press):
    """Measure the node with an obstacle file ('' none), the right arm pressed or not."""
    node = None
    with private_roscore('bench_baxter_sim_'):
        try:
            node = subprocess.Popen([NODE, '_obstacles_file:=' + obstacles_file],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
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
            commander = threading.Thread(target=command_loop,
                                         args=(rospy, publishers, stop, press))
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
            print('baxter_sim node: %.0f s, both arms commanded at 100 Hz (mode 1), obstacles %s%s'
                  % (duration_s, obstacles_file or 'none',
                     ', the right arm pressed into them' if press else ''))
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


def main():
    duration_s = float(sys.argv[1]) if len(sys.argv) > 1 else 20.0
    bed = obstacles.load_obstacles(BED)
    print('BaxterModel.step, both arms (ms per 10 ms step; 1800 steps):')
    for what, shapes, press in (('no obstacles', [], False), ('bed, arms clear', bed, False),
                                ('bed, right arm pressed', bed, True)):
        costs = step_costs(shapes, press)
        print('  %-24s p50 %.3f, p99 %.3f, max %.3f, mean %.3f'
              % (what, percentile(costs, 0.5), percentile(costs, 0.99), max(costs),
                 sum(costs) / len(costs)))
    for obstacles_file, press in (('', False), (BED, False), (BED, True)):
        # A process each: rospy runs one node per process, and each run has its own roscore.
        run = multiprocessing.get_context('spawn').Process(
            target=run_node, args=(duration_s, obstacles_file, press))
        run.start()
        run.join()


if __name__ == '__main__':
    main()
