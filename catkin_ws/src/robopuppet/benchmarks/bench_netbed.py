#!/usr/bin/python3
"""Benchmark: does the two-host test bed (tools/netbed) give the delay and loss it is told, and
can its forwarder carry RoboPuppet's ROS traffic with little CPU?

Usage (as root, after `. tools/env.sh`):
    catkin_ws/src/robopuppet/benchmarks/bench_netbed.py [--seconds S]   (default 10 per ROS run)

1. Raw link: stamped UDP packets (1000/s, and 5000/s for headroom) operator -> robot, for
   several settings: achieved one-way delay p50/p99 vs set, loss vs set, forwarder CPU.
2. ROS traffic across the link, master on the robot host: the operator host
   publishes both puppet arms at 100 Hz (joint_states, gripper_0..3, user_btn per arm), the
   robot host publishes Baxter's /robot/joint_states at 100 Hz; each side subscribes to the
   other's (the joint states with tcp_nodelay, as arm_X and serial_X subscribe). Printed:
   messages received vs sent, one-way latency p50/p99 of the joint states (header stamp to
   callback) vs the delay set, forwarder packets/s and CPU.
Both ends of every measurement run on this machine's one clock.
(`--node operator|robot` is the ROS traffic node this script starts in each namespace.)
"""
import argparse
import json
import os
import socket
import struct
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, '..', 'tests', 'network'))
RATE_HZ = 100.0
ARMS = ('L', 'R')
SO_TIMESTAMPNS = getattr(socket, 'SO_TIMESTAMPNS', 35)


def percentile(values, fraction):
    """Return the nearest-rank percentile of values (fraction 0.99 for p99); nan if empty."""
    ordered = sorted(values)
    if not ordered:
        return float('nan')
    return ordered[min(len(ordered) - 1, max(int(fraction * len(ordered) + 0.999999) - 1, 0))]


def run_node(role, seconds):
    """The ROS traffic of one host: publish its 100 Hz topics, time the other host's."""
    import rospy
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Float32, UInt8
    from robopuppet import interface

    rospy.init_node('bench_%s' % role)
    latencies, received = [], {}

    def on_states(msg, topic):
        latencies.append((time.time() - msg.header.stamp.to_sec()) * 1e3)
        received[topic] = received.get(topic, 0) + 1

    def on_other(_msg, topic):
        received[topic] = received.get(topic, 0) + 1
    pubs = []  # (publisher, make message)
    if role == 'operator':
        names = ['joint_%d' % j for j in range(7)]
        for side in ARMS:
            ns = interface.puppet_ns(side)
            pubs.append((rospy.Publisher('%s/%s' % (ns, interface.JOINT_STATES), JointState,
                                         queue_size=10),
                         lambda: JointState(name=names, position=[0.1] * 7,
                                            effort=[0.0] * 7)))
            for g in range(interface.NUM_GRIPPERS):
                pubs.append((rospy.Publisher(interface.gripper_topic(side, g), Float32,
                                             queue_size=10), lambda: Float32(0.5)))
            pubs.append((rospy.Publisher('%s/%s' % (ns, interface.USER_BUTTON), UInt8,
                                         queue_size=10), lambda: UInt8(0)))
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, on_states,
                         callback_args=interface.ROBOT_JOINT_STATES, queue_size=100,
                         tcp_nodelay=True)
    else:
        names = ['head_pan', 'torso_t0'] + ['%s_%s' % (s, j) for s in ('left', 'right')
                                            for j in ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')]
        names += ['left_gripper', 'right_gripper']
        pubs.append((rospy.Publisher(interface.ROBOT_JOINT_STATES, JointState, queue_size=10),
                     lambda: JointState(name=names, position=[0.0] * len(names),
                                        velocity=[0.0] * len(names), effort=[0.0] * len(names))))
        for side in ARMS:
            ns = interface.puppet_ns(side)
            topic = '%s/%s' % (ns, interface.JOINT_STATES)
            rospy.Subscriber(topic, JointState, on_states, callback_args=topic, queue_size=100,
                             tcp_nodelay=True)
            for g in range(interface.NUM_GRIPPERS):
                rospy.Subscriber(interface.gripper_topic(side, g), Float32, on_other,
                                 callback_args='grippers', queue_size=100)
    print(json.dumps({'ready': True}), flush=True)
    time.sleep(2.0)  # connections across the link
    sent, rate = 0, rospy.Rate(RATE_HZ)
    end = time.monotonic() + seconds
    while time.monotonic() < end and not rospy.is_shutdown():
        for pub, make in pubs:
            msg = make()
            if hasattr(msg, 'header'):
                msg.header.stamp = rospy.Time.now()
            pub.publish(msg)
        sent += 1
        rate.sleep()
    time.sleep(1.0)  # the last messages in flight
    print(json.dumps({'role': role, 'sent_per_topic': sent, 'topics_published': len(pubs),
                      'received': received, 'latency_ms': latencies}), flush=True)


def raw_link(rb, delay_ms, jitter_ms, loss, count=2000, rate_pps=1000):
    """Send stamped UDP operator -> robot; return (delays ms, lost count, forwarder CPU s)."""
    rb.bed.set(delay_ms=delay_ms, jitter_ms=jitter_ms, loss=loss)
    receiver = rb.bed.socket('robot', socket.AF_INET, socket.SOCK_DGRAM)
    receiver.bind((rb.address('robot'), 9700))
    receiver.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
    receiver.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 1 << 22)
    sender = rb.bed.socket('operator', socket.AF_INET, socket.SOCK_DGRAM)
    cpu0 = rb.bed.status()['cpu_s']
    start = time.monotonic()
    for i in range(count):
        sender.sendto(struct.pack('<Id', i, time.time()) + bytes(100), (rb.address('robot'), 9700))
        pause = start + (i + 1) / rate_pps - time.monotonic()
        if pause > 0:
            time.sleep(pause)
    delays = {}
    receiver.settimeout(0.2)
    while True:
        try:
            data, ancillary, _, _ = receiver.recvmsg(256, 64)
        except socket.timeout:
            break
        index, sent_s = struct.unpack('<Id', data[:12])
        for level, kind, value in ancillary:
            if level == socket.SOL_SOCKET and kind == SO_TIMESTAMPNS:
                sec, nsec = struct.unpack('qq', value[:16])
                delays[index] = (sec + nsec * 1e-9 - sent_s) * 1e3
    cpu_s = rb.bed.status()['cpu_s'] - cpu0
    elapsed = time.monotonic() - start
    receiver.close()
    sender.close()
    return list(delays.values()), count - len(delays), cpu_s / elapsed


def ros_traffic(rb, seconds, delay_ms, jitter_ms, loss):
    """Run both hosts' traffic nodes; return their reports and the forwarder's figures."""
    rb.bed.set(delay_ms=delay_ms, jitter_ms=jitter_ms, loss=loss)
    nodes = [rb.python(host, os.path.abspath(__file__), '--node', host, '--seconds', seconds)
             for host in ('robot', 'operator')]
    for node in nodes:
        node.wait_for(lambda p: p.json_lines(), 60, 'the node ready')
    status0 = rb.bed.status()
    t0 = time.monotonic()
    reports = [node.wait_for(lambda p: [x for x in p.json_lines() if 'role' in x], seconds + 60,
                             'its report')[0] for node in nodes]
    status1 = rb.bed.status()
    elapsed = time.monotonic() - t0
    packets = sum(status1['links'][d]['released'] - status0['links'][d]['released']
                  for d in status1['links'])
    return reports, packets / elapsed, (status1['cpu_s'] - status0['cpu_s']) / elapsed


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--seconds', type=float, default=10.0, help='length of a ROS run, s')
    parser.add_argument('--node', choices=('operator', 'robot'), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.node:
        run_node(args.node, args.seconds)
        return 0
    import tempfile
    from netbed_testing import RosBed
    with RosBed(tempfile.mkdtemp(prefix='bench-netbed-')) as rb:
        print('1. raw link, stamped UDP (128 B) operator -> robot, 2 s per row')
        print('   packets/s  set: delay  jitter  loss | got: p50 ms  p99 ms  loss   | '
              'forwarder CPU')
        for rate_pps, delay_ms, jitter_ms, loss in ((1000, 0, 0, 0), (1000, 20, 5, 0.01),
                                                    (1000, 50, 10, 0.05), (5000, 20, 5, 0.0)):
            count = 2 * rate_pps
            delays, lost, cpu = raw_link(rb, delay_ms, jitter_ms, loss, count, rate_pps)
            print('   %9d %11.0f %6.0f  %5.2f | %11.2f %7.2f  %5.3f  | %5.1f %% of a core'
                  % (rate_pps, delay_ms, jitter_ms, loss, percentile(delays, 0.5),
                     percentile(delays, 0.99), lost / count, cpu * 100))
        rb.roscore()
        for delay_ms, jitter_ms, loss in ((0, 0, 0), (20, 5, 0.01)):
            reports, pps, cpu = ros_traffic(rb, args.seconds, delay_ms, jitter_ms, loss)
            print('2. ROS traffic, %.0f s, link set to delay %d ms +- %d ms, loss %.2f'
                  % (args.seconds, delay_ms, jitter_ms, loss))
            for r in reports:
                lat = r['latency_ms']
                print('   %-8s published %d topics x %d messages; received %s; joint states '
                      'one-way p50 %.1f ms p99 %.1f ms' % (
                          r['role'], r['topics_published'], r['sent_per_topic'],
                          json.dumps(r['received'], sort_keys=True), percentile(lat, 0.5),
                          percentile(lat, 0.99)))
            print('   forwarder: %.0f packets/s, CPU %.1f %% of a core' % (pps, cpu * 100))
    return 0


if __name__ == '__main__':
    sys.exit(main())
