"""What a trial shows: goals amber then green when met, spots, the carried object, the path."""
import numpy as np
import pytest

from robopuppet.study import task_shapes, tasks
from robopuppet.study.task_judge import TrialJudge


def named(judge):
    return {shape.name: (shape, rgba) for shape, rgba in task_shapes.task_shapes(judge)}


def test_a_goal_turns_green_while_met():
    trial = tasks.make_trial('trace', 1)
    judge = TrialJudge(trial, 0.0)
    goal = trial.plan[0].goals[0]
    shape, rgba = named(judge)['goal 0']
    assert shape.type == 'sphere' and shape.radius == goal.tolerance_m
    assert shape.xyz == pytest.approx(goal.xyz) and rgba == task_shapes.GOAL_RGBA
    bimanual = TrialJudge(tasks.make_trial('bimanual', 1), 0.0)
    left, right = bimanual.trial.plan[0].goals
    bimanual.update(0.1, {'left': (np.array(left.xyz), np.eye(3)),
                          'right': (np.array(right.xyz) + 0.1, np.eye(3))}, {})
    shown = named(bimanual)
    assert shown['goal 0'][1] == task_shapes.REACHED_RGBA
    assert shown['goal 1'][1] == task_shapes.GOAL_RGBA
    tray = shown['bimanual'][0]
    assert tray.type == 'box' and tray.size[1] == pytest.approx(0.4)


def test_pick_place_shows_its_spots_and_the_object_where_it_is():
    trial = tasks.make_trial('pick_place', 2)
    a, b = (stage.goals[0] for stage in trial.plan)
    judge = TrialJudge(trial, 0.0)
    shown = named(judge)
    assert {'spot A', 'spot B', 'pick_place'} <= set(shown)
    assert shown['spot A'][0].xyz[:2] == pytest.approx(a.xyz[:2])
    assert shown['pick_place'][0].xyz == pytest.approx(a.xyz)
    judge.update(0.1, {'right': (np.array(a.xyz), np.eye(3))}, {'right': False})
    judge.update(0.2, {'right': (np.array(a.xyz), np.eye(3))}, {'right': True})
    carried = np.array(b.xyz) + (0.0, 0.0, 0.1)
    judge.update(0.3, {'right': (carried, np.eye(3))}, {'right': True})
    shown = named(judge)
    assert 'spot A' not in shown and 'spot B' in shown
    assert shown['pick_place'][0].xyz == pytest.approx(carried)


def test_the_trace_path_runs_through_the_waypoints_still_ahead():
    trial = tasks.make_trial('trace', 1)
    points = [stage.goals[0].xyz for stage in trial.plan]
    judge = TrialJudge(trial, 0.0)
    assert task_shapes.task_lines(judge) == [('path', points, task_shapes.PATH_RGBA)]
    judge.update(0.1, {'right': (np.array(points[0]), np.eye(3))}, {})
    judge.update(0.2, {'right': (np.array(points[1]), np.eye(3))}, {})
    assert task_shapes.task_lines(judge)[0][1] == points[1:]
    assert task_shapes.task_lines(TrialJudge(tasks.make_trial('reach_hold', 1), 0.0)) == []
