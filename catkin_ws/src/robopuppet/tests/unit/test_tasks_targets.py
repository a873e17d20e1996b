"""The study tasks' targets: drawn per seed, reachable inside the puppet's angle range (ArmIK)
and clear of the keep-out zones (the whole arm's capsules), for 100 seeds of every task."""
import functools
import os

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.assist.arm_path import ArmPath, joint_bounds
from robopuppet.baxter_sim.baxter_ik import NS_MAP_SEEDS, ArmIK, quaternion_matrix
from robopuppet.study import tasks
from robopuppet.world import arm_capsules, zones

PACKAGE = os.path.join(os.path.dirname(__file__), '..', '..')
CLEARANCE_M = 0.05   # every capsule of the arm this far from every zone at least


@functools.lru_cache(maxsize=None)
def kit(side):
    """Return (ArmIK bounded to the puppet's range, ArmPath, ZoneGuard) of a side."""
    ik = ArmIK(bd.load(), side)
    ik.lower, ik.upper = joint_bounds(side)
    guard = zones.ZoneGuard(arm_capsules.ArmCapsules(bd.load(), bd.read_urdf(), side),
                            zones.load_zones(os.path.join(PACKAGE, 'config', 'zones.yaml')))
    return ik, ArmPath(side), guard


def solution(goal):
    """Return joint angles reaching a goal within the puppet's range, or None."""
    ik, path, _ = kit(goal.arm)
    q = path.solve([goal.xyz])[0]
    if goal.quat is None:
        return q
    mirror = np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0]) if goal.arm == 'left' else 1.0
    neutral = [bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES]
    for seed in [q, neutral] + [np.array(s) * mirror for s in NS_MAP_SEEDS]:
        found = ik.solve(goal.xyz, quaternion_matrix(goal.quat), seed)
        if found is not None:
            return found
    return None


def check_reachable(task, seeds):
    for seed in seeds:
        for stage in tasks.make_trial(task, seed).plan:
            for goal in stage.goals:
                assert goal.arm in tasks.ARMS[task]
                q = solution(goal)
                assert q is not None, (task, seed, goal)
                ik, _, guard = kit(goal.arm)
                assert np.all(q >= ik.lower - 1e-9) and np.all(q <= ik.upper + 1e-9)
                pose = ik.forward(q)[0]
                assert np.linalg.norm(pose[:3, 3] - goal.xyz) < 1e-3
                if goal.quat is not None:
                    turn = tasks.angle_between(pose[:3, :3], quaternion_matrix(goal.quat))
                    assert turn < 0.01
                assert guard.clearance(q).min() > CLEARANCE_M, (task, seed, goal)


@pytest.mark.parametrize('task', sorted(tasks.ARMS))
def test_targets_reachable_and_clear_of_the_zones(task):
    check_reachable(task, range(5))


@pytest.mark.slow
@pytest.mark.parametrize('task', sorted(tasks.ARMS))
def test_targets_reachable_and_clear_for_100_seeds(task):
    check_reachable(task, range(100))


def targets(trial):
    return [goal.xyz for stage in trial.plan for goal in stage.goals]


@pytest.mark.parametrize('task', sorted(tasks.ARMS))
def test_the_same_seed_gives_the_same_targets_another_seed_others(task):
    tasks.make_trial.cache_clear()
    first = targets(tasks.make_trial(task, 11))
    tasks.make_trial.cache_clear()
    assert targets(tasks.make_trial(task, 11)) == first
    assert targets(tasks.make_trial(task, 12)) != first
    assert targets(tasks.make_trial(task, 11, practice=True)) != first


def test_the_task_shapes():
    reach = tasks.make_trial('reach_hold', 1)
    assert len(reach.plan) == 3
    for stage in reach.plan:
        (goal,) = stage.goals
        assert goal.quat is not None and goal.tolerance_m == 0.03 and goal.hold_s == 1.0
        assert goal.tolerance_rad == pytest.approx(np.radians(20.0))
    trace = tasks.make_trial('trace', 1)
    assert len(trace.plan) == 5 and all(s.goals[0].tolerance_m == 0.04 for s in trace.plan)
    pick = tasks.make_trial('pick_place', 1)
    assert [s.kind for s in pick.plan] == ['grasp', 'release']
    assert [s.goals[0].closed for s in pick.plan] == [True, False]
    grip, lift = tasks.make_trial('bimanual', 1).plan
    left, right = grip.goals
    assert np.linalg.norm(np.subtract(left.xyz, right.xyz)) == pytest.approx(0.40)
    for before, after in zip(grip.goals, lift.goals):
        assert np.subtract(after.xyz, before.xyz) == pytest.approx([0.0, 0.0, 0.15])


def test_reach_hold_poses_are_within_15_degrees_of_the_neutral_grippers():
    """A device that keeps the gripper as it starts (the gamepad) is within the tolerance."""
    neutral = tasks.neutral_rotation('right')
    for seed in range(20):
        for stage in tasks.make_trial('reach_hold', seed).plan:
            turn = tasks.angle_between(quaternion_matrix(stage.goals[0].quat), neutral)
            assert np.degrees(turn) < 15.0


def test_an_unknown_task_is_refused():
    with pytest.raises(KeyError):
        tasks.make_trial('juggle', 1)
