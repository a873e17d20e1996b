#!/usr/bin/python3
"""Benchmark the serial path: decoder throughput, and pty-to-subscriber latency of serial_X.

Usage (from the repository, after tools/setup.sh):
    . tools/env.sh && catkin_ws/src/robopuppet/benchmarks/bench_serial.py [--seconds 5]

Starts its own roscore on a free port, publishes active_settings with default settings (as
config_X does), plays the puppet's microcontroller on a pseudo-terminal and runs the real serial
node against it. For each state rate it writes state sets (seven joint states, four grippers,
buttons); the angles of a set's joints 0 and 1 carry its sequence number (plausible angles,
exact in float32). The latency of a set runs from the moment the write holding
its last joint state frame returns to the moment its joint_states message reaches a subscriber
in this process. Prints figures; passes or fails nothing.
"""
import argparse
import os
import subprocess
import sys
import threading
import time
import tty

import psutil

from robopuppet import interface, settings
from robopuppet.protocol import codec

from bench_support import percentile, private_roscore

STATE_RATES_HZ = (10, 100, 500)


def bench_decoder(total_frames=300000):
    """Print decoder throughput for state-set traffic fed in chunks of several sizes."""
    state_set = [codec.JointState(j, 0, 0.1 * j, -0.5) for j in settings.JOINTS]
    state_set += [codec.Gripper(g, 0.5) for g in range(interface.NUM_GRIPPERS)] + [codec.Buttons(0)]
    one_set = b''.join(codec.encode(m) for m in state_set)
    stream = one_set * (total_frames // len(state_set))
    frames = len(state_set) * (total_frames // len(state_set))
    for chunk in (4096, 256, 13):
        decoder = codec.Decoder()
        start = time.perf_counter()
        for i in range(0, len(stream), chunk):
            decoder.feed(stream[i:i + chunk])
        seconds = time.perf_counter() - start
        assert decoder.frames == frames
        print('decoder, %5d-byte chunks: %9.0f frames/s  (%d frames, %.2f MB/s)'
              % (chunk, frames / seconds, frames, len(stream) / seconds / 1e6))


def seq_angles(seq):
    """Return the angles (rad) of joints 0 and 1 that carry a sequence number below 65536."""
    return (seq % 256) / 128.0 - 1.0, (seq // 256) / 128.0 - 1.0


def seq_of(angles_rad):
    """Return the sequence number that seq_angles made into these angles."""
    return int(round((angles_rad[0] + 1.0) * 128)) + 256 * int(round((angles_rad[1] + 1.0) * 128))


class Device:
    """The benchmark's end of the pty: reads host frames, writes timed state sets."""

    def __init__(self):
        self.master, self.slave = os.openpty()
        tty.setraw(self.slave)
        self.path = os.ttyname(self.slave)
        self.decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        self.received = []
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        while True:
            try:
                data = os.read(self.master, 4096)
            except OSError:
                return
            self.received.extend(self.decoder.feed(data))

    def write_set(self, seq):
        """Write one state set; return the perf_counter time its last joint frame was written."""
        angles = seq_angles(seq) + (0.25,) * (settings.NUM_JOINTS - 2)
        joints = b''.join(codec.encode(codec.JointState(j, 0, angles[j], 1.0))
                          for j in settings.JOINTS)
        os.write(self.master, joints)
        written = time.perf_counter()
        rest = [codec.Gripper(g, 0.5) for g in range(interface.NUM_GRIPPERS)] + [codec.Buttons(0)]
        heartbeat = codec.encode(codec.Heartbeat()) if seq % 10 == 0 else b''
        os.write(self.master, heartbeat + b''.join(codec.encode(m) for m in rest))
        return written


def bench_latency(seconds):
    """Run roscore and serial_L, publish active_settings; print latency, loss and CPU per rate."""
    import rospy
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Float32
    from robopuppet_msgs.msg import ArmSettings, JointSettings

    device = Device()
    serial_node = None
    with private_roscore('bench_serial_'):
        try:
            rospy.init_node('bench_serial', disable_signals=True)
            ns = interface.puppet_ns('L')
            stored = rospy.Publisher('%s/%s' % (ns, interface.ACTIVE_SETTINGS), ArmSettings,
                                     queue_size=1, latch=True)
            stored.publish(ArmSettings(joints=[JointSettings(joint=j, **settings.DEFAULTS)
                                               for j in settings.JOINTS]))
            received = {}
            angle_count = [0]

            def on_states(msg):
                received[seq_of(msg.position)] = time.perf_counter()

            def on_angle(msg):
                angle_count[0] += 1
            rospy.Subscriber('%s/%s' % (ns, interface.JOINT_STATES), JointState, on_states,
                             queue_size=5000, tcp_nodelay=True)
            rospy.Subscriber(interface.joint_topic('L', 0, 'angle'), Float32, on_angle,
                             queue_size=5000)
            serial_node = subprocess.Popen(
                ['rosrun', 'robopuppet', 'serial_interface', '__name:=serial_L', '_arm_side:=L',
                 '_port_name:=%s' % device.path], stdout=subprocess.DEVNULL)
            deadline = time.monotonic() + 15.0
            while len(device.received) < 85 and time.monotonic() < deadline:
                time.sleep(0.05)
            print('serial node loaded %d settings frames + opmode into the device'
                  % sum(isinstance(m, codec.JointConfig) for m in device.received))
            process = psutil.Process(serial_node.pid)  # rosrun execs the node's interpreter
            seq = 1
            time.sleep(1.0)
            for rate in STATE_RATES_HZ:
                seq = _run_rate(device, rate, seconds, seq, received, angle_count, process)
        finally:
            if serial_node is not None:
                serial_node.terminate()
                serial_node.wait(10)


def _run_rate(device, rate, seconds, seq, received, angle_count, process):
    sent = {}
    period = 1.0 / rate
    angles_before = angle_count[0]
    cpu_before = sum(process.cpu_times()[:2])
    start = time.perf_counter()
    next_due = start
    seconds = max(seconds, 200.0 / rate)  # at least 200 samples for the p99
    while time.perf_counter() - start < seconds:
        sent[seq] = device.write_set(seq)
        seq += 1
        next_due += period
        delay = next_due - time.perf_counter()
        if delay > 0:
            time.sleep(delay)
    wall = time.perf_counter() - start
    cpu = sum(process.cpu_times()[:2]) - cpu_before
    time.sleep(0.5)
    latencies = sorted((received[s] - t) * 1000.0 for s, t in sent.items() if s in received)
    lost = len(sent) - len(latencies)

    print('%4d Hz: %5d sets, %d lost; latency p50 %.2f ms, p99 %.2f ms, max %.2f ms; '
          'joint_0/angle %.0f Hz; serial node CPU %.1f%% of one core'
          % (rate, len(sent), lost, percentile(latencies, 0.5), percentile(latencies, 0.99),
             latencies[-1],
             (angle_count[0] - angles_before) / wall, 100.0 * cpu / wall))
    return seq


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--seconds', type=float, default=5.0,
                        help='duration per state rate (at least 200 state sets)')
    args = parser.parse_args()
    bench_decoder()
    bench_latency(args.seconds)
    return 0


if __name__ == '__main__':
    sys.exit(main())
