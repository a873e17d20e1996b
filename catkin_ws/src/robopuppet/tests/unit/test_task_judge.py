"""The trial judge: holds, orientation, order, grasp and release, both arms together, timeout;
and tips_of, the tool points of /robot/joint_states."""
import math

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_ik import quaternion_matrix
from robopuppet.study import tasks
from robopuppet.study.task_judge import TrialJudge, tips_of

T0 = 100.0
FAR = (np.array([0.5, -0.9, 0.4]), np.eye(3))


def rz(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def at(goal, offset=(0.0, 0.0, 0.0), turn_rad=0.0):
    """Return a tip at a goal (moved by offset m, turned about the vertical by turn_rad)."""
    rotation = np.eye(3) if goal.quat is None else quaternion_matrix(goal.quat)
    return np.array(goal.xyz) + offset, rz(turn_rad) @ rotation


def run(judge, times, tips, closed=None):
    for t in times:
        judge.update(T0 + t, tips, closed or {})


def steps(start, stop, dt=0.05):
    return np.arange(start, stop + 1e-9, dt)


def test_a_pose_counts_only_after_holding_it_within_tolerance_for_hold_s():
    trial = tasks.make_trial('reach_hold', 4)
    judge = TrialJudge(trial, T0)
    first = trial.plan[0].goals[0]
    run(judge, steps(0.0, 0.9), {'right': at(first)})
    assert judge.stage == 0 and 'hold 0.1 s more' in judge.detail
    run(judge, [0.95], {'right': FAR})                   # a break starts the hold again
    run(judge, steps(1.0, 1.95), {'right': at(first, (0.02, 0.0, 0.0))})
    assert judge.stage == 0
    run(judge, [2.0], {'right': at(first, (0.02, 0.0, 0.0))})
    assert judge.stage == 1 and judge.goals() == list(trial.plan[1].goals)
    run(judge, steps(2.05, 4.0), {'right': at(trial.plan[1].goals[0], (0.0, 0.035, 0.0))})
    assert judge.stage == 1                             # 3.5 cm off: not within 3 cm


def test_a_wrong_orientation_does_not_count():
    trial = tasks.make_trial('reach_hold', 4)
    first = trial.plan[0].goals[0]
    judge = TrialJudge(trial, T0)
    run(judge, steps(0.0, 3.0), {'right': at(first, turn_rad=math.radians(25.0))})
    assert judge.stage == 0 and judge.reached() == [False]
    run(judge, steps(3.05, 4.05), {'right': at(first, turn_rad=math.radians(15.0))})
    assert judge.stage == 1


def test_trace_waypoints_count_only_in_their_order():
    trial = tasks.make_trial('trace', 2)
    points = [stage.goals[0] for stage in trial.plan]
    judge = TrialJudge(trial, T0)
    judge.update(T0 + 0.1, {'right': at(points[1])}, {})   # the second first: not counted
    judge.update(T0 + 0.2, {'right': at(points[0])}, {})
    assert judge.stage == 1
    judge.update(T0 + 0.3, {'right': at(points[2])}, {})
    assert judge.stage == 1
    for n, goal in enumerate(points[1:]):
        judge.update(T0 + 1.0 + n, {'right': at(goal, (0.0, 0.0, 0.035))}, {})
    assert judge.done and judge.success


def pick(seed=3):
    trial = tasks.make_trial('pick_place', seed)
    return trial, trial.plan[0].goals[0], trial.plan[1].goals[0]


def test_a_grasp_needs_the_gripper_open_on_arrival_then_closed():
    trial, a, _ = pick()
    judge = TrialJudge(trial, T0)
    judge.update(T0 + 0.1, {'right': at(a)}, {'right': True})    # arrived closed
    judge.update(T0 + 0.2, {'right': at(a)}, {'right': True})
    assert judge.stage == 0 and not judge.carried()
    judge.update(T0 + 0.3, {'right': at(a)}, {'right': False})   # opened there ...
    judge.update(T0 + 0.4, {'right': FAR}, {'right': False})     # ... but left
    judge.update(T0 + 0.5, {'right': FAR}, {'right': True})
    judge.update(T0 + 0.6, {'right': at(a)}, {'right': True})
    assert not judge.carried()
    judge.update(T0 + 0.7, {'right': at(a, (0.02, 0.0, 0.0))}, {'right': False})
    judge.update(T0 + 0.8, {'right': at(a, (0.0, 0.02, 0.0))}, {'right': True})
    assert judge.carried() and judge.stage == 1


def grasped(judge, a):
    judge.update(T0 + 0.1, {'right': at(a)}, {'right': False})
    judge.update(T0 + 0.2, {'right': at(a)}, {'right': True})
    assert judge.carried()


def test_the_object_follows_the_carrying_gripper_and_a_release_at_b_succeeds():
    trial, a, b = pick()
    judge = TrialJudge(trial, T0)
    assert judge.objects() == [('pick_place', pytest.approx(a.xyz))]
    grasped(judge, a)
    middle = (np.array(a.xyz) + b.xyz) / 2.0
    judge.update(T0 + 1.0, {'right': (middle, np.eye(3))}, {'right': True})
    assert judge.objects()[0][1] == pytest.approx(middle)
    judge.update(T0 + 2.0, {'right': at(b, (0.0, 0.035, 0.0))}, {'right': True})
    assert not judge.done
    judge.update(T0 + 2.1, {'right': at(b, (0.0, 0.035, 0.0))}, {'right': False})
    assert judge.done and judge.success and judge.end_t == T0 + 2.1
    assert not judge.carried()


def test_a_release_away_from_b_drops_the_object_and_fails():
    trial, a, b = pick()
    judge = TrialJudge(trial, T0)
    grasped(judge, a)
    judge.update(T0 + 1.0, {'right': at(b, (0.10, 0.0, 0.0))}, {'right': False})
    assert judge.done and not judge.success and 'dropped 10 cm from spot B' in judge.detail


def test_bimanual_needs_both_handles_held_together():
    trial = tasks.make_trial('bimanual', 5)
    grip, lift = trial.plan
    left, right = grip.goals
    judge = TrialJudge(trial, T0)
    run(judge, steps(0.0, 2.0), {'left': at(left), 'right': FAR})
    run(judge, steps(2.05, 4.0), {'left': FAR, 'right': at(right)})
    assert judge.stage == 0
    run(judge, steps(4.05, 5.05), {'left': at(left), 'right': at(right)})
    assert judge.stage == 1
    up_left, up_right = lift.goals
    run(judge, steps(5.1, 7.0), {'left': at(up_left), 'right': at(right)})
    assert not judge.done
    tray = judge.objects()[0][1]
    assert tray == pytest.approx((np.array(up_left.xyz) + right.xyz) / 2.0)
    run(judge, steps(7.05, 7.55), {'left': at(up_left), 'right': at(up_right)})
    assert judge.done and judge.success


def test_a_trial_not_done_by_its_timeout_fails():
    trial = tasks.make_trial('trace', 1)
    judge = TrialJudge(trial, T0)
    timeout = tasks.TIMEOUT_S['trace']
    judge.update(T0 + timeout - 0.01, {'right': FAR}, {})
    assert not judge.done
    judge.update(T0 + timeout, {'right': FAR}, {})
    assert judge.done and not judge.success and 'timed out' in judge.detail
    assert judge.goals() == []
    judge.update(T0 + timeout + 1.0, {'right': at(trial.plan[0].goals[0])}, {})
    assert not judge.success


def test_tips_of_poses_each_complete_arm():
    description = bd.load()
    names, positions = [], []
    for side in ('left', 'right'):
        for suffix in bd.ARM_JOINT_SUFFIXES:
            names.append('%s_%s' % (side, suffix))
            positions.append(bd.NEUTRAL_POSE[suffix] + 0.1)
    tips = tips_of(description, names, positions)
    for side in ('left', 'right'):
        xyz, quat = description.pose(dict(zip(names, positions)), bd.gripper_link(side))
        assert tips[side][0] == pytest.approx(xyz)
        assert tips[side][1] == pytest.approx(quaternion_matrix(quat))
    positions[names.index('left_e1')] = float('nan')
    assert set(tips_of(description, names[1:], positions[1:])) == {'right'}
    assert set(tips_of(description, names, positions)) == {'right'}
