"""A fast random sweep of the simulated puppet's hand, and Baxter's measured pose against the
keep-out zones (imported by test_zones_sweep.py and benchmarks/bench_zones_sweep.py).

The hand goes from one seeded random pose to the next across the puppet's whole joint range at
the simulated hand's top speed; a new pose as soon as the puppet reports the last one reached.
Recorder keeps every /robot/joint_states sample (Baxter's stamp, both arms) and every puppet
joint_states; evaluate() puts every sample of Baxter's measured arms through the project's
capsule model (world.zones.ZoneGuard, the guards arm/zone_topics.load_guards builds), in
batches, and tracking() compares them with the puppet's pose mapped onto each arm.
"""
import collections
import contextlib
import random
import threading

import numpy as np
import rospy
from sensor_msgs.msg import JointState

from robopuppet import baxter_description as bd, interface
from robopuppet.arm import zone_topics
from robopuppet.arm.joint_motion import clamp, in_puppet_space
from robopuppet.puppet_sim.puppet_arm import HAND_SPEED_RADPS

from teleop_harness import calibrate, max_error
from waiting import wait_for

SWEEP_RAD = 1.5          # poses within +-this: the puppet's angle limits are +-1.571 (arm_X.ini)
REACHED_RAD = 0.05       # the puppet reports every joint this near the pose: next pose
POSE_TIMEOUT_S = 2.0 * SWEEP_RAD / HAND_SPEED_RADPS + 2.0   # ... or after this long
CHUNK = 1000             # samples per clearance batch
JOINT_LABELS = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
ARM_SIDES = {'left': (interface.BUTTON_LEFT,), 'right': (interface.BUTTON_RIGHT,),
             'both': (interface.BUTTON_LEFT, interface.BUTTON_RIGHT)}

Worst = collections.namedtuple('Worst', 'clearance_m zone link t_s arm')
Worst.__doc__ = """The sample nearest a zone (deepest inside): clearance (m, < 0 inside), zone
and link (URDF name), its stamp (s) after a start time, and Baxter's arm."""


def random_poses(seed):
    """Yield seeded random puppet poses (7 rad, uniform within +-SWEEP_RAD) for ever."""
    rng = random.Random(seed)
    while True:
        yield [rng.uniform(-SWEEP_RAD, SWEEP_RAD) for _ in range(7)]


@contextlib.contextmanager
def sweeping_hand(puppet, seed):
    """Drive the operator's hand (teleop_harness.PuppetArm) through random_poses(seed) until the
    block ends; yields the list of (ROS time s, pose) sent so far."""
    stop, sent = threading.Event(), []

    def reached(pose):
        angles = puppet.angles
        return angles is not None and max(abs(a - p) for a, p in zip(angles, pose)) < REACHED_RAD

    def sweep():
        for pose in random_poses(seed):
            puppet.hand(pose)
            sent.append((rospy.get_time(), pose))
            waited = 0.0
            while not (stop.is_set() or reached(pose) or waited > POSE_TIMEOUT_S):
                stop.wait(0.02)   # polls the puppet's reports (10 Hz) for the pose reached
                waited += 0.02
            if stop.is_set():
                return

    mover = threading.Thread(target=sweep, daemon=True)
    mover.start()
    try:
        yield sent
    finally:
        stop.set()
        mover.join()


def follow(puppet, buttons, timeout_s=10.0):
    """Press `buttons` (ARM_SIDES' values) on a ready puppet; wait until those arms follow."""
    for button in buttons:
        puppet.press(button)
    wanted = {'follow_left': interface.BUTTON_LEFT in buttons,
              'follow_right': interface.BUTTON_RIGHT in buttons}
    wait_for(lambda: puppet.state() == interface.FOLLOWING and all(
        getattr(puppet.teleop, key) == on for key, on in wanted.items()), timeout_s,
        'Baxter following buttons %s' % (buttons,))


def start_following(puppet, recorder, arms, hand_pose, wait_s=60.0):
    """Calibrate the simulated puppet at hand_pose, press the follow buttons of Baxter's `arms`
    (sides) and wait until each is on the puppet's pose (within 0.01 rad); return the ROS time
    of the press."""
    wait_for(lambda: puppet.state() == interface.CALIBRATING, wait_s, 'arm_R calibrating')
    puppet.end_piece(False)
    calibrate(puppet, hand_pose)
    wait_for(lambda: puppet.state() == interface.READY, 10, 'ready')
    start = rospy.get_time()
    follow(puppet, sum((ARM_SIDES[arm] for arm in arms), ()))
    wait_for(lambda: all(max_error(recorder.newest(arm),
                                   in_puppet_space(interface.BAXTER_SIDE[puppet.side], arm,
                                                   puppet.angles)) < 0.01
                         for arm in arms), wait_s, 'Baxter on the puppet')
    return start


def keep_following(puppet, buttons, seconds):
    """Let the arms of `buttons` follow the puppet for `seconds` (ROS time); after a fault, as
    an operator would, press them again once the puppet is ready. Return [(fault s, resumed
    s)] (ROS time) of every fault."""
    faults, end_s = [], rospy.get_time() + seconds
    while rospy.get_time() < end_s:
        wait_for(lambda: rospy.get_time() >= end_s or puppet.state() != interface.FOLLOWING,
                 seconds + 10.0, 'the sweep')
        if rospy.get_time() >= end_s:
            break
        fault_s = rospy.get_time()
        wait_for(lambda: puppet.state() == interface.READY, 20,
                 'arm_R ready after %r' % puppet.teleop.detail)
        follow(puppet, buttons)
        faults.append((fault_s, rospy.get_time()))
    return faults


class Recorder:
    """Every /robot/joint_states sample of both arms and every joint_states of one puppet.

    Callbacks only append (stamp s, seq, angles); evaluate() works on the copies window() takes.
    """

    def __init__(self, puppet_side):
        self.puppet_side = puppet_side
        self._lock = threading.Lock()
        self._names = {arm: bd.arm_joint_names(arm) for arm in interface.BAXTER_SIDES}
        self.baxter, self.puppet = [], []   # (stamp s, seq, {arm: 7 rad}), (stamp s, 7 rad)
        rospy.Subscriber(interface.ROBOT_JOINT_STATES, JointState, self._on_baxter,
                         queue_size=2000)
        rospy.Subscriber('%s/%s' % (interface.puppet_ns(puppet_side), interface.JOINT_STATES),
                         JointState, self._on_puppet, queue_size=200)

    def _on_baxter(self, msg):
        where = dict(zip(msg.name, msg.position))
        arms = {arm: [where.get(n, np.nan) for n in names] for arm, names in self._names.items()}
        with self._lock:
            self.baxter.append((msg.header.stamp.to_sec(), msg.header.seq, arms))

    def _on_puppet(self, msg):
        with self._lock:
            self.puppet.append((msg.header.stamp.to_sec(), list(msg.position)))

    def newest(self, arm):
        """Return the newest measured angles (7 rad) of Baxter's `arm` (NaN before any)."""
        with self._lock:
            return self.baxter[-1][2][arm] if self.baxter else [np.nan] * 7

    def still(self, samples=11, tolerance_rad=1e-4):
        """Return whether both arms stood still over the newest `samples` samples."""
        with self._lock:
            rows = self.baxter[-samples:]
        return len(rows) == samples and all(
            np.abs(np.subtract(rows[0][2][arm], rows[-1][2][arm])).max() < tolerance_rad
            for arm in interface.BAXTER_SIDES)

    def window(self, start_s, end_s=np.inf):
        """Return (stamps (N,), {arm: (N, 7)}, missed: samples lost by seq, puppet stamps (P,),
        puppet angles (P, 7)) of Baxter's samples stamped within start_s..end_s (ROS time)."""
        with self._lock:
            rows = [r for r in self.baxter if start_s <= r[0] <= end_s]
            puppet = [p for p in self.puppet if p[0] <= end_s]
        seqs = np.array([r[1] for r in rows])
        missed = int((np.diff(seqs) - 1).clip(0).sum()) if len(seqs) > 1 else 0
        arms = {arm: np.array([r[2][arm] for r in rows]).reshape(-1, 7)
                for arm in interface.BAXTER_SIDES}
        return (np.array([r[0] for r in rows]), arms, missed,
                np.array([p[0] for p in puppet]), np.array([p[1] for p in puppet]).reshape(-1, 7))


def package_guards():
    """Return {arm: ZoneGuard} of config/zones.yaml, as arm_X's zone_topics.load_guards builds
    them."""
    return zone_topics.load_guards(zone_topics.package_zones_file())[0]


def clearances(guard, rows):
    """Return (clearance m, zone index, capsule index) of each (N, 7) row's capsule nearest a
    zone (deepest inside), every row through ZoneGuard's exact distances, CHUNK rows a batch."""
    best, zone, link = (np.empty(len(rows)), np.empty(len(rows), int),
                        np.empty(len(rows), int))
    for at in range(0, len(rows), CHUNK):
        gaps = guard._clearance(np.asarray(rows[at:at + CHUNK], np.float64), np.inf)  # (Z, M, C)
        flat = gaps.transpose(1, 0, 2).reshape(gaps.shape[1], -1)
        pick = np.argmin(flat, axis=1)
        best[at:at + CHUNK] = flat[np.arange(len(pick)), pick]
        zone[at:at + CHUNK], link[at:at + CHUNK] = np.divmod(pick, gaps.shape[2])
    return best, zone, link


def evaluate(guards, stamps, arms, arm_names, start_s):
    """Return ({arm: clearance (N,) m}, Worst over the arms, its time after start_s) of every
    sample of the arms `arm_names`."""
    found, worst = {}, None
    for arm in arm_names:
        best, zone, link = clearances(guards[arm], arms[arm])
        found[arm] = best
        k = int(np.argmin(best))
        if worst is None or best[k] < worst.clearance_m:
            guard = guards[arm]
            worst = Worst(float(best[k]), guard.names[zone[k]], guard.capsules.links[link[k]],
                          float(stamps[k] - start_s), arm)
    return found, worst


def tracking(puppet_side, arm, stamps, measured, puppet_t, puppet_q):
    """Return |measured - target| (N, 7) rad: the target at each Baxter stamp is the newest
    puppet pose by then, on `arm` as arm_X takes it (own side as is, the other mirrored) and
    clamped to Baxter's limits; NaN before the first puppet pose."""
    own = 'left' if puppet_side == 'L' else 'right'
    limits = bd.arm_limits(arm)
    mapped = np.array([clamp(in_puppet_space(own, arm, q), limits) for q in puppet_q])
    newest = np.searchsorted(puppet_t, stamps, side='right') - 1
    lag = np.full(measured.shape, np.nan)
    ok = newest >= 0
    lag[ok] = np.abs(measured[ok] - mapped[newest[ok]])
    return lag


def travel(measured):
    """Return (path length rad summed over the joints, per-joint range rad (7,))."""
    if len(measured) < 2:
        return 0.0, np.zeros(7)
    return float(np.abs(np.diff(measured, axis=0)).sum()), np.ptp(measured, axis=0)


def lag_lines(lag):
    """Return text lines of the tracking lag's p50 / p99 / max per joint (lag (N, 7) rad)."""
    lines = ['  %-46s%s' % ('tracking lag |Baxter - puppet target| (rad)',
                            ' '.join('%5s' % name for name in JOINT_LABELS))]
    for name, q in (('p50', 50), ('p99', 99), ('max', 100)):
        values = (np.nanpercentile(lag, q, axis=0) if np.isfinite(lag).any()
                  else np.full(7, np.nan))
        lines.append('    %-44s%s' % (name, ' '.join('%5.2f' % v for v in values)))
    return lines


def inside_message(worst, what):
    """Return the failure message naming the Worst sample of `what`."""
    return ("Baxter's measured %s arm %.1f mm inside keep-out zone %r (link %s) at %.2f s of %s"
            % (worst.arm, -1000.0 * worst.clearance_m, worst.zone, worst.link, worst.t_s, what))


Summary = collections.namedtuple('Summary', 'lines worst clearance measured moving missed')
Summary.__doc__ = """What report() found: text lines, the Worst sample, {arm: clearance (N,) m}
and {arm: measured (N, 7) rad} of every sample, {arm: measured rows from moving_from_s on},
and the samples lost (by seq)."""


def report(guards, recorder, start_s, end_s, arm_names, moving_from_s=None, lag=True):
    """Return the Summary of Baxter's samples stamped start_s..end_s (ROS time): the clearance
    of every sample (the Worst's time counts from moving_from_s, default start_s); from
    moving_from_s on, per arm, the tracking lag p50 / p99 / max per joint (unless lag is
    False: the puppet drives nothing), the travel, the share of samples inside a zone."""
    stamps, arms, missed, puppet_t, puppet_q = recorder.window(start_s, end_s)
    if not len(stamps):
        raise AssertionError('no /robot/joint_states samples to evaluate')
    moving_from_s = start_s if moving_from_s is None else moving_from_s
    found, worst = evaluate(guards, stamps, arms, arm_names, moving_from_s)
    moving = stamps >= moving_from_s
    lines = ['samples: %d (%d lost by seq), stamped %.1f to %.1f s from the start (%d after '
             'it); puppet joint_states: %d' % (
                 len(stamps), missed, stamps[0] - moving_from_s, stamps[-1] - moving_from_s,
                 moving.sum(), len(puppet_t))]
    for arm in arm_names:
        lines.append('%s arm:' % arm)
        if lag:
            lines += lag_lines(tracking(recorder.puppet_side, arm, stamps[moving],
                                        arms[arm][moving], puppet_t, puppet_q))
        path, spans = travel(arms[arm][moving])
        inside = found[arm][moving] < 0.0
        lines.append('  after the start: travel %.1f rad, joint ranges %s rad; inside a zone: '
                     '%d of %d samples (%.1f %%); nearest a zone (all samples): %.1f mm' % (
                         path, ' '.join('%.2f' % s for s in spans), inside.sum(), len(inside),
                         100.0 * inside.mean() if len(inside) else np.nan,
                         1000.0 * found[arm].min()))
    lines.append('minimum clearance: %.1f mm, zone %r, link %s, %s arm, at %.2f s from the '
                 'start' % (1000.0 * worst.clearance_m, worst.zone, worst.link, worst.arm,
                            worst.t_s))
    return Summary(lines, worst, found, arms,
                   {arm: arms[arm][moving] for arm in arm_names}, missed)
