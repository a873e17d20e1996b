#!/usr/bin/python3
"""Benchmark: latency from a hand movement on the operator host to the JointCommand carrying it
on the robot host, across the network test bed (docs/remote.md), at several one-way delays.

Usage: benchmarks/bench_remote.py [--samples N] [--delays 0,10,50,100] [--jitter 0.1]
    [--tcp-cc reno|bbr] [--sysctl KEY=VALUE ...] [--one-host] [--rt-path] [--robot-args ARGS]
    [--operator-args ARGS]
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
with jitter the effective delay rises towards delay + jitter). Target: p99 beyond the delay
<= one state period + 3 ms (13 ms at 100 Hz), held to "added vs bed" below. A move lost to an arm_R fault is counted, and button 3 pressed
again.

Also counted: consecutive JointCommands that move a joint faster than its velocity limit
(over their arrival interval plus 5 ms of reception jitter); target zero.

"added vs bed" is the honest figure beside "added": the latency minus the delay the bed
actually gave the packet that carried the move (the forwarder traces its packets: see
tools/netbed/forwarder.py, trace and find), instead of the nominal delay. With jitter and
in-order release that delay is up to delay + jitter, which "added" wrongly counts as ours.

Per hop (a second table, p50/p99 in ms, one row per delay), for each move: a listener on each
host subscribes serial_R's joint_states (tcp_nodelay, like arm_R); the operator host's finds the
first sample carrying the new angle, whose header stamp is serial_R's publish time, and the
forwarder finds the packets to the robot host that hold that stamp's bytes (arm_R's copy told
from the robot listener's by its TCP port, `ss -tnp`). Hops: "sample" (the change to the stamp:
the wait for the device's next state set, up to one period, the pty and serial_R's parsing),
"local" (the stamp to the operator host's listener: a subscriber beside serial_R), "to bed"
(the stamp to the forwarder reading arm_R's packet: serial_R's publishing and the operator
host's TCP), "bed" (the delay the forwarder gave it), "bed late" (its write after that delay's
end: the forwarder's scheduling), "robot rx" (the listener's copy written to its arrival at the
robot host's listener: the robot host's TCP and rospy's delivery), "arm_R+" (arm_R's copy
written to the JointCommand's arrival at the command listener: arm_R's reception, step and
publishing, and the command's delivery; with --one-host, from the stamp). The listeners cost
serial_R two more subscriber connections; n counts the moves traced through the bed.

TCP: the bed's hosts use reno (netbed.bed.HOST_TCP_CC, which says why: not this machine's
bbr); --tcp-cc sets another on both before anything starts, --sysctl more (e.g.
net.ipv4.tcp_slow_start_after_idle=0). With bbr, each connection's ProbeRTT (every 10 s
without a lower round trip) clamps it to 4 packets in flight for about 200 ms plus a round trip:
at 100 ms one way, samples waited in serial_R's socket ("to bed" p99 55-63 ms, against 2-7 ms
with reno); docs/remote.md.

--one-host runs operator.launch in the robot host's namespace too (no bed on the path, delay 0
only): the same nodes and load, to tell the bed from CPU and ROS. --robot-args and
--operator-args add roslaunch arguments (e.g. --robot-args obstacles_file:=/dev/null).
--rt-path gives the processes on the path real-time priority (SCHED_FIFO 5, below the bed's
forwarder): this one (the device thread), serial_R, arm_R and the listeners, all their threads.
The other processes on the machine then cannot delay them: a stand-in for two hosts with cores
of their own, when the machine is busy with other work. Not a deployment setting; the bench
drops them back to normal scheduling before it stops anything (see run).
"busy %" is the whole machine's CPU busy share while a delay's moves ran (other work included):
the tails follow it.
"""
import argparse
import collections
import os
import pathlib
import random
import signal
import statistics
import subprocess
import sys
import time

import psutil
from robopuppet import baxter_description, interface

import bench_teleop
from bench_support import percentile

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / 'tests' / 'network'))
from netbed_testing import HELPERS, RosBed  # noqa: E402
from netbed.bed import HOST_TCP_CC  # noqa: E402
from remote_trace import (HOPS, RT_PATH_PRIORITY, TRACE_KEEP_S, Listener,  # noqa: E402
                          Tracer, prioritise, schedule)

COMM_RATE_HZ = 100.0
STEP_RAD = 0.01
RECEPTION_JITTER_S = 0.005
LIMITS = baxter_description.arm_limits('right')


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


def measure(device, commands, teleop, tracer, samples, delay_s):
    """Make samples moves of joint 6; return (latencies, latencies less the bed's delay of
    each move's packet, {hop: [s]}, moves that never arrived, arm_R faults: after each, button
    3 is pressed again to follow)."""
    latencies, net_latencies, missed, faults = [], [], 0, 0
    per_hop = collections.defaultdict(list)
    with device.lock:
        angle = device.angles[6]
    for i in range(samples):
        time.sleep(random.uniform(0.0, 1.0 / COMM_RATE_HZ) + 0.03)
        angle += STEP_RAD if i % 2 == 0 else -STEP_RAD
        start, marks = len(commands.update()), tracer.marks()
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
            times, bed_delay = tracer.hops(marks, angle, moved_wall, hit)
            for name, value in times.items():
                if value is not None:
                    per_hop[name].append(value)
            if tracer.bed is None:
                net_latencies.append(hit - moved_wall)
            elif bed_delay is not None:
                net_latencies.append(hit - moved_wall - bed_delay)
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
    return latencies, net_latencies, per_hop, missed, faults


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--samples', type=int, default=150, help='moves per delay')
    parser.add_argument('--delays', default='0,10,50,100', help='one-way delays (ms)')
    parser.add_argument('--jitter', type=float, default=0.1, help='jitter as a share of delay')
    parser.add_argument('--one-host', action='store_true',
                        help='run the operator host\'s nodes on the robot host (no bed; delay 0)')
    parser.add_argument('--rt-path', action='store_true',
                        help='real-time priority for the processes on the path (module docstring)')
    parser.add_argument('--robot-args', default='', help='more robot.launch arguments')
    parser.add_argument('--operator-args', default='', help='more operator.launch arguments')
    parser.add_argument('--tcp-cc', default=HOST_TCP_CC,
                        help="TCP congestion control of both hosts (default the bed's, %s; "
                             "module docstring)" % HOST_TCP_CC)
    parser.add_argument('--sysctl', action='append', default=[],
                        help='KEY=VALUE set on both hosts before anything starts')
    options = parser.parse_args()
    if options.one_host:
        options.delays = '0'
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit('bench_remote: terminated'))
    work = pathlib.Path(os.environ.get('TMPDIR', '/tmp')) / ('bench_remote_%d' % os.getpid())
    work.mkdir(parents=True)
    with RosBed(work) as rb:
        for host in ('operator', 'robot'):
            for setting in ['net.ipv4.tcp_congestion_control=' + options.tcp_cc] + options.sysctl:
                subprocess.run(rb.bed.command(host, ['sysctl', '-q', '-w', setting]), check=True)
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
    operator = 'robot' if options.one_host else 'operator'
    rb.roslaunch('robot', 'robot.launch', 'gripper_calibrated:=true', *common,
                 *options.robot_args.split())
    rb.roslaunch(operator, 'operator.launch', 'sim_puppet:=false', 'port_R:=%s' % link,
                 'gui:=false', 'rviz:=false', 'record_sides:=R', *common,
                 *options.operator_args.split())
    node = str(HELPERS / 'ros_node.py')
    commands = Listener(rb.python('robot', str(HELPERS / 'command_stamps.py'),
                                  interface.limb_topic('right', 'joint_command')))
    teleop = Listener(rb.python('robot', node, 'listen', '%s/%s' % (
        interface.puppet_ns('R'), interface.TELEOP_STATE), 'robopuppet_msgs/TeleopState'))
    time.sleep(8.0)   # nodes up, settings loaded, Baxter enabled
    tracer = Tracer(rb, operator, None if options.one_host else rb.bed)
    time.sleep(2.0)   # the listeners connected
    path = prioritise(rb.procs) if options.rt_path else []
    if path:
        print('real-time priority (SCHED_FIFO %d) for %s' % (RT_PATH_PRIORITY, ', '.join(
            ' '.join(process.cmdline()[1:3])[-40:] for process in path)))
    try:
        measure_delays(rb, device, commands, teleop, tracer, operator, options)
    finally:
        # Never tear down at real-time priority: a process that spins as it shuts down (the
        # listeners did, once, for 12 minutes) starves the whole machine.
        schedule(path, os.SCHED_OTHER, 0)


def measure_delays(rb, device, commands, teleop, tracer, operator, options):
    """Measure at each delay of options.delays; print the tables."""
    if not options.one_host:
        rb.bed.request({'cmd': 'trace', 'keep_s': TRACE_KEEP_S})
    print('Hand movement (%s host) -> JointCommand (robot host), comm_rate %g Hz, '
          '%d%% jitter, TCP %s%s' % (operator, COMM_RATE_HZ, round(100 * options.jitter),
                                    options.tcp_cc, ''.join(' ' + x for x in options.sysctl)))
    print('%8s %7s %8s %8s %9s %9s %9s %9s %7s %10s %6s' % (
        'delay ms', 'samples', 'p50 ms', 'p99 ms', 'added p50', 'added p99', 'vs bed p50',
        'vs bed p99', 'target', 'overspeed', 'busy %'))
    target_ms = 1000.0 / COMM_RATE_HZ + 3.0
    hop_rows = []
    for delay_ms in [float(d) for d in options.delays.split(',')]:
        print('running %g ms ...' % delay_ms, file=sys.stderr, flush=True)
        rb.bed.set(delay_ms=delay_ms, jitter_ms=delay_ms * options.jitter, loss=0)
        time.sleep(6.0)   # the clock estimate's window (5 s) holds this delay's round trips
        first = len(commands.update())
        why = follow(device, commands, teleop)
        if why is not None:
            print('%8g  never followed: %s' % (delay_ms, why), flush=True)
            continue
        psutil.cpu_percent()
        latencies, net, per_hop, missed, faults = measure(
            device, commands, teleop, tracer, options.samples, delay_ms / 1000.0)
        over = overspeeds(commands.update()[first:])
        if not latencies:
            print('%8g  no move arrived (%d missed)' % (delay_ms, missed), flush=True)
            continue
        busy = psutil.cpu_percent()
        added = [lat - delay_ms / 1000.0 for lat in latencies]
        print('%8g %7d %8.1f %8.1f %9.1f %9.1f %9s %9s %7.1f %10d %6.0f%s' % (
            delay_ms, len(latencies), 1000 * statistics.median(latencies),
            1000 * percentile(latencies, 0.99), 1000 * statistics.median(added),
            1000 * percentile(added, 0.99), *p50_p99(net, '%9.1f'), target_ms, over, busy,
            '  (%d moves never arrived, %d arm_R faults)' % (missed, faults) if missed else ''),
            flush=True)
        hop_rows.append((delay_ms, per_hop))
    print('Per hop, p50/p99 ms (module docstring)')
    print('%8s %5s' % ('delay ms', 'n') + ''.join('%13s' % name for name in HOPS))
    for delay_ms, per_hop in hop_rows:
        print('%8g %5d' % (delay_ms, len(per_hop['bed'])) + ''.join(
            '%13s' % '/'.join(p50_p99(per_hop[name], '%.1f')) for name in HOPS), flush=True)


def p50_p99(values, form):
    """Return (p50, p99) of values (s) formatted in ms, or ('-', '-') when there are none."""
    if not values:
        return '-', '-'
    return form % (1000 * statistics.median(values)), form % (1000 * percentile(values, 0.99))


if __name__ == '__main__':
    main()
