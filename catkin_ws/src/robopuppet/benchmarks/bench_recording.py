#!/usr/bin/python3
"""Benchmark: does the recorder keep every message of both arms at 100 Hz, and how big is it?

Usage: benchmarks/bench_recording.py [--minutes M]   (after `. tools/env.sh`; default 0.25 min;
starts its own roscore and recorder with ~sides LR)

This process publishes synthetic traffic at 100 Hz on every recorded topic of both puppet arms
and Baxter's (joint_states, gripper_0..3, user_btn, opmode, joint_command, gripper command and
state, /robot/joint_states, /diagnostics), records one episode through /puppet/record, and
prints messages written vs published (in all, and of the topic that lost most), MB per minute
and the recorder's CPU.
The other half of the issue 10 benchmark, the hand->JointCommand latency that recording adds, is
measured by bench_teleop.py --record (the real stack and recorder on a played puppet).
"""
import argparse
import os
import subprocess
import sys
import time

import psutil
import rosbag
import rospy
from baxter_core_msgs.msg import EndEffectorCommand, EndEffectorState, JointCommand
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, String, UInt8

from bench_support import private_roscore
from robopuppet.episodes import recording
from robopuppet_msgs.srv import Record

RATE_HZ = 100.0
NODES = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'nodes')
TYPES = {'joint_states': lambda: JointState(name=['joint_%d' % j for j in range(7)],
                                            position=[0.1] * 7, effort=[0.0] * 7),
         'user_btn': lambda: UInt8(0), 'opmode': lambda: String('limp'),
         'joint_command': lambda: JointCommand(mode=1, command=[0.2] * 7,
                                               names=['right_s0'] * 7),
         'command': EndEffectorCommand, 'state': EndEffectorState,
         'diagnostics': lambda: DiagnosticArray(status=[DiagnosticStatus(name='x')] * 3)}


def message_for(topic):
    """Return a plausible message for a recorded topic (Float32 for the grippers)."""
    last = topic.rsplit('/', 1)[-1]
    if last == 'joint_states' and topic.startswith('/robot'):
        return JointState(name=['j%d' % j for j in range(17)], position=[0.0] * 17,
                          velocity=[0.0] * 17, effort=[0.0] * 17)
    return TYPES.get(last, lambda: Float32(0.5))()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--minutes', type=float, default=0.25)
    args = parser.parse_args()
    with private_roscore('bench_recording_') as work:
        recorder = subprocess.Popen([sys.executable, os.path.join(NODES, 'recorder'),
                                     '__name:=recorder', '_sides:=LR',
                                     '_episodes_dir:=' + os.path.join(work, 'episodes')])
        try:
            run(args.minutes, psutil.Process(recorder.pid))
        finally:
            recorder.terminate()
            recorder.wait(10)


def run(minutes, recorder):
    rospy.init_node('bench_recording')
    topics = [t for t in recording.recorded_topics(('L', 'R'))
              if not t.endswith(('teleop_state', 'stored_settings'))]
    pubs = {t: (rospy.Publisher(t, type(message_for(t)), queue_size=100), message_for(t))
            for t in topics}
    record = rospy.ServiceProxy(recording.RECORD_SERVICE, Record)
    record.wait_for_service(20)
    deadline = time.monotonic() + 10
    while any(p.get_num_connections() == 0 for p, _ in pubs.values()):
        if time.monotonic() > deadline:
            raise RuntimeError('the recorder did not subscribe to every topic')
        time.sleep(0.1)
    answer = record(True, 'benchmark')
    published = dict.fromkeys(topics, 0)
    recorder.cpu_percent()
    start = time.monotonic()
    tick = start
    while time.monotonic() - start < minutes * 60:
        for topic, (pub, msg) in pubs.items():
            pub.publish(msg)
            published[topic] += 1
        tick += 1.0 / RATE_HZ
        time.sleep(max(0.0, tick - time.monotonic()))
    time.sleep(0.5)  # let the last messages arrive
    cpu = recorder.cpu_percent()
    record(False, '')
    with rosbag.Bag(answer.episode) as bag:
        info = bag.get_type_and_topic_info().topics
    written = {t: info[t].message_count if t in info else 0 for t in topics}
    size_mb = os.path.getsize(answer.episode) / 1e6
    print('recorded %.2f min of %d topics at %.0f Hz (sides LR)' % (minutes, len(topics), RATE_HZ))
    print('messages written / published: %d / %d (%.3f %%), worst topic %s: %d / %d' % (
        sum(written.values()), sum(published.values()),
        100.0 * sum(written.values()) / sum(published.values()),
        *min(((t, written[t], published[t]) for t in topics), key=lambda x: x[1] / x[2])))
    print('bag size: %.1f MB, %.1f MB per minute' % (size_mb, size_mb / minutes))
    print('recorder CPU: %.0f %% of one core' % cpu)


if __name__ == '__main__':
    main()
