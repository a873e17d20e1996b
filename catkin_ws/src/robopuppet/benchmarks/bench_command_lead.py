#!/usr/bin/python3
"""Benchmark: how far Baxter's mode-1 target leads its measured pose while a puppet moves fast,
and how far Baxter goes on (coasts) once the command stream stops.

Usage (after `. tools/env.sh`): bench_command_lead.py [--seconds S] [--stops N] [--seed K]
    [--range puppet|urdf] [--kills N]
Mode 1 has no command timeout: a Baxter whose commands stop (arm_X killed, the robot host's
master dead) goes on to the last target it got. At the default speed ratio 0.3 it moves a joint
at most 0.3 x its URDF velocity limit, while arm_X may move the target at the full limit, so the
target runs ahead of the arm, and that lead is how far the arm coasts.

1. Tracking (own roscore, baxter_sim.launch headless without cameras or obstacles): for one arm,
   then both, S seconds (60) of random smooth motion sent at 100 Hz on
   /robot/limb/<side>/joint_command (mode 1): each joint to a seeded random point of its range
   (puppet: the puppet's +-1.5 rad within the URDF limits; urdf: the URDF limits) on a
   half-cosine at a peak speed of 0.5-1 x its URDF velocity limit, dwelling 0-0.3 s, the
   commands passed through arm_X's SpeedBudget (arm/joint_motion.py, a 10 ms burst). For every
   /robot/joint_states sample: lead = |newest command sent by its stamp - measured| per joint
   (rad) and the distance between the gripper tip (<side>_gripper, baxter_description FK) at
   that command and at the measured pose (cm); p50, p99, max; and the share of samples a leash
   of D rad (no target more than D ahead of the measured pose) would have cut.
2. Stops: N times (10) per configuration the stream stops at a random moment 1.5-4 s into a
   motion; from the last command on: how long until the arm stands still (its last sample that
   moved more than 1e-5 rad), how far it went (max joint rad, gripper tip cm straight and along
   its path) and the lead at the stop.
3. Leash (no ROS; baxter_sim's BaxterModel, the right arm's motion of 1, each command cut to
   within D of the pose measured 10 ms before): tracking error (SpeedBudget command - measured,
   max joint rad and tip cm), commands cut, and the largest lead (the most the arm can coast,
   joint rad and tip cm) without a leash, with D = 0.02 ... 0.3 rad on every joint, and with
   D = T x each joint's mode-1 speed (T = 0.05, 0.1, 0.2 s: the arm coasts at most about T).
4. --kills N (default 0: off): main_sim.launch headless (zones and obstacles off, so that
   neither cuts the motion), the simulated puppet's hand sweeping random poses at its top speed
   (tests/integration/sweep_harness.py), Baxter's right arm following; arm_R killed with SIGKILL
   after 2-5 s, Baxter's coast measured from arm_R's last command as in 2; arm_R restarted.
"""
import argparse
import math
import multiprocessing
import os
import random
import signal
import sys
import threading
import time

import numpy as np

from bench_support import percentile, private_roscore, start_process, stop_process
from robopuppet import baxter_description as bd, interface
from robopuppet.arm.joint_motion import SpeedBudget, clamp
from robopuppet.baxter_sim.baxter_model import DEFAULT_SPEED_RATIO, POSITION_MODE, BaxterModel

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests',
                                'integration'))

PERIOD_S = 0.01          # arm_X's command period (100 Hz), also the SpeedBudget burst
MOVED_RAD = 1e-5         # a sample that moved less than this from the one before stands still
STILL_SAMPLES = 30       # ... and this many such samples in a row: the arm stands still
PUPPET_RAD = 1.5         # the puppet's angle range (arm_X.ini's limits are +-1.571)
LEASHES_RAD = (0.1, 0.2, 0.3)
MODEL_LEASHES_RAD = (0.02, 0.05) + LEASHES_RAD
MODEL_LEASHES_S = (0.05, 0.1, 0.2)   # leashes of this long at each joint's mode-1 speed


class Hand:
    """Seeded random smooth motion of one arm's 7 joints (rad), each joint on its own."""

    def __init__(self, limits, rng, start, t, full_range=False):
        self.limits, self.rng = limits, rng
        span = (lambda lim: (lim.lower, lim.upper)) if full_range else (
            lambda lim: (max(lim.lower, -PUPPET_RAD), min(lim.upper, PUPPET_RAD)))
        self.ranges = [span(lim) for lim in limits]
        self.restart(start, t)

    def restart(self, start, t):
        """Start every joint's next move from start (7 rad) at time t (s)."""
        self.moves = [self._move(j, min(max(q, lo), hi), t)
                      for j, (q, (lo, hi)) in enumerate(zip(start, self.ranges))]

    def _move(self, j, q0, t0):
        q1 = self.rng.uniform(*self.ranges[j])
        peak = self.rng.uniform(0.5, 1.0) * self.limits[j].velocity
        duration = max(0.5 * math.pi * abs(q1 - q0) / peak, 0.1)   # half-cosine's peak speed
        return (t0, q0, q1, duration, self.rng.uniform(0.0, 0.3))

    def pose(self, t):
        """Return the 7 angles (rad) at time t (s, not before the previous call)."""
        angles = []
        for j in range(len(self.moves)):
            t0, q0, q1, duration, dwell = self.moves[j]
            if t >= t0 + duration + dwell:
                self.moves[j] = self._move(j, q1, t0 + duration + dwell)
                t0, q0, q1, duration, dwell = self.moves[j]
            s = min(max((t - t0) / duration, 0.0), 1.0)
            angles.append(q0 + (q1 - q0) * 0.5 * (1.0 - math.cos(math.pi * s)))
        return angles


def stats(values):
    return percentile(values, 0.5), percentile(values, 0.99), max(values)


def tips(side, rows):
    """Return the gripper tip positions (N, 3) m of the (N, 7) joint rows of an arm."""
    description, names, link = bd.load(), bd.arm_joint_names(side), bd.gripper_link(side)
    return np.array([description.transform(dict(zip(names, row)), link)[:3, 3] for row in rows])


def print_lead(label, leads, tip_cm):
    """Print the lead table: per joint p50/p99/max (rad), the worst joint's, the tip's (cm)."""
    print('  %s: %d samples' % (label, len(leads)))
    print('    %-10s %s' % ('rad', ' '.join('%6s' % s for s in bd.ARM_JOINT_SUFFIXES + ('any',))))
    worst = leads.max(axis=1)
    for k, name in enumerate(('p50', 'p99', 'max')):
        row = [stats(leads[:, j])[k] for j in range(7)] + [stats(worst)[k]]
        print('    lead %-5s %s' % (name, ' '.join('%6.3f' % v for v in row)))
    print('    tip: p50 %.1f cm, p99 %.1f cm, max %.1f cm' % stats(tip_cm))
    for d in LEASHES_RAD:
        print('    leash %.1f rad would cut (%% of samples) %s  any %3.0f' % (d, ' '.join(
            '%6.0f' % (100.0 * np.mean(leads[:, j] > d)) for j in range(7)),
            100.0 * np.mean(worst > d)))


class Stream:
    """Mode-1 commands at 100 Hz to some arms along their Hands, and the joint_states seen."""

    def __init__(self, rospy, sides, rng, full_range):
        from baxter_core_msgs.msg import JointCommand
        from sensor_msgs.msg import JointState
        self.rospy, self.JointCommand, self.sides = rospy, JointCommand, sides
        self.limits = {s: bd.arm_limits(s) for s in sides}
        self.rng, self.full_range = rng, full_range
        self.lock, self.samples, self.sent = threading.Lock(), [], {s: [] for s in sides}
        self.pubs = {s: rospy.Publisher(interface.limb_topic(s, 'joint_command'), JointCommand,
                                        queue_size=10, tcp_nodelay=True) for s in sides}
        self.names = {s: bd.arm_joint_names(s) for s in sides}
        self.subscriber = rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState,
                                           self._on_joints, queue_size=1000, tcp_nodelay=True)

    def _on_joints(self, msg):
        where = dict(zip(msg.name, msg.position))
        with self.lock:
            self.samples.append((msg.header.stamp.to_sec(),
                                 {s: [where[n] for n in self.names[s]] for s in self.sides}))

    def newest(self):
        with self.lock:
            return self.samples[-1][1]

    def run(self, seconds):
        """Send commands for `seconds` from where the arms are; return the last send time."""
        t = self.rospy.get_time()
        pose = self.newest()
        hands = {s: Hand(self.limits[s], self.rng, pose[s], t, self.full_range)
                 for s in self.sides}
        budgets = {s: SpeedBudget(pose[s], PERIOD_S, t) for s in self.sides}
        speeds = {s: [lim.velocity for lim in self.limits[s]] for s in self.sides}
        end, deadline = t + seconds, time.monotonic()
        while True:
            t = self.rospy.get_time()
            if t >= end:
                return last
            for side in self.sides:
                command = budgets[side].move(hands[side].pose(t), speeds[side], t)
                self.pubs[side].publish(self.JointCommand(
                    mode=POSITION_MODE, names=self.names[side], command=command))
                self.sent[side].append((t, command))
            last = t
            deadline += PERIOD_S
            time.sleep(max(deadline - time.monotonic(), 0.0))

    def still(self):
        """Return whether the last STILL_SAMPLES samples of every arm stood still."""
        with self.lock:
            rows = self.samples[-STILL_SAMPLES:]
        return len(rows) == STILL_SAMPLES and all(
            max(abs(a - b) for a, b in zip(p[1][s], q[1][s])) < MOVED_RAD
            for p, q in zip(rows, rows[1:]) for s in self.sides)

    def window(self, side, start, end=math.inf):
        """Return (stamps, (N, 7) measured, (N, 7) newest command sent by each stamp)."""
        with self.lock:
            rows = [(t, pose[side]) for t, pose in self.samples if start <= t <= end]
        sent_t = np.array([t for t, _ in self.sent[side]])
        sent = np.array([c for _, c in self.sent[side]])
        stamps = np.array([t for t, _ in rows])
        picked = np.searchsorted(sent_t, stamps, 'right') - 1
        keep = picked >= 0
        return stamps[keep], np.array([p for _, p in rows])[keep], sent[picked[keep]]


def coast(stream, side, stop_t):
    """Return (s moving after stop_t, max joint rad moved, tip cm straight, tip cm along the
    path, max joint lead rad at the stop) of an arm whose commands stopped at stop_t."""
    stamps, measured, _ = stream.window(side, stop_t - 1.0)
    at = int(np.searchsorted(stamps, stop_t, 'right')) - 1
    after = measured[at:]
    steps = np.abs(np.diff(after, axis=0)).max(axis=1)
    moving = np.nonzero(steps > MOVED_RAD)[0]
    moved_s = stamps[at + 1 + moving[-1]] - stop_t if len(moving) else 0.0
    tip = tips(side, after)
    return (moved_s, np.abs(after - after[0]).max(), 100.0 * np.linalg.norm(tip[-1] - tip[0]),
            100.0 * np.linalg.norm(np.diff(tip, axis=0), axis=1).sum(),
            np.abs(stream.sent[side][-1][1] - after[0]).max())


def print_coasts(label, rows):
    print('  %s: %d stops' % (label, len(rows)))
    for k, name in enumerate(('moving after the last command (s)', 'joint moved (rad, max)',
                              'tip moved (cm, straight)', 'tip path (cm)',
                              'lead at the stop (rad, max joint)')):
        values = [r[k] for r in rows]
        print('    %-36s p50 %6.3f  max %6.3f  min %6.3f' % (name, percentile(values, 0.5),
                                                             max(values), min(values)))


def stand_in(args):
    """Parts 1 and 2 against the baxter_sim node."""
    from waiting import wait_for
    with private_roscore('bench_command_lead_') as work:
        launch = start_process(['roslaunch', 'robopuppet', 'baxter_sim.launch', 'rviz:=false',
                                'sim_cameras:=false', 'obstacles_file:=/dev/null'],
                               open(os.path.join(work, 'launch.log'), 'w'))
        try:
            import rospy
            from std_msgs.msg import Bool
            rospy.init_node('bench_command_lead', disable_signals=True)
            enable = rospy.Publisher(interface.SET_SUPER_ENABLE, Bool, queue_size=1, latch=True)
            enable.publish(Bool(True))
            rng = random.Random(args.seed)
            for sides in (('right',), ('right', 'left')):
                stream = Stream(rospy, sides, rng, args.range == 'urdf')
                wait_for(lambda: stream.samples and stream.still(), 30, 'Baxter standing still')
                print('%s arm%s, mode 1 at speed ratio 0.3, commands at 100 Hz:'
                      % (' and '.join(sides), 's' if len(sides) > 1 else ''), flush=True)
                start = rospy.get_time() + 1.0   # from 1 s on: the lead has built up
                end = stream.run(args.seconds + 1.0)
                for side in sides:
                    _, measured, commands = stream.window(side, start, end)
                    tip_cm = 100.0 * np.linalg.norm(tips(side, commands) - tips(side, measured),
                                                    axis=1)
                    print_lead('%s arm, %.0f s tracking' % (side, end - start),
                               np.abs(commands - measured), tip_cm)
                rows = {side: [] for side in sides}
                for _ in range(args.stops):
                    wait_for(stream.still, 60, 'Baxter standing still')
                    stop_t = stream.run(rng.uniform(1.5, 4.0))
                    wait_for(stream.still, 60, 'Baxter standing still after the stop')
                    for side in sides:
                        rows[side].append(coast(stream, side, stop_t))
                for side in sides:
                    print_coasts('%s arm, stream stopped' % side, rows[side])
                stream.subscriber.unregister()
            rospy.signal_shutdown('benchmark done')
        finally:
            stop_process(launch)


def leash_model(args, leash_rad):
    """Part 3 for one leash (7 rad, None: none): return (tracking error (N, 7) rad, tracking
    error of the tip (N,) cm, share of commands cut, lead (N, 7) rad, lead of the tip (N,) cm)
    of the right arm over args.seconds."""
    model = BaxterModel(bd.load(), 0.0)
    model.set_enabled(True)
    arm, names = model.arms['right'], bd.arm_joint_names('right')
    limits = bd.arm_limits('right')
    speeds = [lim.velocity for lim in limits]
    measured = [arm.positions[n] for n in names]
    hand = Hand(limits, random.Random(args.seed), measured, 0.0, args.range == 'urdf')
    budget = SpeedBudget(measured, PERIOD_S, 0.0)
    rows, cut = {'wanted': [], 'command': [], 'before': [], 'measured': []}, 0
    steps = int(round((args.seconds + 1.0) / PERIOD_S))
    for i in range(steps):
        t = i * PERIOD_S
        wanted = budget.move(hand.pose(t), speeds, t)
        command = list(wanted)
        if leash_rad is not None:   # around the pose measured one step (10 ms) ago
            command = [min(max(c, m - d), m + d)
                       for c, m, d in zip(wanted, measured, leash_rad)]
            cut += command != wanted
        model.joint_command('right', POSITION_MODE, names, command, t)
        model.step(t + PERIOD_S)
        before, measured = measured, [arm.positions[n] for n in names]
        if t >= 1.0:   # from 1 s on, as the ROS run
            for key, row in (('wanted', wanted), ('command', command), ('before', before),
                             ('measured', measured)):
                rows[key].append(row)
    rows = {key: np.array(value) for key, value in rows.items()}
    tip = {key: tips('right', value) for key, value in rows.items()}

    def tip_cm(a, b):
        return 100.0 * np.linalg.norm(tip[a] - tip[b], axis=1)
    return (np.abs(rows['wanted'] - rows['measured']), tip_cm('wanted', 'measured'),
            cut / float(steps), np.abs(rows['command'] - rows['before']),
            tip_cm('command', 'before'))


def print_leashes(args):
    print('leash, no ROS (baxter_sim BaxterModel, right arm, mode 1 at 0.3, %.0f s, the leash '
          'around the pose measured 10 ms before):' % args.seconds)
    print('  (a leash of T s: T x each joint\'s mode-1 speed, %s rad)' % ' '.join(
        '%.3f' % (DEFAULT_SPEED_RATIO * lim.velocity) for lim in bd.arm_limits('right')))
    print('  %-8s %-22s %-20s %-7s %s' % ('leash', 'tracking p50/p99/max', 'tip p50/p99/max',
                                          'cut', 'lead max = coast max: joint, tip'))
    speeds = [DEFAULT_SPEED_RATIO * lim.velocity for lim in bd.arm_limits('right')]
    leashes = ([('none', None)] + [('%.2f rad' % d, [d] * 7) for d in MODEL_LEASHES_RAD]
               + [('%.2f s' % t, [t * v for v in speeds]) for t in MODEL_LEASHES_S])
    for name, leash in leashes:
        errors, tip_error_cm, cut, leads, tip_lead_cm = leash_model(args, leash)
        print('  %-8s %-22s %-20s %5.1f %%  %.3f rad, %.1f cm' % (
            name,
            '%.3f %.3f %.3f rad' % stats(list(errors.max(axis=1))),
            '%.1f %.1f %.1f cm' % stats(list(tip_error_cm)), 100.0 * cut, leads.max(),
            tip_lead_cm.max()), flush=True)


def arm_x_kills(args):
    """Part 4: main_sim, arm_R killed mid-motion args.kills times."""
    from hand_pose import HAND_POSE
    from sweep_harness import follow, sweeping_hand
    from teleop_harness import PuppetArm, calibrate, max_error, node_pid
    from waiting import wait_for
    import rospy
    with private_roscore('bench_command_lead_') as work:
        log = open(os.path.join(work, 'launch.log'), 'w')
        launch = start_process(
            ['roslaunch', 'robopuppet', 'main_sim.launch', 'rviz:=false', 'gui:=false',
             'sim_cameras:=false', 'zones_file:=/dev/null', 'obstacles_file:=/dev/null',
             'sim_link_prefix:=%s/pty' % work], log)
        arm = None
        try:
            rospy.init_node('bench_command_lead', disable_signals=True)
            puppet, stream = PuppetArm('R'), Stream(rospy, ('right',), None, False)
            from baxter_core_msgs.msg import JointCommand
            rospy.Subscriber(interface.limb_topic('right', 'joint_command'), JointCommand,
                             lambda m: stream.sent['right'].append((rospy.get_time(),
                                                                    list(m.command))),
                             queue_size=1000, tcp_nodelay=True)
            wait_for(lambda: puppet.state() == interface.CALIBRATING, 60, 'arm_R calibrating')
            puppet.end_piece(False)
            calibrate(puppet, HAND_POSE)
            rng, rows, limits = random.Random(args.seed), [], bd.arm_limits('right')
            for k in range(args.kills):
                wait_for(lambda: puppet.state() == interface.READY, 30, 'arm_R ready')
                follow(puppet, (interface.BUTTON_RIGHT,))
                # The slow approach (0.5 rad/s) done: arm_R tracks the puppet directly.
                wait_for(lambda: max_error(stream.newest()['right'],
                                           clamp(puppet.angles, limits)) < 0.01, 60,
                         'Baxter on the puppet')
                pid = node_pid('/arm_R')
                with sweeping_hand(puppet, args.seed + k):
                    time.sleep(rng.uniform(2.0, 5.0))   # the arm follows for a random while
                    os.kill(pid, signal.SIGKILL)
                    wait_for(stream.still, 60, 'Baxter standing still after the kill')
                puppet.hand(HAND_POSE)   # the next trial starts where the first did
                rows.append(coast(stream, 'right', stream.sent['right'][-1][0]))
                print('  kill %2d: Baxter moved %.2f s after arm_R\'s last command, %.3f rad, '
                      'tip %.1f cm straight, %.1f cm path; lead %.3f rad'
                      % ((k + 1,) + rows[-1]), flush=True)
                if arm is not None:
                    stop_process(arm)   # killed already: reaped
                puppet.teleop = None
                arm = start_process(['rosrun', 'robopuppet', 'arm', '__name:=arm_R',
                                     '_arm_side:=R', '_comm_rate:=10', '_max_sample_age:=0.35',
                                     '_zones_file:=/dev/null'], log)
            print_coasts('main_sim, right arm following the swept puppet, arm_R killed', rows)
            rospy.signal_shutdown('benchmark done')
        finally:
            if arm is not None:
                stop_process(arm)
            stop_process(launch)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--seconds', type=float, default=60.0, help='tracking time per run')
    parser.add_argument('--stops', type=int, default=10, help='stream stops per configuration')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--range', choices=('puppet', 'urdf'), default='puppet',
                        help='where the random targets lie')
    parser.add_argument('--kills', type=int, default=0, help='arm_R kills in main_sim (0: off)')
    args = parser.parse_args()
    # A process each: rospy runs one node per process, and each run has its own roscore.
    for part in (stand_in,) + ((arm_x_kills,) if args.kills else ()):
        run = multiprocessing.get_context('spawn').Process(target=part, args=(args,))
        run.start()
        run.join()
    print_leashes(args)


if __name__ == '__main__':
    main()
