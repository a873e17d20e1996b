#!/usr/bin/python3
"""Benchmark: the recorder idle and recording both arms at 100 Hz and three cameras.

Usage: benchmarks/bench_recording.py [--minutes M] [--episodes N] [--idle S] [--cameras NAMES]
(after `. tools/env.sh`; defaults 0.25 min, 3 episodes, 20 s, the simulated cameras; starts its
own roscore and recorder with ~sides LR)

This process publishes synthetic traffic at 100 Hz on every recorded topic of both puppet arms
and Baxter's (joint_states, gripper_0..3, user_btn, opmode, joint_command, gripper command and
state, /robot/joint_states, /diagnostics) and, at 15 Hz, 40 kB JPEG-sized CompressedImages on
each camera's image/compressed. It prints the recorder's CPU while idle (IDLE s, from
/proc/<pid>/stat), then records N episodes through /puppet/record and prints how long after the
start each topic's first message was written, messages written vs published from then on, MB
per minute and the recorder's CPU while recording.
The other half of the recording benchmark, the hand->JointCommand latency that recording adds, is
measured by bench_teleop.py --record (the real stack and recorder on a played puppet).
"""
import argparse
import bisect
import os
import statistics
import subprocess
import sys
import time

import rosbag
import rospy
import yaml
from baxter_core_msgs.msg import EndEffectorCommand, EndEffectorState, JointCommand
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import CompressedImage, JointState
from std_msgs.msg import Float32, String, UInt8

from bench_support import private_roscore
from robopuppet import interface
from robopuppet.episodes import recording
from robopuppet_msgs.srv import Record

RATE_HZ = 100.0
CAMERA_RATE_HZ = 15.0
JPEG_BYTES = 40000          # a 640x480 JPEG of quality 80 is 30-60 kB
NODES = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'nodes')
TYPES = {'joint_states': lambda: JointState(name=['joint_%d' % j for j in range(7)],
                                            position=[0.1] * 7, effort=[0.0] * 7),
         'user_btn': lambda: UInt8(0), 'opmode': lambda: String('limp'),
         'joint_command': lambda: JointCommand(mode=1, command=[0.2] * 7,
                                               names=['right_s0'] * 7),
         'command': EndEffectorCommand, 'state': EndEffectorState,
         'diagnostics': lambda: DiagnosticArray(status=[DiagnosticStatus(name='x')] * 3),
         'compressed': lambda: CompressedImage(format='bgr8; jpeg compressed bgr8',
                                               data=os.urandom(JPEG_BYTES))}


def message_for(topic):
    """Return a plausible message for a recorded topic (Float32 for the grippers)."""
    last = topic.rsplit('/', 1)[-1]
    if last == 'joint_states' and topic.startswith('/robot'):
        return JointState(name=['j%d' % j for j in range(17)], position=[0.0] * 17,
                          velocity=[0.0] * 17, effort=[0.0] * 17)
    return TYPES.get(last, lambda: Float32(0.5))()


def cpu_s(pid):
    """Return the CPU time (s, user + system) a process has used, from /proc/<pid>/stat."""
    with open('/proc/%d/stat' % pid) as stat:
        fields = stat.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


class Traffic:
    """Publishers of every recorded topic; publish() sends what is due and logs the times."""

    def __init__(self, cameras):
        topics = [t for t in recording.recorded_topics(('L', 'R'), cameras)
                  if not t.endswith(('teleop_state', 'stored_settings'))]
        self.pubs = {t: (rospy.Publisher(t, type(message_for(t)), queue_size=100),
                         message_for(t)) for t in topics}
        self.period_s = {t: 1.0 / (CAMERA_RATE_HZ if t.endswith('compressed') else RATE_HZ)
                         for t in topics}
        self.sent = {t: [] for t in topics}   # ROS times of publication
        self._next = dict.fromkeys(topics, 0.0)

    def run_for(self, seconds):
        """Publish every topic at its rate for seconds."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            now = time.monotonic()
            for topic, (pub, msg) in self.pubs.items():
                if now >= self._next[topic]:
                    self.sent[topic].append(rospy.get_time())
                    pub.publish(msg)
                    self._next[topic] = max(self._next[topic] + self.period_s[topic], now)
            time.sleep(max(0.0, min(self._next.values()) - time.monotonic()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--minutes', type=float, default=0.25, help='of each episode')
    parser.add_argument('--episodes', type=int, default=3)
    parser.add_argument('--idle', type=float, default=20.0,
                        help='s of traffic with the recorder idle, for its idle CPU')
    parser.add_argument('--cameras', default=','.join(interface.SIM_CAMERAS),
                        help="camera names, comma separated ('' for none)")
    args = parser.parse_args()
    cameras = recording.parse_cameras(args.cameras)
    with private_roscore('bench_recording_') as work:
        recorder = subprocess.Popen([sys.executable, os.path.join(NODES, 'recorder'),
                                     '__name:=recorder', '_sides:=LR',
                                     '_cameras:=[%s]' % ','.join(cameras),
                                     '_episodes_dir:=' + os.path.join(work, 'episodes')])
        try:
            run(args, cameras, recorder.pid)
        finally:
            recorder.terminate()
            recorder.wait(10)


def run(args, cameras, pid):
    rospy.init_node('bench_recording')
    traffic = Traffic(cameras)
    record = rospy.ServiceProxy(interface.RECORD_SERVICE, Record)
    record.wait_for_service(20)
    traffic.run_for(3.0)  # connections made (to a recorder that subscribes while idle), settled
    before = cpu_s(pid)
    traffic.run_for(args.idle)
    idle_cpu = 100.0 * (cpu_s(pid) - before) / args.idle
    print('recorder idle: %.1f %% of one core over %.0f s (%d topics published, %s cameras)' % (
        idle_cpu, args.idle, len(traffic.pubs), len(cameras)), flush=True)
    episodes, recording_s, recording_cpu_s = [], 0.0, 0.0
    for _ in range(args.episodes):
        before, started = cpu_s(pid), time.monotonic()
        answer = record(True, 'benchmark', '')
        traffic.run_for(args.minutes * 60)
        stop_s = rospy.get_time()
        record(False, '', '')
        recording_cpu_s += cpu_s(pid) - before
        recording_s += time.monotonic() - started
        episodes.append((answer.episode, stop_s))
        traffic.run_for(1.0)
    report(traffic, episodes, idle_cpu, 100.0 * recording_cpu_s / recording_s)


def report(traffic, episodes, idle_cpu, recording_cpu):
    """Print the start delays, messages written vs published, size and CPU of the episodes."""
    delays, written, published, missing, size_mb, minutes = [], 0, 0, set(), 0.0, 0.0
    for path, stop_s in episodes:
        delays.append({})  # topic: ms from the start to its first message
        start_s = yaml.safe_load(open(path[:-len(recording.BAG)] + recording.META))['start_stamp']
        stamps = {}
        with rosbag.Bag(path) as bag:
            for topic, _, stamp in bag.read_messages():
                stamps.setdefault(topic, []).append(stamp.to_sec())
            minutes += (bag.get_end_time() - bag.get_start_time()) / 60.0
        size_mb += os.path.getsize(path) / 1e6
        end_s = stop_s - 0.1  # what was published until shortly before the stop
        for topic, sent in traffic.sent.items():
            if topic not in stamps:
                missing.add(topic)
                continue
            first_s = stamps[topic][0]
            delays[-1][topic] = 1000 * (first_s - start_s)
            written += bisect.bisect_right(stamps[topic], end_s)
            published += (bisect.bisect_right(sent, end_s)
                          - bisect.bisect_left(sent, first_s - traffic.period_s[topic] / 2))
    every = [d for episode in delays for d in episode.values()]
    print('%d episodes, %.2f min, %d topics (sides LR at %.0f Hz, cameras at %.0f Hz)' % (
        len(episodes), minutes, len(traffic.pubs), RATE_HZ, CAMERA_RATE_HZ))
    print('first message written after the start: median %.0f ms, max %.0f ms over topics and '
          'episodes; per episode the slowest topic: %s' % (
              statistics.median(every), max(every), ', '.join(
                  '%.0f ms %s' % max((d, t) for t, d in episode.items()) for episode in delays)))
    print("messages written / published from each topic's first one: %d / %d (%.2f %%)%s" % (
        written, published, 100.0 * written / max(published, 1),
        '; never written: ' + ', '.join(sorted(missing)) if missing else ''))
    print('bag size: %.1f MB, %.1f MB per minute' % (size_mb, size_mb / max(minutes, 1e-9)))
    print('recorder CPU: idle %.1f %%, recording %.0f %% of one core' % (idle_cpu, recording_cpu))


if __name__ == '__main__':
    main()
