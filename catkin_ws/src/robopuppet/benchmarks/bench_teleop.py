#!/usr/bin/python3
"""Benchmark: latency from a puppet movement to the first Baxter JointCommand that carries it.

Usage: benchmarks/bench_teleop.py [--samples N]   (after `. tools/env.sh`; starts its own roscore)

The benchmark plays the puppet's microcontroller itself on a pseudo-terminal (heartbeat, state
sets at comm_rate, all joints Working), so that a "hand movement" is an instant change of joint 6's
angle at a random moment; the real config, serial and arm nodes and the Baxter stand-in run as in
main_sim. Latency = first JointCommand on /robot/limb/right/joint_command carrying the new angle
minus the moment of the change; it includes the wait for the next state frame (up to one state
period), so the target is p99 <= one state period + 3 ms.

The 2020 design's timing is measured in the same run: state stream at 10 Hz, and two relays in
this process that poll at a fixed 10 Hz like the 2020 host loops (the serial node's update loop and
the arm controller's loop) between the serial node and the arm node.

Also printed: the CPU share of the host stack (config, serial and arm nodes) at each rate.
"""
import argparse
import os
import random
import signal
import statistics
import subprocess
import sys
import threading
import time

import psutil
import rospy
from baxter_core_msgs.msg import JointCommand
from sensor_msgs.msg import JointState

from robopuppet import interface
from robopuppet.protocol import codec

from bench_support import percentile, private_roscore

HOST_NODES = ('config', 'serial', 'arm')
POSE = [0.2, 0.4, 0.3, 1.0, -0.3, 0.6, 0.25]
STEP_RAD = 0.01


class Device:
    """A puppet microcontroller on a pty: streams Working joint states at a fixed rate."""

    def __init__(self, link, rate_hz):
        self.link = link
        self.period_s = 1.0 / rate_hz
        self.master, slave = os.openpty()
        os.symlink(os.ttyname(slave), link)
        self._slave = slave
        self.lock = threading.Lock()
        self.angles = list(POSE)
        self.button = 0
        self.changed_t = None
        self._stop = False
        threading.Thread(target=self._write, daemon=True).start()
        threading.Thread(target=self._drain, daemon=True).start()

    def _drain(self):
        while not self._stop:
            try:
                os.read(self.master, 4096)  # the host's frames: settings, opmode; not needed
            except OSError:
                time.sleep(0.01)

    def _write(self):
        next_t = time.monotonic()
        beat_t = next_t
        while not self._stop:
            with self.lock:
                frames = [codec.encode(codec.JointState(j, 0, a, 0.0))
                          for j, a in enumerate(self.angles)]
                frames += [codec.encode(codec.Gripper(g, 1.0 if g == interface.END_PIECE_GRIPPER
                                                   else 0.0))
                           for g in range(interface.NUM_GRIPPERS)]
                frames.append(codec.encode(codec.Buttons(self.button)))
            if time.monotonic() >= beat_t:
                frames.insert(0, codec.encode(codec.Heartbeat()))
                beat_t += 1.0
            try:
                os.write(self.master, b''.join(frames))
            except OSError:
                pass
            next_t += self.period_s
            time.sleep(max(next_t - time.monotonic(), 0.0))

    def move(self, angle):
        """Set joint 6 to angle now; return the moment of the change."""
        with self.lock:
            self.angles[6] = angle
            self.changed_t = time.monotonic()
            return self.changed_t

    def close(self):
        self._stop = True
        os.unlink(self.link)


class Relay:
    """Republish the newest JointState on a fixed-rate loop, like a polled 2020 host loop."""

    def __init__(self, source, target, rate_hz):
        self._newest = None
        self._pub = rospy.Publisher(target, JointState, queue_size=10, tcp_nodelay=True)
        self._sub = rospy.Subscriber(source, JointState, self._on_msg, tcp_nodelay=True)
        self._timer = rospy.Timer(rospy.Duration(1.0 / rate_hz), self._on_timer)

    def _on_msg(self, msg):
        self._newest = msg

    def _on_timer(self, event):
        if self._newest is not None:
            self._pub.publish(self._newest)
            self._newest = None

    def stop(self):
        self._timer.shutdown()
        self._sub.unregister()
        self._pub.unregister()


def start(args, log):
    return subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def stop(process):
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGINT)
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def run_scenario(name, rate_hz, legacy, samples, work, log):
    """Run one configuration; return (latencies s, cpu shares % by node, command count)."""
    link = os.path.join(work, 'puppet_%s' % name.replace(' ', '_'))
    device = Device(link, rate_hz)
    states_topic = '%s/%s' % (interface.puppet_ns('R'), interface.JOINT_STATES)
    relays = []
    arm_args = ['_command_rate:=100', '_comm_rate:=%g' % rate_hz]
    if legacy:
        relays = [Relay(states_topic, '/bench/serial_loop', 10.0),
                  Relay('/bench/serial_loop', '/bench/arm_loop', 10.0)]
        arm_args = ['_command_rate:=10', '_comm_rate:=%g' % rate_hz,
                    '%s:=/bench/arm_loop' % states_topic]
    ini = os.path.join(work, 'arm_R_%s.ini' % name.replace(' ', '_'))
    processes = {
        'config': start(['rosrun', 'robopuppet', 'config', '__name:=config_R', '_arm_side:=R',
                         '_file_name:=' + ini], log),
        'serial': start(['rosrun', 'robopuppet', 'serial_interface', '__name:=serial_R',
                         '_arm_side:=R', '_port_name:=' + link], log),
        'arm': start(['rosrun', 'robopuppet', 'arm', '__name:=arm_R', '_arm_side:=R'] + arm_args,
                     log),
    }
    commands = []  # (reception time, joint 6 command)
    watch = {'angle': None, 't': None, 'hit': threading.Event()}

    def on_command(msg):
        now = time.monotonic()
        commands.append((now, msg.command[6]))
        if watch['angle'] is not None and abs(msg.command[6] - watch['angle']) < 1e-6 \
                and not watch['hit'].is_set():
            watch['t'] = now
            watch['hit'].set()

    sub = rospy.Subscriber(interface.limb_topic('right', 'joint_command'), JointCommand, on_command,
                           queue_size=1000, tcp_nodelay=True)
    try:
        time.sleep(4.0)  # nodes up, settings loaded, Baxter enabled
        with device.lock:
            device.button = interface.BUTTON_RIGHT
        time.sleep(0.5)
        with device.lock:
            device.button = 0
        deadline = time.monotonic() + 30
        while not (commands and abs(commands[-1][1] - POSE[6]) < 1e-6):
            if time.monotonic() > deadline:
                raise RuntimeError('%s: Baxter never tracked the puppet' % name)
            time.sleep(0.1)
        time.sleep(1.0)
        cpu_before = {k: psutil.Process(p.pid).cpu_times() for k, p in processes.items()}
        wall_before = time.monotonic()
        count_before = len(commands)
        latencies = []
        angle = POSE[6]
        for i in range(samples):
            time.sleep(random.uniform(0.0, 1.0 / rate_hz) + (0.35 if legacy else 0.03))
            angle += STEP_RAD if i % 2 == 0 else -STEP_RAD
            watch['hit'].clear()
            watch['angle'] = angle
            moved_t = device.move(angle)
            if watch['hit'].wait(2.0):
                latencies.append(watch['t'] - moved_t)
        wall = time.monotonic() - wall_before
        cpu = {}
        for key, process in processes.items():
            after = psutil.Process(process.pid).cpu_times()
            used = (after.user - cpu_before[key].user) + (after.system - cpu_before[key].system)
            cpu[key] = 100.0 * used / wall
        command_rate = (len(commands) - count_before) / wall
        return latencies, cpu, command_rate
    finally:
        sub.unregister()
        for relay in relays:
            relay.stop()
        for process in processes.values():
            stop(process)
        device.close()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--samples', type=int, default=200, help='moves per configuration')
    options = parser.parse_args()
    with private_roscore('bench_teleop_') as work:
        run_all(options.samples, work)


def run_all(samples, work):
    """Start the Baxter stand-in, run every configuration and print its figures."""
    log = open(os.path.join(work, 'nodes.log'), 'w')
    baxter = None
    try:
        baxter = start(['rosrun', 'robopuppet', 'baxter_sim', '_gripper_calibrated:=true'], log)
        rospy.init_node('bench_teleop', disable_signals=True)
        scenarios = [('2020 timing (10 Hz loops)', 10.0, True, max(samples // 4, 30)),
                     ('comm_rate 10', 10.0, False, max(samples // 4, 30)),
                     ('comm_rate 100', 100.0, False, samples),
                     ('comm_rate 250', 250.0, False, samples),
                     ('comm_rate 500', 500.0, False, samples),
                     ('comm_rate 1000', 1000.0, False, samples)]
        print('Latency from a puppet movement to the first JointCommand carrying it')
        print('%-27s %7s %8s %8s %8s %9s  %s' % ('configuration', 'samples', 'p50 ms', 'p99 ms',
                                                'target', 'cmd/s', 'CPU % (config serial arm)'))
        for name, rate, legacy, count in scenarios:
            print('running %s ...' % name, file=sys.stderr, flush=True)
            latencies, cpu, command_rate = run_scenario(name, rate, legacy, count, work, log)
            lost = count - len(latencies)
            target = '' if legacy else '%.1f' % (1000.0 / rate + 3.0)
            print('%-27s %7d %8.1f %8.1f %8s %9.0f  %s%s' % (
                name, len(latencies), 1000 * statistics.median(latencies),
                1000 * percentile(latencies, 0.99), target, command_rate,
                ' '.join('%.1f' % cpu[k] for k in HOST_NODES),
                '  (%d moves never arrived)' % lost if lost else ''), flush=True)
    finally:
        rospy.signal_shutdown('done')
        if baxter is not None:
            stop(baxter)
        log.close()


if __name__ == '__main__':
    main()
