"""Tests of the pure helpers of robopuppet.arm.arm_node (puppet joint_states matched by name)."""
import math

import pytest
from sensor_msgs.msg import JointState

from robopuppet.arm.arm_node import joint_angles

NAMES = ['joint_%d' % j for j in range(7)]


def test_joint_states_are_matched_by_name_not_by_index():
    angles = [0.1 * (j + 1) for j in range(7)]
    msg = JointState(name=list(reversed(NAMES)), position=list(reversed(angles)))
    assert joint_angles(msg) == pytest.approx(angles)


def test_extra_joints_are_ignored_and_non_finite_angles_pass_through_for_teleop():
    msg = JointState(name=NAMES + ['joint_7'], position=[0.0, math.nan] + [0.2] * 6)
    angles = joint_angles(msg)
    assert len(angles) == 7 and math.isnan(angles[1])


@pytest.mark.parametrize('names, positions, match', [
    ([], [0.0] * 7, '0 names but 7 positions'),
    (NAMES[:6], [0.0] * 6, 'no joint_6'),
    (NAMES, [0.0] * 6, '7 names but 6 positions'),
    (['a', 'b', 'c', 'd', 'e', 'f', 'g'], [0.0] * 7, 'no joint_0, joint_1'),
])
def test_joint_states_without_the_seven_names_are_refused_with_the_reason(names, positions,
                                                                         match):
    with pytest.raises(ValueError, match=match):
        joint_angles(JointState(name=names, position=positions))
