"""Tests of robopuppet.baxter_sim.baxter_joint_command: each mode's clamp, the refusals."""
import math

import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_joint_command import (MODES, POSITION_MODE, RAW_POSITION_MODE,
                                                        TORQUE_MODE, VELOCITY_MODE,
                                                        command_targets)
from robopuppet.baxter_sim.baxter_refusals import CommandError

DESC = bd.load()
LIMITS = {lim.name: lim for lim in DESC.arm_limits('left')}
EFFORT = {name: DESC.joints[name].effort for name in LIMITS}


def targets(mode, names, values):
    return command_targets('left', mode, names, values, LIMITS, EFFORT)


def test_the_modes_are_baxters_four():
    assert MODES == (POSITION_MODE, VELOCITY_MODE, TORQUE_MODE, RAW_POSITION_MODE) == (1, 2, 3, 4)


@pytest.mark.parametrize('mode', [POSITION_MODE, RAW_POSITION_MODE])
def test_positions_are_clamped_to_the_joint_limits(mode):
    s0 = LIMITS['left_s0']
    assert targets(mode, ['left_s0', 'left_e1'], [100.0, 0.5]) == {'left_s0': s0.upper,
                                                                    'left_e1': 0.5}
    assert targets(mode, ['left_s0'], [-100.0]) == {'left_s0': s0.lower}


def test_velocities_and_torques_are_clamped_to_their_limits():
    assert targets(VELOCITY_MODE, ['left_w2'], [-1e9]) == {'left_w2': -LIMITS['left_w2'].velocity}
    assert targets(TORQUE_MODE, ['left_w2'], [1e9]) == {'left_w2': EFFORT['left_w2']}
    assert targets(TORQUE_MODE, ['left_w2'], [1.5]) == {'left_w2': 1.5}


@pytest.mark.parametrize('mode, names, values, reason', [
    (0, ['left_s0'], [0.1], 'unknown mode'),
    (1, ['left_s0'], [], 'length mismatch'),
    (1, [], [], 'empty'),
    (1, ['left_s0'] * 8, [0.1] * 8, 'too many joints'),
    (1, ['right_s0'], [0.1], 'unknown joint'),
    (1, ['left_s0', 'left_s0'], [0.1, 0.2], 'repeated joint'),
    (3, ['left_s0'], [math.nan], 'non-finite value'),
])
def test_a_bad_command_is_refused_naming_arm_and_reason(mode, names, values, reason):
    with pytest.raises(CommandError) as caught:
        targets(mode, names, values)
    assert caught.value.reason == reason and str(caught.value).startswith('left arm:')
