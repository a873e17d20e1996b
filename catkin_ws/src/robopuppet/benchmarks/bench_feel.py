#!/usr/bin/python3
"""Benchmark feel mode's loop: a change of Baxter's pose to the puppet setpoint frame carrying it.

Usage: benchmarks/bench_feel.py [--samples N] [--rate HZ]
(after `. tools/env.sh`; starts its own roscore)

The real config_R, serial_R and arm_R run as in main_sim (the state rate, comm_rate, at --rate,
100 Hz by default). The benchmark plays both ends itself: the puppet's microcontroller on a
pseudo-terminal (all joints Working, a state set at the state rate and a heartbeat every
second; it decodes what the host sends with robopuppet.protocol.codec) and Baxter (/robot/state
enabled and /robot/joint_states at 100 Hz, its right arm on the puppet's pose). It presses
button 3 (Baxter's right arm follows) and button 1 twice (limp, hold, feel), then steps
Baxter's right_w2 by 0.01 rad at a random moment, N times: latency = the first JointSetpoint
frame for joint 6 on the serial line carrying the new angle minus the moment of the step. It
includes the wait for Baxter's next joint states (up to 10 ms) and for the puppet's next state
set (arm_R streams the feel pose once per state set: up to one state period). Prints p50, p99,
max and the samples, the CPU of the three nodes and the machine's load; passes or fails nothing.
"""
import argparse
import os
import random
import signal
import statistics
import sys
import threading
import time
import tty

import psutil
import rospy
from baxter_core_msgs.msg import AssemblyState
from sensor_msgs.msg import JointState

from robopuppet import baxter_description as bd, interface
from robopuppet.protocol import codec
from robopuppet_msgs.msg import TeleopState

from bench_support import (cpu_seconds, percentile, private_roscore, start_process,
                           stop_process)

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests',
                                'integration'))
from hand_pose import HAND_POSE as POSE  # noqa: E402

STEPPED = 6           # right_w2: the joint whose measured angle Baxter steps
STEP_RAD = 0.01
BAXTER_RATE_HZ = 100.0
MATCH_RAD = 1e-6      # a float32 setpoint within this of the new angle carries it
NODES = ('config', 'serial', 'arm')


class Device:
    """The puppet's microcontroller on a pty: state sets out, host frames decoded and timed."""

    def __init__(self, link, rate_hz):
        self.link, self.period_s = link, 1.0 / rate_hz
        self.master, slave = os.openpty()
        tty.setraw(slave)
        os.symlink(os.ttyname(slave), link)
        self._slave = slave
        self.lock = threading.Lock()
        self.button = 0
        self.opmode = None   # the newest Opmode frame's mode (codec.LIMP / codec.HOLD)
        self.watch = None    # (angle, event, [arrival]) of the setpoint awaited
        self._stop = threading.Event()
        self._threads = [threading.Thread(target=f, daemon=True) for f in (self._write,
                                                                             self._read)]
        for thread in self._threads:
            thread.start()

    def _read(self):
        decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        while not self._stop.is_set():
            try:
                data = os.read(self.master, 4096)
            except OSError:
                return
            now = time.perf_counter()
            for message in decoder.feed(data):
                if isinstance(message, codec.Opmode):
                    self.opmode = message.mode
                elif isinstance(message, codec.JointSetpoint) and message.joint == STEPPED:
                    watch = self.watch
                    if watch and abs(message.angle_rad - watch[0]) < MATCH_RAD and \
                            not watch[1].is_set():
                        watch[2].append(now)
                        watch[1].set()

    def _write(self):
        due = beat = time.perf_counter()
        while not self._stop.is_set():
            with self.lock:
                button = self.button
            messages = [codec.JointState(j, 0, a, 0.0) for j, a in enumerate(POSE)]
            messages += [codec.Gripper(g, 1.0 if g == interface.END_PIECE_GRIPPER else 0.0)
                         for g in range(interface.NUM_GRIPPERS)]
            messages.append(codec.Buttons(button))
            if time.perf_counter() >= beat:
                messages.insert(0, codec.Heartbeat())
                beat += 1.0
            try:
                os.write(self.master, b''.join(codec.encode(m) for m in messages))
            except OSError:
                pass
            due += self.period_s
            time.sleep(max(due - time.perf_counter(), 0.0))

    def press(self, button):
        """Hold a user button down for 0.3 s, then let go."""
        with self.lock:
            self.button = button
        time.sleep(0.3)
        with self.lock:
            self.button = 0
        time.sleep(0.3)

    def close(self):
        self._stop.set()
        os.unlink(self.link)


class Baxter:
    """Baxter's /robot/state and /robot/joint_states at 100 Hz; its right arm where told."""

    def __init__(self):
        self.names = bd.arm_joint_names('left') + bd.arm_joint_names('right')
        left = bd.neutral_pose('left')
        self._left = [left[n] for n in bd.arm_joint_names('left')]
        self.right = list(POSE)
        self._state = rospy.Publisher(interface.ROBOT_STATE, AssemblyState, queue_size=10)
        self._joints = rospy.Publisher(interface.ROBOT_JOINT_STATES, JointState, queue_size=10,
                                       tcp_nodelay=True)
        self._timer = rospy.Timer(rospy.Duration(1.0 / BAXTER_RATE_HZ), self._publish)

    def _publish(self, event):
        self._state.publish(AssemblyState(enabled=True, ready=True))
        msg = JointState(name=self.names, position=self._left + self.right,
                         velocity=[0.0] * len(self.names), effort=[0.0] * len(self.names))
        msg.header.stamp = rospy.Time.now()
        self._joints.publish(msg)

    def stop(self):
        self._timer.shutdown()


class Teleop:
    """arm_R's newest teleop_state."""

    def __init__(self):
        self.msg = None
        rospy.Subscriber('%s/%s' % (interface.puppet_ns('R'), interface.TELEOP_STATE),
                         TeleopState, self._on)

    def _on(self, msg):
        self.msg = msg

    def wait(self, condition, timeout_s, what):
        deadline = time.monotonic() + timeout_s
        while not (self.msg is not None and condition(self.msg)):
            if time.monotonic() > deadline:
                raise RuntimeError('timed out waiting for %s (teleop_state %s)' % (what, self.msg))
            time.sleep(0.05)


def enter_feel(device, teleop):
    """Follow with Baxter's right arm (button 3) and cycle button 1 into feel mode."""
    teleop.wait(lambda m: m.state in (interface.READY, interface.FOLLOWING), 30, 'arm_R ready')
    if not teleop.msg.follow_right:
        device.press(interface.BUTTON_RIGHT)
    teleop.wait(lambda m: m.state == interface.FOLLOWING, 10, 'following')
    for _ in interface.OPMODES:
        if teleop.msg.opmode == interface.FEEL:
            break
        before = teleop.msg.opmode
        device.press(interface.BUTTON_OPMODE)
        teleop.wait(lambda m: m.opmode != before, 10, 'opmode after %s' % before)
    teleop.wait(lambda m: m.opmode == interface.FEEL, 1, 'opmode feel')
    deadline = time.monotonic() + 5
    while device.opmode != codec.HOLD:
        if time.monotonic() > deadline:
            raise RuntimeError('no hold frame on the serial line in feel mode')
        time.sleep(0.05)


def measure(device, baxter, teleop, samples, period_s, processes):
    """Step Baxter's pose `samples` times; return (latencies s, missed, feel restarts, CPU % per
    node, wall s, machine busy %). A step whose setpoint never comes is missed; if arm_R has
    left feel meanwhile (a fault: puppet samples late on a loaded machine), feel is entered
    again before the next step and counted."""
    latencies, missed, restarts = [], 0, 0
    cpu_before = {k: cpu_seconds(p) for k, p in processes.items()}
    psutil.cpu_percent()
    start = time.monotonic()
    for i in range(samples):
        time.sleep(random.uniform(0.0, period_s) + 0.02)
        right = list(baxter.right)
        right[STEPPED] = POSE[STEPPED] + (STEP_RAD if i % 2 == 0 else 0.0)
        watch = (right[STEPPED], threading.Event(), [])
        device.watch = watch
        stepped_t = time.perf_counter()
        baxter.right = right      # the next /robot/joint_states carries it
        if watch[1].wait(1.0):
            latencies.append(watch[2][0] - stepped_t)
            continue
        missed += 1
        if teleop.msg.opmode != interface.FEEL:
            restarts += 1
            enter_feel(device, teleop)
    wall = time.monotonic() - start
    busy = psutil.cpu_percent()
    cpu = {k: 100.0 * (cpu_seconds(p) - cpu_before[k]) / wall for k, p in processes.items()}
    return latencies, missed, restarts, cpu, wall, busy


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--samples', type=int, default=1000, help='pose steps to time')
    parser.add_argument('--rate', type=float, default=100.0, help='state rate (Hz)')
    options = parser.parse_args()
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit('bench_feel: terminated'))
    with private_roscore('bench_feel_') as work:
        log = open(os.path.join(work, 'nodes.log'), 'w')
        device = baxter = None
        processes = {}
        try:
            rospy.init_node('bench_feel', disable_signals=True)
            link = os.path.join(work, 'puppet_R')
            device = Device(link, options.rate)
            baxter, teleop = Baxter(), Teleop()
            ini = os.path.join(work, 'arm_R.ini')
            for key, args in (
                    ('config', ['config', '__name:=config_R', '_arm_side:=R',
                                '_file_name:=' + ini]),
                    ('serial', ['serial_interface', '__name:=serial_R', '_arm_side:=R',
                                '_port_name:=' + link, '_comm_rate:=%g' % options.rate]),
                    ('arm', ['arm', '__name:=arm_R', '_arm_side:=R',
                             '_comm_rate:=%g' % options.rate])):
                processes[key] = start_process(['rosrun', 'robopuppet'] + args, log)
            enter_feel(device, teleop)
            time.sleep(1.0)
            latencies, missed, restarts, cpu, wall, busy = measure(
                device, baxter, teleop, options.samples, 1.0 / options.rate, processes)
            teleop_now = teleop.msg
        finally:
            for process in processes.values():
                stop_process(process)
            if baxter is not None:
                baxter.stop()
            if device is not None:
                device.close()
            rospy.signal_shutdown('done')
            log.close()
    ms = sorted(1000.0 * x for x in latencies)
    print('Feel mode: Baxter pose change -> puppet setpoint frame on the serial line')
    print('state rate %g Hz, Baxter joint states %g Hz, teleop %s / opmode %s at the end'
          % (options.rate, BAXTER_RATE_HZ, teleop_now.state, teleop_now.opmode))
    if ms:
        print('samples %d (%d never arrived, feel entered again %d times): p50 %.1f ms, '
              'p99 %.1f ms, max %.1f ms, mean %.1f ms'
              % (len(ms), missed, restarts, percentile(ms, 0.5), percentile(ms, 0.99), ms[-1],
                 statistics.mean(ms)))
    else:
        print('no samples: %d steps never arrived' % missed)
    print('CPU %% of one core: %s; machine busy %.0f %% of %d cores, load average %s over %.0f s'
          % (', '.join('%s_R %.1f' % (k, cpu[k]) for k in NODES), busy, psutil.cpu_count(),
             ' '.join('%.2f' % x for x in os.getloadavg()), wall))
    return 0


if __name__ == '__main__':
    sys.exit(main())
