"""A trial's measures: path, idle time, jerk, zone time, clutches, completion."""
import numpy as np
import pytest

from robopuppet.assist.demonstration import minimum_jerk
from robopuppet.study import metrics, tasks
from robopuppet.study.task_judge import TrialJudge

RATE_HZ = 100.0
START = np.array([0.75, -0.3, 0.12])


def feed(measure, t, xyz, following=None, zone_held=None, arms=('right',)):
    """Update measure with tips at xyz (N, 3) at times t (each arm the same, y mirrored)."""
    for n, (when, here) in enumerate(zip(t, xyz)):
        tips = {arm: (here * ((1, -1, 1) if arm == 'left' else 1), np.eye(3)) for arm in arms}
        measure.update(when, tips, {a: following[n] if following else True for a in arms},
                       {a: zone_held[n] if zone_held else False for a in arms}, {})


def trial(task='reach_hold'):
    return tasks.make_trial(task, 1)


def test_the_path_of_a_straight_motion_is_its_length():
    measure = metrics.TrialMetrics(trial(), 0.0)
    t = np.arange(0.0, 3.0, 1.0 / RATE_HZ)
    xyz = START + np.outer(minimum_jerk(t / t[-1]), [0.3, 0.0, 0.0])
    feed(measure, t, xyz)
    assert measure.row()['path_m'] == pytest.approx(0.3, abs=1e-6)


def test_bimanual_sums_both_arms_paths():
    measure = metrics.TrialMetrics(trial('bimanual'), 0.0)
    t = np.arange(0.0, 2.0, 1.0 / RATE_HZ)
    feed(measure, t, START + np.outer(t / t[-1], [0.0, 0.0, 0.15]), arms=('left', 'right'))
    assert measure.row()['path_m'] == pytest.approx(0.30, abs=1e-6)


def test_a_pause_is_idle_time_and_motion_is_not():
    measure = metrics.TrialMetrics(trial(), 0.0)
    t = np.arange(0.0, 4.0, 1.0 / RATE_HZ)
    # 0.1 m/s for 1 s, still for 2 s, 0.1 m/s again for 1 s
    along = np.clip(t, 0.0, 1.0) * 0.1 + np.clip(t - 3.0, 0.0, 1.0) * 0.1
    feed(measure, t, START + np.outer(along, [1.0, 0.0, 0.0]))
    assert measure.row()['idle_s'] == pytest.approx(2.0, abs=0.12)


def test_a_jerky_motion_has_more_jerk_than_a_minimum_jerk_one():
    t = np.arange(0.0, 2.0, 1.0 / RATE_HZ)
    smooth = START + np.outer(minimum_jerk(t / t[-1]), [0.3, 0.0, 0.0])
    # The same reach in four stop-and-go jolts (each a minimum-jerk quarter of it).
    quarter = minimum_jerk((t * 4.0 / t[-1]) % 1.0) + np.floor(t * 4.0 / t[-1])
    jerky = START + np.outer(np.minimum(quarter / 4.0, 1.0), [0.3, 0.0, 0.0])
    values = []
    for xyz in (smooth, jerky):
        measure = metrics.TrialMetrics(trial(), 0.0)
        feed(measure, t, xyz)
        values.append(measure.row()['jerk'])
    assert 0.0 < values[0] and values[1] > 10.0 * values[0]
    # A minimum-jerk reach of D in T has mean squared jerk 720 D^2 / T^6 (smoothing lowers it).
    assert values[0] == pytest.approx(720.0 * 0.3 ** 2 / t[-1] ** 6, rel=0.2)


def test_zone_time_counts_while_a_task_arm_is_held():
    measure = metrics.TrialMetrics(trial(), 0.0)
    t = np.arange(0.0, 4.0, 0.05)
    held = [1.0 <= when < 2.5 for when in t]
    feed(measure, t, np.tile(START, (len(t), 1)), zone_held=held)
    assert measure.row()['zone_s'] == pytest.approx(1.5)


def test_clutches_count_each_start_of_following():
    measure = metrics.TrialMetrics(trial(), 0.0)
    following = [True, True, False, False, True, True, False, True]
    t = np.arange(len(following)) * 0.1
    feed(measure, t, np.tile(START, (len(t), 1)), following=following)
    assert measure.row()['clutches'] == 2


def test_completion_is_the_judges_end_and_later_updates_are_left_out():
    made = trial('trace')
    judge = TrialJudge(made, 10.0)
    measure = metrics.TrialMetrics(made, 10.0, judge)
    for n, stage in enumerate(made.plan):
        when = 11.0 + n
        tips = {'right': (np.array(stage.goals[0].xyz), np.eye(3))}
        judge.update(when, tips, {})
        measure.update(when, tips, {'right': True}, {'right': False}, {})
    measure.update(20.0, {'right': (START, np.eye(3))}, {'right': True}, {}, {})
    row = measure.row()
    assert row['success'] and row['completion_s'] == pytest.approx(5.0)
    points = np.array([stage.goals[0].xyz for stage in made.plan])
    assert row['path_m'] == pytest.approx(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())
    assert set(row) == {'completion_s', 'success', 'path_m', 'jerk', 'zone_s', 'clutches',
                        'idle_s'}
