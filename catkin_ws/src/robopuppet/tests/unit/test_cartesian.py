"""Unit tests of study.cartesian: a device's twist as a joint step, and a pose solved."""
import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_ik import rotation_error
from robopuppet.study.cartesian import CartesianArm

NEUTRAL = [bd.NEUTRAL_POSE[s] for s in bd.ARM_JOINT_SUFFIXES]
BENT = [0.3, -0.3, 0.0, 1.6, 0.0, 0.3, 0.0]   # the tip at (0.52, -0.50, -0.31) m: room all round


@pytest.fixture(scope='module')
def arm():
    return CartesianArm('right')


@pytest.mark.parametrize('axis', range(3))
@pytest.mark.parametrize('sign', [1.0, -1.0])
def test_a_step_moves_the_tip_the_way_asked_and_keeps_the_orientation(arm, axis, sign):
    q = np.array(BENT)
    xyz0, rot0 = arm.tip(q)
    twist = np.zeros(6)
    twist[axis] = 0.1 * sign
    for _ in range(50):   # 1 s at 50 Hz
        q = arm.step(q, twist, 0.02)
    xyz, rot = arm.tip(q)
    moved = xyz - xyz0
    assert moved[axis] * sign == pytest.approx(0.1, abs=0.005)
    assert np.linalg.norm(np.delete(moved, axis)) < 0.005
    assert np.linalg.norm(rotation_error(rot0, rot)) < 0.01


def test_a_turn_turns_the_gripper_about_that_axis(arm):
    q = np.array(BENT)
    rot0 = arm.tip(q)[1]
    for _ in range(25):
        q = arm.step(q, [0, 0, 0, 0, 0, 0.4], 0.02)
    turned = rotation_error(arm.tip(q)[1], rot0)   # from now back to the start
    assert turned == pytest.approx([0.0, 0.0, 0.2], abs=0.01)


def test_steps_stay_within_the_joint_limits(arm):
    q = np.array(NEUTRAL)
    for _ in range(100):   # far beyond the reach: 10 m asked
        q = arm.step(q, [1.0, -1.0, 1.0, 0, 0, 0], 0.1)
        assert np.all(q >= arm.lower) and np.all(q <= arm.upper) and np.all(np.isfinite(q))


def test_no_twist_leaves_the_angles_and_clips_them(arm):
    assert np.allclose(arm.step(NEUTRAL, np.zeros(6), 0.02), NEUTRAL)
    beyond = np.array(NEUTRAL)
    beyond[0] = 10.0
    assert arm.step(beyond, np.zeros(6), 0.02)[0] == arm.upper[0]


def test_solve_reaches_a_pose_and_refuses_the_unreachable_and_nan(arm):
    q = np.array(NEUTRAL)
    xyz, rot = arm.tip(q)
    quaternion = bd.matrix_quaternion(rot)
    solution = arm.solve(xyz + [-0.05, 0.0, 0.05], quaternion, q)
    assert solution is not None
    assert np.allclose(arm.tip(solution)[0], xyz + [-0.05, 0.0, 0.05], atol=1e-3)
    assert arm.solve(xyz + [5.0, 0.0, 0.0], quaternion, q) is None
    assert arm.solve([np.nan, 0.0, 0.0], quaternion, q) is None
    assert arm.solve(xyz, (0.0, 0.0, 0.0, 0.0), q) is None


def test_solve_near_reaches_the_pose_within_narrower_bounds_or_says_none(arm):
    q_goal = np.array([1.2, -0.7, 0.1, 0.9, -0.3, 1.45, 1.3])   # w1 near a puppet's limit
    xyz, rotation = arm.tip(q_goal)
    q = arm.solve_near(xyz, rotation, np.array(NEUTRAL))
    assert np.linalg.norm(arm.tip(q)[0] - xyz) < 0.004 and q[5] > 1.3
    bounded = CartesianArm('right', bounds=(arm.lower, np.minimum(arm.upper, 1.3)))
    assert bounded.solve_near(xyz, rotation, np.array(NEUTRAL)) is None   # w1 > 1.3 needed
    assert np.all(bounded.clip(np.full(7, 3.0)) <= 1.3)
