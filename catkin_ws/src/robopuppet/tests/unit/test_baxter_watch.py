"""robopuppet.arm.baxter_watch: which of Baxter's poses arm_X believes, and where the arm is now."""
import math

import pytest

from robopuppet import baxter_description
from robopuppet.arm.baxter_watch import MAX_EXTRAPOLATION_S, ROBOT_POSE_MARGIN_RAD, BaxterWatch

LIMITS = {side: baxter_description.arm_limits(side) for side in ('left', 'right')}
POSE = [0.0, -0.5, 0.0, 0.8, 0.0, 1.0, 0.0]   # within the limits


def test_a_pose_within_the_margin_past_a_limit_is_believed_one_beyond_it_is_not():
    watch = BaxterWatch(LIMITS)
    upper = LIMITS['right'][0].upper
    watch.on_robot_pose(1.0, {'right': [upper + ROBOT_POSE_MARGIN_RAD * 0.9] + POSE[1:]})
    assert watch.pose['right'][0] == pytest.approx(upper + ROBOT_POSE_MARGIN_RAD * 0.9)
    watch.on_robot_pose(2.0, {'right': [upper + ROBOT_POSE_MARGIN_RAD * 1.1] + POSE[1:]})
    assert watch.pose['right'][0] < upper + ROBOT_POSE_MARGIN_RAD   # the previous one stays
    assert watch.pose_age('right', 2.5) == pytest.approx(1.5) and watch.ignored_poses == 1


def test_a_non_finite_pose_is_ignored_per_arm_and_counted():
    watch = BaxterWatch(LIMITS)
    watch.on_robot_pose(1.0, {'left': POSE, 'right': [math.nan] + POSE[1:]})
    assert watch.pose == {'left': POSE} and watch.ignored_poses == 1
    assert watch.now('right', 1.0) is None and watch.measured('right') is None
    assert watch.pose_age('right', 1.0) is None


def test_where_the_arm_is_now_moves_on_by_its_velocity_for_at_most_the_extrapolation_limit():
    watch = BaxterWatch(LIMITS)
    speeds = [0.5, 0.0, 0.0, -0.5, 0.0, 0.0, 0.0]
    watch.on_robot_pose(1.0, {'right': POSE}, {'right': speeds})
    assert watch.now('right', 1.02) == pytest.approx(
        [a + v * 0.02 for a, v in zip(POSE, speeds)])
    assert watch.now('right', 5.0) == pytest.approx(
        [a + v * MAX_EXTRAPOLATION_S for a, v in zip(POSE, speeds)])
    assert watch.now('right', 0.5) == pytest.approx(POSE)   # before the measurement: no motion


def test_velocities_beyond_the_limit_or_not_finite_count_as_still():
    watch = BaxterWatch(LIMITS)
    too_fast = LIMITS['right'][0].velocity * 1.5
    watch.on_robot_pose(1.0, {'right': POSE}, {'right': [too_fast, math.inf] + [0.0] * 5})
    assert watch.now('right', 1.05) == pytest.approx(POSE)
    assert watch.measured('right') == (1.0, POSE, [0.0] * 7)


def test_where_the_arm_is_now_stays_within_its_limits():
    watch = BaxterWatch(LIMITS)
    upper = LIMITS['right'][0].upper
    watch.on_robot_pose(1.0, {'right': [upper + 0.05] + POSE[1:]})
    assert watch.now('right', 1.0)[0] == pytest.approx(upper)


def test_the_measurement_handed_out_is_a_copy():
    watch = BaxterWatch(LIMITS)
    watch.on_robot_pose(1.0, {'right': POSE})
    watch.measured('right')[1][0] = 9.0
    assert watch.pose['right'] == POSE
