"""The study's four tasks: their rules, timeouts and targets drawn per seed (docs/study.md).

Goals are for a gripper's tool point (baxter_description.gripper_link) in Baxter's base frame
(x forward, y to Baxter's left, z up; m). Every target lies over the patient in the region where
Baxter's arms reach with the gripper pointing down inside the puppet's default angle range
(assist.arm_path's bounds: what every study device can show, the puppet too), the whole arm
7 cm clear of config/zones.yaml's zones at least; tests/unit/test_tasks_targets.py checks 100
seeds with ArmIK and the zones. A trial is a list of stages: each names the goals that must be reached together (two
for bimanual) and how (`hold`, `grasp`, `release`); task_judge.TrialJudge walks through them.
Pure: numpy only.
"""
import collections
import functools
import math

import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.assist import arm_path, tasks as assist_tasks

Goal = collections.namedtuple('Goal', 'arm xyz quat closed tolerance_m tolerance_rad hold_s')
Goal.__doc__ = """One target of a gripper's tool point: arm 'left'|'right'; xyz (3 m, base);
quat (x, y, z, w) or None (any orientation); closed: the gripper state wanted there (True grasp,
False open/release, None any); tolerance_m; tolerance_rad (None: any orientation); hold_s."""
Stage = collections.namedtuple('Stage', 'kind goals text')
Stage.__doc__ = """One step of a trial: kind 'hold' (all goals within tolerance together for
their hold_s), 'grasp' (arrive open, close there) or 'release' (open the carrying gripper
there); goals, a tuple of Goals; text, what to do (the judge's detail)."""
Trial = collections.namedtuple('Trial', 'task seed practice plan')
Trial.__doc__ = """One trial: task (interface.STUDY_TASKS), seed, practice (bool), plan (a tuple
of Stages)."""

TIMEOUT_S = {'reach_hold': 120.0, 'trace': 120.0, 'pick_place': 120.0, 'bimanual': 120.0}
ARMS = {'reach_hold': ('right',), 'trace': ('right',), 'pick_place': ('right',),
        'bimanual': ('left', 'right')}

# reach_hold: 3 poses in this box (right arm), each at least REACH_APART_M from the one before;
# the gripper points down, turned about the vertical by up to REACH_TURN_RAD from how it is at
# Baxter's neutral pose (where every trial starts), so that a device that keeps the gripper's
# orientation (the gamepad) stays within the tolerance.
REACH_BOX = ((0.73, 0.80), (-0.45, 0.0), (0.10, 0.20))
REACH_APART_M = 0.12
REACH_TURN_RAD = math.radians(10.0)
REACH_TOLERANCE_M, REACH_TOLERANCE_RAD, REACH_HOLD_S = 0.03, math.radians(20.0), 1.0
REACH_POSES = 3
# trace: 5 waypoints over the patient from the chest to the legs (right arm), zigzagging
# TRACE_ZIGZAG_M about a line from x TRACE_X, TRACE_STEP_M apart along y from TRACE_START_Y and
# TRACE_DRIFT_M further from Baxter at its end (where the right arm reaches further out).
TRACE_X, TRACE_ZIGZAG_M, TRACE_DRIFT_M = (0.75, 0.77), 0.025, 0.08
TRACE_START_Y, TRACE_STEP_M, TRACE_Z = (0.0, 0.06), (0.11, 0.13), (0.09, 0.15)
TRACE_WAYPOINTS, TRACE_TOLERANCE_M = 5, 0.04
# pick_place: the object stands on spot A, is carried to spot B (right arm); which of the two
# places is A is drawn per seed.
PICK_PLACES = (((0.80, -0.40, 0.10), (0.03, 0.04, 0.02)),
               ((0.76, -0.02, 0.10), (0.03, 0.04, 0.02)))
PICK_TOLERANCE_M, PLACE_TOLERANCE_M = 0.03, 0.04
# bimanual: the tray of assist.tasks' carry_tray (handles 0.40 m apart, on a stand over the bed)
# but lower and nearer, so that it can be lifted by BIMANUAL_LIFT_M within the puppet's range.
# It stands on Baxter's midline (drawn along x and z only): one SpaceMouse moves the arms
# mirrored about it, from the mirrored start every trial has (Baxter's neutral pose).
TRAY = assist_tasks.CARRY_TRAY.geometry
TRAY_WIDTH_M = TRAY['tray_width_m']
TRAY_CENTRE, TRAY_SPREAD = (0.77, 0.0, 0.08), (0.02, 0.0, 0.01)
BIMANUAL_LIFT_M, BIMANUAL_TOLERANCE_M, BIMANUAL_HOLD_S, BIMANUAL_UP_HOLD_S = 0.15, 0.03, 1.0, 0.5
PRACTICE_SALT = 7919   # a practice trial draws from another stream than the trial of its seed


def _rz(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _draw(rng, box):
    return np.array([rng.uniform(lo, hi) for lo, hi in box])


def _spread(rng, centre, spread):
    return np.array(centre) + rng.uniform(-1.0, 1.0, 3) * np.array(spread)


def neutral_rotation(side):
    """Return the 3x3 orientation of a side's gripper at Baxter's neutral pose."""
    q = [bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES]
    return assist_tasks.arm_kinematics(side).forward(np.array(q))[0][:3, :3]


def angle_between(r_1, r_2):
    """Return the angle (rad) of the rotation between two 3x3 orientations."""
    return math.acos(max(-1.0, min(1.0, (np.trace(r_1 @ r_2.T) - 1.0) / 2.0)))


def oriented_pose(side, xyz, turn_rad):
    """Return (joint angles, 3x3 orientation): the gripper at xyz pointing down as far as the
    puppet's range allows (assist.arm_path), then turned by its last joint (w2) to be nearest the
    neutral pose's orientation turned by turn_rad about the vertical.

    Raises:
        arm_path.PathError: xyz is out of reach inside the bounds.
    """
    path = arm_path.ArmPath(side)
    q = path.solve([xyz])[0]
    arm = assist_tasks.arm_kinematics(side)
    wanted = _rz(turn_rad) @ neutral_rotation(side)
    best = None
    for w2 in np.linspace(path.lower[6], path.upper[6], 121):
        q[6] = w2
        rotation = arm.forward(q)[0][:3, :3]
        miss = angle_between(rotation, wanted)
        if best is None or miss < best[0]:
            best = (miss, q.copy(), rotation)
    return best[1], best[2]


def _reach_hold(rng):
    stages, last = [], None
    for n in range(REACH_POSES):
        xyz = _draw(rng, REACH_BOX)
        while last is not None and np.linalg.norm(xyz - last) < REACH_APART_M:
            xyz = _draw(rng, REACH_BOX)
        _, rotation = oriented_pose('right', xyz, rng.uniform(-REACH_TURN_RAD, REACH_TURN_RAD))
        goal = Goal('right', tuple(xyz), bd.matrix_quaternion(rotation), None,
                    REACH_TOLERANCE_M, REACH_TOLERANCE_RAD, REACH_HOLD_S)
        stages.append(Stage('hold', (goal,), 'pose %d of %d: reach it and hold %g s'
                            % (n + 1, REACH_POSES, REACH_HOLD_S)))
        last = xyz
    return stages


def _trace(rng):
    x, y, step = rng.uniform(*TRACE_X), rng.uniform(*TRACE_START_Y), rng.uniform(*TRACE_STEP_M)
    side = rng.choice((-1.0, 1.0))
    stages = []
    for n in range(TRACE_WAYPOINTS):
        along = n / (TRACE_WAYPOINTS - 1.0)
        xyz = (x + TRACE_DRIFT_M * along + side * TRACE_ZIGZAG_M * (-1) ** n, y - n * step,
               rng.uniform(*TRACE_Z))
        goal = Goal('right', xyz, None, None, TRACE_TOLERANCE_M, None, 0.0)
        stages.append(Stage('hold', (goal,), 'waypoint %d of %d: pass through it'
                            % (n + 1, TRACE_WAYPOINTS)))
    return stages


def _pick_place(rng):
    order = (0, 1) if rng.uniform() < 0.5 else (1, 0)
    a, b = (tuple(_spread(rng, *PICK_PLACES[i])) for i in order)
    return [Stage('grasp', (Goal('right', a, None, True, PICK_TOLERANCE_M, None, 0.0),),
                  'spot A: arrive with the gripper open, close it'),
            Stage('release', (Goal('right', b, None, False, PLACE_TOLERANCE_M, None, 0.0),),
                  'spot B: open the gripper there')]


def handles(centre):
    """Return {arm: xyz} of the tray's handles about its centre (m)."""
    half = np.array([0.0, TRAY_WIDTH_M / 2.0, 0.0])
    return {'left': np.asarray(centre) + half, 'right': np.asarray(centre) - half}


def _bimanual(rng):
    centre = _spread(rng, TRAY_CENTRE, TRAY_SPREAD)
    up = centre + (0.0, 0.0, BIMANUAL_LIFT_M)
    grip = tuple(Goal(arm, tuple(xyz), None, None, BIMANUAL_TOLERANCE_M, None, BIMANUAL_HOLD_S)
                 for arm, xyz in sorted(handles(centre).items()))
    lift = tuple(Goal(arm, tuple(xyz), None, None, BIMANUAL_TOLERANCE_M, None,
                      BIMANUAL_UP_HOLD_S) for arm, xyz in sorted(handles(up).items()))
    return [Stage('hold', grip, 'both grippers to the handles, hold %g s together'
                  % BIMANUAL_HOLD_S),
            Stage('hold', lift, 'both %g cm up together, hold %g s'
                  % (BIMANUAL_LIFT_M * 100.0, BIMANUAL_UP_HOLD_S))]


_PLANS = {'reach_hold': _reach_hold, 'trace': _trace, 'pick_place': _pick_place,
          'bimanual': _bimanual}


@functools.lru_cache(maxsize=64)
def make_trial(task, seed, practice=False):
    """Return the Trial of a task drawn from seed (the same seed, the same targets).

    Raises:
        KeyError: no such task. ValueError: a negative seed.
    """
    if task not in _PLANS:
        raise KeyError('no study task %r (tasks: %s)' % (task, ', '.join(_PLANS)))
    seeds = [int(seed)] + ([PRACTICE_SALT] if practice else [])
    rng = np.random.default_rng(seeds)
    return Trial(task, int(seed), bool(practice), tuple(_PLANS[task](rng)))
