"""The assist's bimanual nursing tasks: their text, geometry in Baxter's base frame and metrics.

The leader is the arm the nurse drives (Baxter's right), the follower the arm the assist drives
(Baxter's left). Positions are of each arm's tool point, `<side>_gripper` (what the stand-in
reports as its endpoint), in Baxter's base frame (x forward, y to Baxter's left, z up; m).
Metrics take MEASURED joint angles over time and return each metric's worst value over the
sequence; Task.bounds holds the limit each must not pass for the task to count as done.
Pure: numpy only.
"""
import collections
import functools
import math

import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_ik import ArmIK

Task = collections.namedtuple('Task', 'key text leader follower bounds geometry')
Task.__doc__ = """One bimanual task.

key: the name commands take ('carry_tray'); text: the episode's task string, exactly;
leader, follower: the Baxter sides ('right', 'left'); bounds: {metric: its largest allowed value};
geometry: {name: number or xyz (m)}, the task's places in Baxter's base frame."""

# The tray: its handles are TRAY_WIDTH_M apart, one in each gripper; it starts on a stand over
# the bed (clear of the patient's keep-out zone by ~8 cm at the lowest start), is lifted,
# carried sideways and forward and set down again.
CARRY_TRAY = Task(
    'carry_tray', 'carry the tray level with both hands', 'right', 'left',
    {'tilt_deg': 10.0, 'hand_distance_error_m': 0.05},
    {'tray_width_m': 0.40,
     'start_centre': (0.80, 0.0, 0.11),     # the tray's centre at the grasp (m), +- start_spread
     'start_spread': (0.03, 0.04, 0.02),
     'lift_m': (0.08, 0.14),                # lift, range drawn per execution
     'carry_sideways_m': (-0.08, 0.08),     # along y
     'carry_forward_m': (0.0, 0.05)})       # along x

# The patient's forearm: the follower takes the wrist from above and lifts it to the hold point;
# the leader wipes along the wiping line under the lifted forearm (nearer to Baxter than the
# hold, so that the two grippers never meet), several strokes, then leaves, and the follower
# lays the forearm down again. Places lie where both arms reach with the gripper pointing down
# inside the puppet's angle range; heights keep the grippers clear of the patient's keep-out
# zone (config/zones.yaml's patient body reaches z -0.025).
HOLD_FOREARM = Task(
    'hold_forearm', 'hold the forearm up and wipe under it', 'right', 'left',
    {'hold_drift_m': 0.04, 'lift_shortfall_m': 0.02},
    {'grasp': (0.84, 0.14, 0.09),            # over the wrist (m), +- grasp_spread
     'grasp_spread': (0.03, 0.03, 0.01),
     'hold_lift_m': (0.13, 0.16),            # lift above the grasp, range per execution
     'lifted_z_m': 0.20,                     # the forearm counts as held up above this height
     'wipe_start': (0.70, 0.02, 0.07),       # the wiping line: start and end (m)
     'wipe_end': (0.70, 0.20, 0.07),
     'wipe_spread': (0.03, 0.03, 0.01),
     'wipe_band_m': 0.05,                    # the leader's tip this near the line is wiping
     'strokes': (3, 5)})                     # strokes per execution (end included)

TASKS = collections.OrderedDict((t.key, t) for t in (CARRY_TRAY, HOLD_FOREARM))


def by_text(text):
    """Return the Task whose text is exactly `text`, or None."""
    return next((t for t in TASKS.values() if t.text == text), None)


@functools.lru_cache(maxsize=None)
def arm_kinematics(side):
    """Return the stand-in's ArmIK of one side (its forward kinematics and Jacobian), cached."""
    return ArmIK(bd.load(), side)


def tip_positions(side, angles):
    """Return (N, 3) positions (m, base frame) of a side's tool point at (N, 7) angles (rad)."""
    arm = arm_kinematics(side)
    return np.array([arm.forward(q)[0][:3, 3] for q in np.atleast_2d(angles)])


def _carry_tray(geometry, left_tips, right_tips):
    between = left_tips - right_tips
    level = np.hypot(between[:, 0], between[:, 1])
    tilt = np.degrees(np.arctan2(np.abs(between[:, 2]), level))
    distance = np.linalg.norm(between, axis=1)
    return {'tilt_deg': float(tilt.max()),
            'hand_distance_error_m': float(np.abs(distance - geometry['tray_width_m']).max())}


def wiping(geometry, leader_tips):
    """Return (N,) bool: the leader's tip is within the wipe band of the wiping line."""
    start, end = np.array(geometry['wipe_start']), np.array(geometry['wipe_end'])
    line = end - start
    along = np.clip((leader_tips - start) @ line / (line @ line), 0.0, 1.0)
    nearest = start + along[:, None] * line
    return np.linalg.norm(leader_tips - nearest, axis=1) <= geometry['wipe_band_m']


def _hold_forearm(geometry, left_tips, right_tips):
    wipes = wiping(geometry, right_tips)
    if not wipes.any():   # the leader never wiped: nothing was held for it
        return {'hold_drift_m': math.inf, 'lift_shortfall_m': math.inf}
    held = left_tips[wipes]
    drift = np.linalg.norm(held - held[0], axis=1)
    shortfall = np.maximum(0.0, geometry['lifted_z_m'] - held[:, 2])
    return {'hold_drift_m': float(drift.max()), 'lift_shortfall_m': float(shortfall.max())}


_METRICS = {'carry_tray': _carry_tray, 'hold_forearm': _hold_forearm}


def metrics(key, left_q, right_q):
    """Return {metric: worst value over the sequence} of a task done with these arm motions.

    carry_tray: tilt_deg, the largest angle (deg) of the line between the two tool points from
    the horizontal; hand_distance_error_m, the largest |distance between them - tray width|.
    hold_forearm: over the samples where the leader wipes (its tool point within wipe_band_m of
    the wiping line): hold_drift_m, the largest distance of the follower's tool point from where
    it was at the first of them; lift_shortfall_m, how far (m) it came below lifted_z_m at worst.
    Both are infinite when the leader never wiped.

    Args:
        key: a TASKS key.
        left_q, right_q: (N, 7) measured joint angles (rad) of Baxter's left and right arm.
    Raises:
        KeyError: no such task. ValueError: the sequences are empty or of different lengths.
    """
    task = TASKS[key]
    left_q, right_q = np.atleast_2d(left_q), np.atleast_2d(right_q)
    if len(left_q) == 0 or left_q.shape != right_q.shape or left_q.shape[1] != 7:
        raise ValueError('need two (N, 7) joint sequences of one length, got %s and %s'
                         % (left_q.shape, right_q.shape))
    return _METRICS[key](task.geometry, tip_positions('left', left_q),
                         tip_positions('right', right_q))


def within_bounds(key, values):
    """Return {metric: True when its value is within the task's bound}."""
    return {name: values[name] <= limit for name, limit in TASKS[key].bounds.items()}
