"""Scripted demonstrations of the assist's tasks: both arms' joint motion, varied per seed.

A task's plan is a list of Cartesian waypoints of both tool points (tasks.py's geometry), each
reached in its own duration along a minimum-jerk profile (Flash and Hogan 1985); a seed varies
the start, distances, speed, pauses and number of strokes, and adds small smooth hand noise to
the leader's hand. arm_path turns the positions into joint angles (inside the joints' limits and
the puppet's angle range). unfamiliar() is a leader motion no demonstration shows, with the
follower held at its start. Pure: numpy only.
"""
import collections

import numpy as np

from robopuppet.assist import tasks
from robopuppet.assist.arm_path import ArmPath

Demo = collections.namedtuple('Demo', 't left right left_closed right_closed')
Demo.__doc__ = """One execution of a task: t (N,) s from 0; left, right (N, 7) joint angles
(rad, puppet order s0..w2) of Baxter's arms; left_closed, right_closed (N,) bool grippers."""

# One step of a plan: reach left and right tool-point positions (m) in duration_s, with the
# grippers as given (from the step's start).
Step = collections.namedtuple('Step', 'duration_s left right left_closed right_closed')

NOISE_M = 0.002          # the leader's hand noise: amplitude of each of its sine components
NOISE_HZ = (0.2, 1.2)    # their frequencies
NOISE_PARTS = 3
SPEED = (0.8, 1.3)       # a whole execution's durations are divided by a factor drawn here
# The unfamiliar motion: the leader reaches high and out to its side.
UNFAMILIAR_REACH = ((0.80, -0.50, 0.22), (0.62, -0.72, 0.18))


def minimum_jerk(s):
    """Return the minimum-jerk profile 10 s^3 - 15 s^4 + 6 s^5 at s in [0, 1]."""
    return s ** 3 * (10.0 - 15.0 * s + 6.0 * s * s)


def sample(steps, start_left, start_right, rate_hz):
    """Return (t, left xyz, right xyz, left closed, right closed) of a plan at rate_hz."""
    t_all, left, right, closed_l, closed_r = [0.0], [start_left], [start_right], [False], [False]
    here_l, here_r, t0 = np.array(start_left), np.array(start_right), 0.0
    for step in steps:
        count = max(1, int(round(step.duration_s * rate_hz)))
        s = minimum_jerk(np.arange(1, count + 1) / count)[:, None]
        to_l, to_r = np.array(step.left), np.array(step.right)
        left.extend(here_l + s * (to_l - here_l))
        right.extend(here_r + s * (to_r - here_r))
        t_all.extend(t0 + np.arange(1, count + 1) / rate_hz)
        closed_l.extend([step.left_closed] * count)
        closed_r.extend([step.right_closed] * count)
        here_l, here_r, t0 = to_l, to_r, t_all[-1]
    closed_l[0], closed_r[0] = closed_l[1], closed_r[1]
    return (np.array(t_all), np.array(left), np.array(right), np.array(closed_l),
            np.array(closed_r))


def hand_noise(rng, t):
    """Return (N, 3) smooth noise (m) of a hand over times t, 0 at t[0]."""
    noise = np.zeros((len(t), 3))
    for axis in range(3):
        for _ in range(NOISE_PARTS):
            hz, phase = rng.uniform(*NOISE_HZ), rng.uniform(0.0, 2.0 * np.pi)
            noise[:, axis] += NOISE_M * np.sin(2.0 * np.pi * hz * (t - t[0]) + phase)
    return noise - noise[0]


def _between(rng, pair):
    return rng.uniform(*pair)


def _spread(rng, centre, spread):
    return np.array(centre) + rng.uniform(-1.0, 1.0, 3) * np.array(spread)


def carry_tray_plan(rng, speed):
    """Return (start left, start right, steps) of one tray carry."""
    g = tasks.CARRY_TRAY.geometry
    half = np.array([0.0, g['tray_width_m'] / 2.0, 0.0])
    centre = _spread(rng, g['start_centre'], g['start_spread'])
    lift = np.array([0.0, 0.0, _between(rng, g['lift_m'])])
    carry = np.array([_between(rng, g['carry_forward_m']), _between(rng, g['carry_sideways_m']),
                      0.0])
    steps = []

    def to(duration_s, centre_to, closed):
        steps.append(Step(duration_s / speed, centre_to + half, centre_to - half, closed, closed))
    to(rng.uniform(0.3, 0.8), centre, False)                 # reach the handles
    to(rng.uniform(0.3, 0.6), centre, True)                  # grasp
    to(rng.uniform(1.2, 2.0), centre + lift, True)           # lift
    to(rng.uniform(0.0, 0.5), centre + lift, True)
    to(rng.uniform(1.5, 2.5), centre + lift + carry, True)   # carry
    to(rng.uniform(0.0, 0.5), centre + lift + carry, True)
    to(rng.uniform(1.2, 2.0), centre + carry, True)          # set down
    to(rng.uniform(0.3, 0.6), centre + carry, False)         # let go
    return centre + half, centre - half, steps


def hold_forearm_plan(rng, speed):
    """Return (start left, start right, steps) of one forearm hold and wipe."""
    g = tasks.HOLD_FOREARM.geometry
    grasp = _spread(rng, g['grasp'], g['grasp_spread'])
    above = grasp + (0.0, 0.0, 0.04)
    held = grasp + (0.0, 0.0, _between(rng, g['hold_lift_m']))
    offset = rng.uniform(-1.0, 1.0, 3) * np.array(g['wipe_spread'])
    wipe = [np.array(g['wipe_start']) + offset, np.array(g['wipe_end']) + offset]
    ready = wipe[0] + (0.0, 0.0, 0.08)
    leader_start = wipe[0] + (0.0, -0.04, 0.12)
    steps = []

    def to(duration_s, left, right, left_closed):
        steps.append(Step(duration_s / speed, left, right, left_closed, False))
    to(rng.uniform(0.3, 0.8), above, leader_start, False)
    to(rng.uniform(0.8, 1.2), grasp, leader_start, False)        # take the wrist
    to(rng.uniform(0.3, 0.5), grasp, leader_start, True)
    to(rng.uniform(1.5, 2.2), held, ready, True)                 # lift; the leader gets ready
    to(rng.uniform(0.6, 1.0), held, wipe[0], True)               # the leader goes down
    strokes = rng.integers(g['strokes'][0], g['strokes'][1] + 1)
    for stroke in range(strokes):
        to(rng.uniform(0.9, 1.4), held, wipe[(stroke + 1) % 2], True)
    to(rng.uniform(1.0, 1.4), held, leader_start, True)          # the leader leaves
    to(rng.uniform(1.5, 2.0), grasp, leader_start, True)         # lay the forearm down
    to(rng.uniform(0.3, 0.5), grasp, leader_start, False)
    to(rng.uniform(0.8, 1.2), above, leader_start, False)
    return above, leader_start, steps


PLANS = {'carry_tray': carry_tray_plan, 'hold_forearm': hold_forearm_plan}


def _demo(key, plan, rate_hz, noise_rng):
    start_left, start_right, steps = plan
    t, left, right, left_closed, right_closed = sample(steps, start_left, start_right, rate_hz)
    if noise_rng is not None:
        if tasks.TASKS[key].leader == 'right':
            right = right + hand_noise(noise_rng, t)
        else:
            left = left + hand_noise(noise_rng, t)
    return Demo(t, ArmPath('left').solve(left), ArmPath('right').solve(right),
                left_closed, right_closed)


def demonstrate(key, seed, rate_hz=50.0):
    """Return one varied execution (a Demo) of task `key`; the same seed gives the same one.

    Raises:
        KeyError: no such task.
    """
    rng = np.random.default_rng([seed, list(tasks.TASKS).index(key)])
    speed = rng.uniform(*SPEED)
    return _demo(key, PLANS[key](rng, speed), rate_hz, rng)


def unfamiliar(key, seed, rate_hz=50.0):
    """Return a Demo whose leader reaches high and out to its side, a motion the task never
    shows, starting from the task's start; the follower holds its start pose, gripper open."""
    rng = np.random.default_rng([seed, list(tasks.TASKS).index(key), 1])
    start_left, start_right, _ = PLANS[key](np.random.default_rng([0, 0]), 1.0)
    speed = rng.uniform(*SPEED)
    mirror = np.array([1.0, -1.0, 1.0]) if tasks.TASKS[key].leader == 'left' else 1.0
    reach = [np.array(p) * mirror + rng.uniform(-0.03, 0.03, 3) for p in UNFAMILIAR_REACH]
    leader_start = start_right if tasks.TASKS[key].leader == 'right' else start_left
    steps = []
    for duration_s, to in ((0.5, leader_start), (2.0, reach[0]), (1.0, reach[1]),
                           (1.5, reach[0]), (2.0, leader_start)):
        right, left = (to, start_left) if tasks.TASKS[key].leader == 'right' \
            else (start_right, to)
        steps.append(Step(duration_s / speed, left, right, False, False))
    return _demo(key, (start_left, start_right, steps), rate_hz, rng)


def transfer(frm, to, speed_rad_s, rate_hz=50.0):
    """Return a Demo moving both arms in joint space from Demo frm's last pose to Demo to's
    first, no joint faster than speed_rad_s (minimum jerk: its peak is 1.875 x the mean)."""
    ends = {s: (getattr(frm, s)[-1], getattr(to, s)[0]) for s in ('left', 'right')}
    span = max(np.abs(b - a).max() for a, b in ends.values())
    t = np.arange(0.0, max(1.0, 1.875 * span / speed_rad_s) + 0.5 / rate_hz, 1.0 / rate_hz)
    s = minimum_jerk(t / t[-1])[:, None]
    arms = {side: a + s * (b - a) for side, (a, b) in ends.items()}
    still = np.zeros(len(t), bool)
    return Demo(t, arms['left'], arms['right'], still, still)
