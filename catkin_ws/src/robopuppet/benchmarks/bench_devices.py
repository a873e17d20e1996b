#!/usr/bin/python3
"""Benchmark: latency from a study device's input event to the first Baxter command it moves.

Usage: benchmarks/bench_devices.py [--samples N] [--devices keyboard,gamepad,...]
(after `. tools/env.sh`; starts its own roscore)

The Baxter stand-in, config_R and arm_R (comm_rate 10, no zones) run as in main_sim; each device
in turn feeds arm_R's puppet topics: input_device for keyboard, gamepad and spacemouse (evdev
records written to its FIFO, as the simulated participant writes them), marker (feedback
published on its server, as RViz sends it), and for comparison the simulated puppet (serial_R
and puppet_sim_R; the operator's hand moved on its hand topic). While Baxter's right arm
follows and its commands are steady, an event starts a motion (keyboard: joint 6 jogged;
gamepad and SpaceMouse: the tool point forward or back; marker: a pose 1 cm away; puppet: the
hand's joint 6 by 0.05 rad) at a random moment; latency = the first JointCommand on
/robot/limb/right/joint_command that differs from the steady one, minus the moment the event
was written. Then the motion is stopped and the next event waits for steady commands again.
Printed: p50, p95 and max per device.
"""
import argparse
import os
import random
import signal
import sys
import threading
import time

import numpy as np
import rospy
from baxter_core_msgs.msg import JointCommand
from evdev import ecodes as e
from geometry_msgs.msg import Pose
from visualization_msgs.msg import InteractiveMarkerFeedback as Feedback

from robopuppet import baxter_description, interface
from robopuppet.study import input_events
from robopuppet.study.cartesian import CartesianArm
from robopuppet_msgs.msg import LinkPing

from bench_support import percentile, private_roscore, start_process, stop_process

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests',
                                'integration'))
from hand_pose import HAND_POSE  # noqa: E402
from teleop_harness import Baxter, PuppetArm, calibrate  # noqa: E402
from waiting import wait_for  # noqa: E402

DEVICES = ('keyboard', 'gamepad', 'spacemouse', 'marker', 'puppet')
BENT = [0.3, -0.3, 0.0, 1.6, 0.0, 0.3, 0.0]   # room all round the tool point
STEADY_COMMANDS = 10   # commands within STEADY_RAD of each other: the arm is held still
STEADY_RAD, MOVED_RAD = 1e-6, 1e-5
# (start, stop) event pairs of each FIFO device, alternating so the arm stays where it is
MOTIONS = {'keyboard': [((e.EV_KEY, e.KEY_J, 1),), ((e.EV_KEY, e.KEY_J, 0),),
                        ((e.EV_KEY, e.KEY_M, 1),), ((e.EV_KEY, e.KEY_M, 0),)],
           'gamepad': [((e.EV_ABS, e.ABS_RY, -32768),), ((e.EV_ABS, e.ABS_RY, 0),),
                       ((e.EV_ABS, e.ABS_RY, 32767),), ((e.EV_ABS, e.ABS_RY, 0),)],
           'spacemouse': [((e.EV_REL, e.REL_Y, -350),), ((e.EV_REL, e.REL_Y, 0),),
                          ((e.EV_REL, e.REL_Y, 350),), ((e.EV_REL, e.REL_Y, 0),)]}
FOLLOW = {'keyboard': e.KEY_F3, 'gamepad': e.BTN_EAST, 'spacemouse': e.BTN_0}


class Watch:
    """Baxter's right-arm commands and arm_R's state and echoes, with reception times."""

    def __init__(self):
        self.lock, self.commands, self.echoes, self.state = threading.Lock(), [], [], None
        ns = interface.puppet_ns('R') + '/'
        self.puppet = PuppetArm('R')   # teleop_state, joint_states; the simulated hand
        self.baxter = Baxter()
        rospy.Subscriber(interface.limb_topic('right', 'joint_command'), JointCommand,
                         self._on_command, queue_size=1000, tcp_nodelay=True)
        rospy.Subscriber(ns + interface.LINK_ECHO, LinkPing,
                         lambda m: self.echoes.append(time.monotonic()), queue_size=100)
        self.command = rospy.Publisher(interface.limb_topic('right', 'joint_command'),
                                       JointCommand, queue_size=10)

    def _on_command(self, msg):
        with self.lock:
            self.commands.append((time.monotonic(), np.array(msg.command)))

    def steady(self):
        """Return the steady command (the last STEADY_COMMANDS equal), or None."""
        with self.lock:
            last = [c for _, c in self.commands[-STEADY_COMMANDS:]]
        if len(last) == STEADY_COMMANDS and all(
                np.max(np.abs(c - last[-1])) < STEADY_RAD for c in last):
            return list(last[-1])
        return None

    def first_change(self, since, steady):
        """Return the reception time of the first command after since that differs from steady."""
        with self.lock:
            recent = self.commands[-200:]
        return next((t for t, c in recent
                     if t > since and np.max(np.abs(c - np.array(steady))) > MOVED_RAD), None)


class FifoInput:
    def __init__(self, path, name):
        os.mkfifo(path)
        self.path, self.name, self._fd, self._n = path, name, os.open(path, os.O_RDWR), 0

    def write(self, *events):
        t = time.time()
        os.write(self._fd, b''.join(input_events.encode(input_events.InputEvent(t, *x))
                                    for x in events + (input_events.sync(t)[1:],)))

    def follow(self):
        self.write((e.EV_KEY, FOLLOW[self.name], 1))
        time.sleep(0.3)   # held as a person holds it, then released
        self.write((e.EV_KEY, FOLLOW[self.name], 0))

    def start(self, steady):
        self.write(*MOTIONS[self.name][self._n % 4])

    def stop(self):
        self.write(*MOTIONS[self.name][self._n % 4 + 1])
        self._n += 2


class MarkerInput:
    def __init__(self, arm):
        self._arm, self._n = arm, 0
        self._pub = rospy.Publisher(interface.marker_server('R') + '/feedback', Feedback,
                                    queue_size=10)

    def _send(self, kind, **fields):
        msg = Feedback(client_id='/bench', marker_name='gripper', event_type=kind, **fields)
        msg.header.frame_id = baxter_description.BASE_FRAME
        self._pub.publish(msg)

    def follow(self):
        self._send(Feedback.MENU_SELECT, menu_entry_id=1)

    def start(self, steady):
        xyz, rotation = self._arm.tip(steady)
        pose = Pose()
        self._n += 1
        pose.position.x, pose.position.y, pose.position.z = xyz + [
            0.01 if self._n % 2 else -0.01, 0.0, 0.0]
        q = baxter_description.matrix_quaternion(rotation)
        pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q
        self._send(Feedback.POSE_UPDATE, pose=pose)

    def stop(self):
        pass


class PuppetInput:
    def __init__(self, puppet):
        self._puppet, self._n = puppet, 0

    def follow(self):
        self._puppet.press(interface.BUTTON_RIGHT)

    def start(self, steady):
        self._n += 1
        pose = list(HAND_POSE)
        pose[6] += 0.05 if self._n % 2 else 0.0
        self._puppet.hand(pose)

    def stop(self):
        pass


def start_source(name, work, log, watch, arm):
    """Start what feeds arm_R for a device; return (its Popens, its input)."""
    run = lambda *args: start_process(['rosrun', 'robopuppet'] + list(args), log)
    if name == 'puppet':
        link = os.path.join(work, 'puppet_link')
        return [run('puppet_sim', '__name:=puppet_sim_R', '_arm_side:=R', '_port_link:=' + link),
                run('serial_interface', '__name:=serial_R', '_arm_side:=R',
                    '_port_name:=' + link)], PuppetInput(watch.puppet)
    source = MarkerInput(arm) if name == 'marker' else FifoInput(
        os.path.join(work, name + '_R'), name)
    return [run('input_device', '__name:=input_R', '_arm_side:=R', '_device:=' + name,
                '_events:=' + getattr(source, 'path', ''))], source


def measure(name, samples, work, log, watch, arm):
    """Return the latencies (s) of one device's events."""
    names = baxter_description.arm_joint_names('right')
    wait_for(lambda: watch.command.publish(JointCommand(
        mode=JointCommand.POSITION_MODE, names=names, command=BENT)) or np.max(np.abs(
            np.array(watch.baxter.arm('right')) - BENT)) < 0.01, 30, 'the start pose')
    since = time.monotonic()
    processes, source = start_source(name, work, log, watch, arm)
    try:
        if name == 'puppet':
            calibrate(watch.puppet, HAND_POSE)
        wait_for(lambda: sum(t > since for t in watch.echoes) >= 5, 30, name + ': echoes')
        echoed = [t for t in watch.echoes if t > since][4]
        wait_for(lambda: watch.puppet.teleop_log[-1][0] > echoed
                 and watch.puppet.teleop.state == interface.READY, 20, name + ': ready')
        source.follow()
        wait_for(lambda: watch.puppet.teleop.follow_right, 10, name + ': following')
        latencies = []
        for _ in range(samples):
            steady = wait_for(watch.steady, 10, name + ': steady commands')
            time.sleep(random.uniform(0.0, 0.05))   # a random moment
            moved = time.monotonic()
            source.start(steady)
            hit = wait_for(lambda: watch.first_change(moved, steady), 2.0, step_s=0.005)
            if hit:
                latencies.append(hit - moved)
            source.stop()
        return latencies
    finally:
        for process in processes:
            stop_process(process)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--samples', type=int, default=40, help='events per device')
    parser.add_argument('--devices', default=','.join(DEVICES), help='comma-separated')
    options = parser.parse_args()
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, lambda signum, frame: sys.exit('bench_devices: terminated'))
    with private_roscore('bench_devices_') as work:
        log = open(os.path.join(work, 'nodes.log'), 'w')
        run = lambda *args: start_process(['rosrun', 'robopuppet'] + list(args), log)
        stack = [run('baxter_sim', '_gripper_calibrated:=true', '_obstacles_file:=/dev/null'),
                 run('config', '__name:=config_R', '_arm_side:=R',
                     '_file_name:=' + os.path.join(work, 'arm_R.ini')),
                 run('arm', '__name:=arm_R', '_arm_side:=R', '_comm_rate:=10', '_zones_file:=')]
        try:
            rospy.init_node('bench_devices', disable_signals=True)
            watch, arm = Watch(), CartesianArm('right')
            print('Latency from an input event to the first JointCommand it moves (ms)')
            print('%-11s %7s %7s %7s %7s' % ('device', 'events', 'p50', 'p95', 'max'))
            for name in options.devices.split(','):
                print('running %s ...' % name, file=sys.stderr, flush=True)
                got = measure(name, options.samples, work, log, watch, arm)
                print('%-11s %7d %7.1f %7.1f %7.1f%s' % (
                    name, len(got), 1000 * percentile(got, 0.5), 1000 * percentile(got, 0.95),
                    1000 * max(got), '' if len(got) == options.samples else
                    '  (%d never arrived)' % (options.samples - len(got))), flush=True)
        finally:
            rospy.signal_shutdown('done')
            for process in stack:
                stop_process(process)
            log.close()


if __name__ == '__main__':
    main()
