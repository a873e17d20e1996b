"""robopuppet.arm.readings: the puppet's and Baxter's joints from message fields, by name."""
import math

import pytest

from robopuppet import baxter_description, settings
from robopuppet.arm.readings import arm_poses, joint_angles, non_finite_joints

NAMES = list(settings.JOINT_NAMES)
BAXTER_NAMES = {side: baxter_description.arm_joint_names(side) for side in ('left', 'right')}


def test_joint_states_are_matched_by_name_not_by_index():
    angles = [0.1 * (j + 1) for j in range(7)]
    assert joint_angles(list(reversed(NAMES)), list(reversed(angles))) == pytest.approx(angles)


def test_extra_joints_are_ignored_and_non_finite_angles_pass_through_for_teleop():
    angles = joint_angles(NAMES + ['joint_7'], [0.0, math.nan] + [0.2] * 6)
    assert len(angles) == 7 and math.isnan(angles[1])
    assert non_finite_joints(angles) == ['joint_1']


@pytest.mark.parametrize('names, positions, match', [
    ([], [0.0] * 7, '0 names but 7 positions'),
    (NAMES[:6], [0.0] * 6, 'no joint_6'),
    (NAMES, [0.0] * 6, '7 names but 6 positions'),
    (['a', 'b', 'c', 'd', 'e', 'f', 'g'], [0.0] * 7, 'no joint_0, joint_1'),
])
def test_joint_states_without_the_seven_names_are_refused_with_the_reason(names, positions,
                                                                         match):
    with pytest.raises(ValueError, match=match):
        joint_angles(names, positions)


def test_baxter_arms_are_matched_by_name_and_an_incomplete_arm_is_left_out():
    right = BAXTER_NAMES['right']
    names = ['head_pan'] + list(reversed(right)) + BAXTER_NAMES['left'][:6]
    positions = [9.0] + [0.1 * (7 - k) for k in range(7)] + [0.0] * 6
    poses, speeds = arm_poses(names, positions, [], BAXTER_NAMES)
    assert poses == {'right': pytest.approx([0.1 * (k + 1) for k in range(7)])}
    assert speeds['right'] == [0.0] * 7  # no velocities: none assumed


def test_baxter_velocities_count_only_when_there_is_one_per_name():
    right = BAXTER_NAMES['right']
    _, speeds = arm_poses(right, [0.0] * 7, [0.5] * 7, BAXTER_NAMES)
    assert speeds['right'] == [0.5] * 7
    _, speeds = arm_poses(right, [0.0] * 7, [0.5] * 6, BAXTER_NAMES)
    assert speeds['right'] == [0.0] * 7


def test_garbage_names_are_cut_in_the_error_a_node_logs():
    garbage = ['x' * 10000 for _ in range(7)]
    with pytest.raises(ValueError) as error:
        joint_angles(garbage, [0.0] * 7)
    assert 'no joint_0' in str(error.value) and len(str(error.value)) < 300
