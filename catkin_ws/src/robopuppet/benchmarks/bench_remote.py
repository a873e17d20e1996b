#!/usr/bin/python3
"""Benchmark: latency from a hand movement on the operator host to the JointCommand carrying it
on the robot host, across the network test bed (issue 9), at several one-way delays.

Usage: benchmarks/bench_remote.py [--samples N] [--delays 0,10,50,100] [--jitter 0.1]
(as root, after `. tools/env.sh`; builds its own bed: tools/netbed, and its own roscore)

The bed's robot host runs roscore and robot.launch (arm_R, the Baxter stand-in); the operator
host runs operator.launch (config_R, serial_R, recorder, ghost; no GUI, no RViz) at comm_rate 100
on a pseudo-terminal whose other end this process plays as the puppet's microcontroller
(bench_teleop.Device: heartbeat, state sets at 100 Hz, all joints Working). A "hand movement" is
an instant change of joint 6 at a random moment; a listener on the robot host (tests/network/
helpers/command_stamps.py, tcp_nodelay) stamps each JointCommand on
/robot/limb/right/joint_command with time.time() on arrival (the namespaces share the kernel's
clock). Latency = that stamp of the first command carrying the new angle minus the moment of the
change; added = latency minus the nominal one-way delay (the bed releases packets in order, so
with jitter the effective delay rises towards delay + jitter). Target: added p99 <= one state
period + 3 ms (13 ms at 100 Hz). A move lost to an arm_R fault is counted, and button 3 pressed
again.

Also counted: consecutive JointCommands that move a joint faster than its velocity limit
(over their arrival interval plus 5 ms of reception jitter); target zero.
"""
import argparse
import json
import os
import pathlib
import random
import signal
import statistics
import sys
import time

from robopuppet import baxter_description, interface

import bench_teleop
from bench_support import percentile

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / 'tests' / 'network'))
from netbed_testing import HELPERS, RosBed  # noqa: E402

COMM_RATE_HZ = 100.0
STEP_RAD = 0.01
RECEPTION_JITTER_S = 0.005
LIMITS = baxter_description.arm_limits('right')


class Listener:
    """A ros_node.py listener's output, read incrementally: [(t, msg)]."""

    def __init__(self, proc):
        self.proc, self.items, self._offset = proc, [], 0

    def update(self):
        with open(self.proc.log_path) as log:
            log.seek(self._offset)
            text = log.read()
        end = text.rfind('\n') + 1
        self._offset += len(text[:end].encode())
        for line in text[:end].splitlines():
            if line.startswith('{"t"'):
                item = json.loads(line)
                self.items.append((item['t'], item['msg']))
        return self.items


def follow(device, commands, teleop, timeout_s=30.0):
    """Press button 3 until the robot host reports following and commands carry joint 6."""
    deadline = time.monotonic() + timeout_s
    while True:
        state = teleop.update()[-1][1] if teleop.update() else None
        if state and state['state'] == interface.FOLLOWING:
            with device.lock:
                angle = device.angles[6]
            items = commands.update()
            if items and abs(items[-1][1]['command'][6] - angle) < 1e-6:
                return None
        elif time.monotonic() < deadline:
            with device.lock:
                device.button = interface.BUTTON_RIGHT
            time.sleep(0.3)
            with device.lock:
                device.button = 0
        if time.monotonic() > deadline:
            return state['detail'] if state else 'no teleop_state'
        time.sleep(0.3)


def overspeeds(items):
    """Count consecutive commands that move a joint faster than its velocity limit."""
    count = 0
    for (t0, a), (t1, b) in zip(items, items[1:]):
        dt = max(t1 - t0, 0.0) + RECEPTION_JITTER_S
        if any(abs(x - y) > lim.velocity * dt + 1e-6
               for x, y, lim in zip(a['command'], b['command'], LIMITS)):
            count += 1
    return count


def measure(device, commands, teleop, samples, delay_s):
    """Make samples moves of joint 6; return (latencies, moves that never arrived, arm_R
    faults: after each, button 3 is pressed again to follow)."""
    latencies, missed, faults = [], 0, 0
    with device.lock:
        angle = device.angles[6]
    for i in range(samples):
        time.sleep(random.uniform(0.0, 1.0 / COMM_RATE_HZ) + 0.03)
        angle += STEP_RAD if i % 2 == 0 else -STEP_RAD
        start = len(commands.update())
        moved_wall = time.time()
        device.move(angle)
        deadline = time.monotonic() + 2.0 + 2 * delay_s
        hit = None
        while hit is None and time.monotonic() < deadline:
            time.sleep(0.005)
            for t, msg in commands.update()[start:]:
                if abs(msg['command'][6] - angle) < 1e-6:
                    hit = t
                    break
        if hit is not None:
            latencies.append(hit - moved_wall)
            continue
        missed += 1
        items = teleop.update()
        if items and items[-1][1]['state'] != interface.FOLLOWING:
            faults += 1
            why = follow(device, commands, teleop)
            if why is not None:
                raise RuntimeError('arm_R does not follow again: %s' % why)
            with device.lock:
                angle = device.angles[6]
    return latencies, missed, faults


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--samples', type=int, default=150, help='moves per delay')
    parser.add_argument('--delays', default='0,10,50,100', help='one-way delays (ms)')
    parser.add_argument('--jitter', type=float, default=0.1, help='jitter as a share of delay')
    options = parser.parse_args()
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit('bench_remote: terminated'))
    work = pathlib.Path(os.environ.get('TMPDIR', '/tmp')) / ('bench_remote_%d' % os.getpid())
    work.mkdir(parents=True)
    with RosBed(work) as rb:
        rb.roscore()
        link = str(work / 'puppet_R')
        device = bench_teleop.Device(link, COMM_RATE_HZ)
        try:
            run(rb, device, link, options)
        finally:
            device.close()
    print('logs: %s' % work)


def run(rb, device, link, options):
    common = ('run_side_L:=false', 'comm_rate:=%g' % COMM_RATE_HZ)
    rb.roslaunch('robot', 'robot.launch', 'gripper_calibrated:=true', *common)
    rb.roslaunch('operator', 'operator.launch', 'sim_puppet:=false', 'port_R:=%s' % link,
                 'gui:=false', 'rviz:=false', 'record_sides:=R', *common)
    node = str(HELPERS / 'ros_node.py')
    commands = Listener(rb.python('robot', str(HELPERS / 'command_stamps.py'),
                                  interface.limb_topic('right', 'joint_command')))
    teleop = Listener(rb.python('robot', node, 'listen', '%s/%s' % (
        interface.puppet_ns('R'), interface.TELEOP_STATE), 'robopuppet_msgs/TeleopState'))
    time.sleep(8.0)   # nodes up, settings loaded, Baxter enabled
    print('Hand movement (operator host) -> JointCommand (robot host), comm_rate %g Hz, '
          '%d%% jitter' % (COMM_RATE_HZ, round(100 * options.jitter)))
    print('%8s %7s %8s %8s %9s %9s %7s %10s' % ('delay ms', 'samples', 'p50 ms', 'p99 ms',
                                               'added p50', 'added p99', 'target',
                                               'overspeed'))
    target_ms = 1000.0 / COMM_RATE_HZ + 3.0
    for delay_ms in [float(d) for d in options.delays.split(',')]:
        print('running %g ms ...' % delay_ms, file=sys.stderr, flush=True)
        rb.bed.set(delay_ms=delay_ms, jitter_ms=delay_ms * options.jitter, loss=0)
        time.sleep(6.0)   # the clock estimate's window (5 s) holds this delay's round trips
        first = len(commands.update())
        why = follow(device, commands, teleop)
        if why is not None:
            print('%8g  never followed: %s' % (delay_ms, why), flush=True)
            continue
        latencies, missed, faults = measure(device, commands, teleop, options.samples,
                                            delay_ms / 1000.0)
        over = overspeeds(commands.update()[first:])
        if not latencies:
            print('%8g  no move arrived (%d missed)' % (delay_ms, missed), flush=True)
            continue
        added = [lat - delay_ms / 1000.0 for lat in latencies]
        print('%8g %7d %8.1f %8.1f %9.1f %9.1f %7.1f %10d%s' % (
            delay_ms, len(latencies), 1000 * statistics.median(latencies),
            1000 * percentile(latencies, 0.99), 1000 * statistics.median(added),
            1000 * percentile(added, 0.99), target_ms, over,
            '  (%d moves never arrived, %d arm_R faults)' % (missed, faults) if missed else ''),
            flush=True)


if __name__ == '__main__':
    main()
