#!/usr/bin/python3
"""Benchmark: latency from a puppet movement to the first Baxter JointCommand that carries it.

Usage: benchmarks/bench_teleop.py [--samples N] [--record [--rounds R]]
(after `. tools/env.sh`; starts its own roscore)

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

--record: recording on vs off instead, at comm_rate 100 only, N samples per mode: no
recorder; the real recorder running idle (recorder.launch, record_sides:=R); and recording, an
episode of the whole traffic (side R and Baxter's topics) started and stopped through
/puppet/record. The modes run in R rounds of interleaved blocks (order reversed every other
round) on one host stack, so that a change in the load of other processes on the machine falls
on every mode alike. Printed: p50/p99 per mode and the differences, CPU per process, the
machine's CPU busy share, and what the episodes hold.
"""
import argparse
import collections
import os
import random
import signal
import statistics
import sys
import threading
import time

import psutil
import rospy
from baxter_core_msgs.msg import JointCommand
from sensor_msgs.msg import JointState

from robopuppet import interface
from robopuppet.protocol import codec
from robopuppet_msgs.msg import TeleopState

import bench_teleop_record
from bench_support import (cpu_seconds, percentile, private_roscore, run_queue_wait_s,
                           start_process, stop_process)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests',
                                'integration'))
from hand_pose import HAND_POSE  # noqa: E402

HOST_NODES = ('config', 'serial', 'arm')
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
        self.angles = list(HAND_POSE)
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


Block = collections.namedtuple('Block', 'latencies cpu wait command_rate busy faults')
Block.__doc__ = """One run of moves: latencies (s); by process name, CPU % of one core and the time
its threads waited for a CPU (run queue, ms per s); JointCommands per second; the machine's CPU
busy share (% of all cores, every process on it); and arm_R's faults (after each, the puppet's
button 3 was pressed again to follow)."""


class Stack:
    """Side R's host stack (config, serial, arm nodes; 2020 relays when legacy) on a Device.

    A context manager: entering starts it, leaving stops every process it started.
    """

    def __init__(self, name, rate_hz, legacy, work, log):
        self.name, self.rate_hz, self.legacy = name, rate_hz, legacy
        self._work, self._log = work, log
        self.processes = {}
        self.relays = []
        self.commands = []  # (reception time, joint 6 command)
        self._watch = {'angle': None, 't': None, 'hit': threading.Event()}
        self._subs = []
        self.device = None
        self.state = None    # arm_R's teleop_state
        self.faults = 0

    def __enter__(self):
        try:
            self._start()
        except BaseException:
            self.close()
            raise
        return self

    def __exit__(self, *exc):
        self.close()

    def _start(self):
        slug = self.name.replace(' ', '_')
        link = os.path.join(self._work, 'puppet_%s' % slug)
        self.device = Device(link, self.rate_hz)
        states_topic = '%s/%s' % (interface.puppet_ns('R'), interface.JOINT_STATES)
        arm_args = ['_command_rate:=100', '_comm_rate:=%g' % self.rate_hz]
        if self.legacy:
            self.relays = [Relay(states_topic, '/bench/serial_loop', 10.0),
                           Relay('/bench/serial_loop', '/bench/arm_loop', 10.0)]
            arm_args = ['_command_rate:=10', '_comm_rate:=%g' % self.rate_hz,
                        '%s:=/bench/arm_loop' % states_topic]
        ini = os.path.join(self._work, 'arm_R_%s.ini' % slug)
        for key, args in (
                ('config', ['config', '__name:=config_R', '_arm_side:=R', '_file_name:=' + ini]),
                ('serial', ['serial_interface', '__name:=serial_R', '_arm_side:=R',
                            '_port_name:=' + link]),
                ('arm', ['arm', '__name:=arm_R', '_arm_side:=R'] + arm_args)):
            self.processes[key] = start_process(['rosrun', 'robopuppet'] + args, self._log)
        self._subs = [
            rospy.Subscriber(interface.limb_topic('right', 'joint_command'), JointCommand,
                             self._on_command, queue_size=1000, tcp_nodelay=True),
            rospy.Subscriber('%s/%s' % (interface.puppet_ns('R'), interface.TELEOP_STATE),
                             TeleopState, self._on_teleop_state)]
        time.sleep(4.0)  # nodes up, settings loaded, Baxter enabled
        self._follow()

    def _on_teleop_state(self, msg):
        if msg.state == interface.FAULT and self.state != interface.FAULT:
            self.faults += 1
        self.state = msg.state

    def _follow(self):
        """Press button 3 until arm_R follows, then wait until Baxter is commanded the puppet."""
        deadline = time.monotonic() + 30
        while self.state != interface.FOLLOWING:
            if time.monotonic() > deadline:
                raise RuntimeError('%s: arm_R never followed (%s)' % (self.name, self.state))
            with self.device.lock:
                self.device.button = interface.BUTTON_RIGHT
            time.sleep(0.5)
            with self.device.lock:
                self.device.button = 0
            pressed_t = time.monotonic()
            while self.state != interface.FOLLOWING and time.monotonic() < pressed_t + 2.0:
                time.sleep(0.05)
        with self.device.lock:
            angle = self.device.angles[6]
        while not (self.commands and abs(self.commands[-1][1] - angle) < 1e-6):
            if time.monotonic() > deadline:
                raise RuntimeError('%s: Baxter never tracked the puppet' % self.name)
            time.sleep(0.1)
        time.sleep(1.0)

    def _on_command(self, msg):
        now = time.monotonic()
        self.commands.append((now, msg.command[6]))
        watch = self._watch
        if watch['angle'] is not None and abs(msg.command[6] - watch['angle']) < 1e-6 \
                and not watch['hit'].is_set():
            watch['t'] = now
            watch['hit'].set()

    def measure(self, samples, others=None):
        """Make samples moves of joint 6; return a Block (CPU of ours and of others' Popens)."""
        watched = dict(self.processes, **(others or {}))
        cpu_before = {key: cpu_seconds(process) for key, process in watched.items()}
        wait_before = {key: run_queue_wait_s(process) for key, process in watched.items()}
        psutil.cpu_percent()
        wall_before = time.monotonic()
        count_before = len(self.commands)
        faults_before = self.faults
        latencies = []
        with self.device.lock:
            angle = self.device.angles[6]
        for i in range(samples):
            time.sleep(random.uniform(0.0, 1.0 / self.rate_hz) + (0.35 if self.legacy else 0.03))
            angle += STEP_RAD if i % 2 == 0 else -STEP_RAD
            self._watch['hit'].clear()
            self._watch['angle'] = angle
            moved_t = self.device.move(angle)
            if self._watch['hit'].wait(2.0):
                latencies.append(self._watch['t'] - moved_t)
                continue
            gone = ['%s (exit %s)' % (key, process.poll()) for key, process in watched.items()
                    if process.poll() is not None]
            if gone:
                raise RuntimeError('%s: %s ended during the run' % (self.name, ', '.join(gone)))
            if self.state != interface.FOLLOWING:
                self._follow()
        wall = time.monotonic() - wall_before
        busy = psutil.cpu_percent()
        cpu = {key: 100.0 * (cpu_seconds(process) - cpu_before[key]) / wall
               for key, process in watched.items()}
        wait = {key: 1000.0 * (run_queue_wait_s(process) - wait_before[key]) / wall
                for key, process in watched.items()}
        return Block(latencies, cpu, wait, (len(self.commands) - count_before) / wall, busy,
                     self.faults - faults_before)

    def close(self):
        for sub in self._subs:
            sub.unregister()
        for relay in self.relays:
            relay.stop()
        for process in self.processes.values():
            stop_process(process)
        if self.device is not None:
            self.device.close()


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--samples', type=int, default=200,
                        help='moves per configuration (per mode with --record)')
    parser.add_argument('--record', action='store_true',
                        help='recording on vs off at comm_rate 100 instead of the rates')
    parser.add_argument('--rounds', type=int, default=16,
                        help='with --record: interleaved rounds the samples are spread over')
    options = parser.parse_args()
    # Stop cleanly (every process this starts) on Ctrl-C and on kill, also when run in the
    # background, where SIGINT comes in ignored.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit('bench_teleop: terminated'))
    with private_roscore('bench_teleop_') as work:
        log = open(os.path.join(work, 'nodes.log'), 'w')
        baxter = None
        try:
            baxter = start_process(['rosrun', 'robopuppet', 'baxter_sim',
                                    '_gripper_calibrated:=true'], log)
            rospy.init_node('bench_teleop', disable_signals=True)
            if options.record:
                with Stack('recording', 100.0, False, work, log) as stack:
                    bench_teleop_record.run(stack, options.samples, max(options.rounds, 1),
                                            work, log, baxter)
            else:
                run_rates(options.samples, work, log)
        finally:
            rospy.signal_shutdown('done')
            if baxter is not None:
                stop_process(baxter)
            log.close()


def run_rates(samples, work, log):
    """Run every configuration against the running Baxter stand-in and print its figures."""
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
        with Stack(name, rate, legacy, work, log) as stack:
            block = stack.measure(count)
        latencies = block.latencies
        lost = count - len(latencies)
        target = '' if legacy else '%.1f' % (1000.0 / rate + 3.0)
        print('%-27s %7d %8.1f %8.1f %8s %9.0f  %s%s%s' % (
            name, len(latencies), 1000 * statistics.median(latencies),
            1000 * percentile(latencies, 0.99), target, block.command_rate,
            ' '.join('%.1f' % block.cpu[k] for k in HOST_NODES),
            '  (%d moves never arrived)' % lost if lost else '',
            ', %d arm_R faults' % block.faults if block.faults else ''), flush=True)


if __name__ == '__main__':
    main()
