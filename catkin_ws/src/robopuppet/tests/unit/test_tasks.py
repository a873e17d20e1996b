"""The assist's tasks: their texts, and metrics that measure what the task asks of both arms."""
import math

import numpy as np
import pytest

from robopuppet.assist import tasks
from robopuppet.assist.arm_path import MIRROR

RIGHT_POSE = np.array([0.6, -0.7, 0.0, 1.2, 0.0, 0.9, 0.0])


def test_each_task_is_found_by_its_exact_text_only():
    for task in tasks.TASKS.values():
        assert tasks.by_text(task.text) is task
        assert tasks.by_text(task.text.upper()) is None
        assert tasks.by_text(task.text + ' ') is None
        assert (task.leader, task.follower) == ('right', 'left')
        assert set(task.bounds) and all(limit > 0 for limit in task.bounds.values())
    assert tasks.by_text('') is None


def test_mirrored_arms_hold_the_tray_level_and_their_distance_is_measured():
    left = RIGHT_POSE * MIRROR     # Baxter's arms are mirror images: the tips mirror in y
    right_tip = tasks.tip_positions('right', RIGHT_POSE)[0]
    values = tasks.metrics('carry_tray', [left], [RIGHT_POSE])
    assert values['tilt_deg'] == pytest.approx(0.0, abs=1e-6)
    width = tasks.CARRY_TRAY.geometry['tray_width_m']
    assert values['hand_distance_error_m'] == pytest.approx(abs(2 * abs(right_tip[1]) - width))


def test_a_raised_hand_tilts_the_tray_and_the_worst_sample_counts():
    left = RIGHT_POSE * MIRROR
    raised = left.copy()
    raised[1] -= 0.2               # the left shoulder lifts: its tip rises
    tips = tasks.tip_positions('left', [left, raised])
    right_tip = tasks.tip_positions('right', RIGHT_POSE)[0]
    between = tips[1] - right_tip
    expected = math.degrees(math.atan2(abs(between[2]), math.hypot(*between[:2])))
    values = tasks.metrics('carry_tray', [left, raised, left], [RIGHT_POSE] * 3)
    assert values['tilt_deg'] == pytest.approx(expected) and expected > 5.0


def test_hold_metrics_are_infinite_when_the_leader_never_wipes():
    values = tasks.metrics('hold_forearm', [RIGHT_POSE * MIRROR] * 3, [RIGHT_POSE] * 3)
    assert values == {'hold_drift_m': math.inf, 'lift_shortfall_m': math.inf}
    assert not any(tasks.within_bounds('hold_forearm', values).values())


def test_wiping_is_near_the_wiping_line_only():
    g = tasks.HOLD_FOREARM.geometry
    start, end = np.array(g['wipe_start']), np.array(g['wipe_end'])
    band = g['wipe_band_m']
    points = [start, (start + end) / 2 + (0, 0, band * 0.9), end + (0, band * 0.9, 0),
              end + (0, band * 1.1, 0), start + (0, 0, band * 1.1)]
    assert tasks.wiping(g, np.array(points)).tolist() == [True, True, True, False, False]


def test_metrics_refuse_sequences_that_do_not_match():
    with pytest.raises(ValueError):
        tasks.metrics('carry_tray', np.zeros((3, 7)), np.zeros((2, 7)))
    with pytest.raises(ValueError):
        tasks.metrics('carry_tray', np.zeros((0, 7)), np.zeros((0, 7)))
    with pytest.raises(KeyError):
        tasks.metrics('juggle', np.zeros((1, 7)), np.zeros((1, 7)))
