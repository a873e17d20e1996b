"""Tests of robopuppet.baxter_sim.baxter_feed_forward: which points are malformed."""
import math

import pytest

from robopuppet.baxter_sim.baxter_feed_forward import check_feed_forward

SEVEN = [0.1] * 7


@pytest.mark.parametrize('positions, velocities, accelerations', [
    (SEVEN, [], []), (SEVEN, SEVEN, []), (SEVEN, SEVEN, SEVEN)])
def test_a_well_formed_point_is_refused_because_the_stand_in_is_kinematic(
        positions, velocities, accelerations):
    error = check_feed_forward('left', positions, velocities, accelerations)
    assert error.reason == 'kinematic stand-in' and 'left arm' in str(error)


@pytest.mark.parametrize('positions, velocities, accelerations, words', [
    ([], [], [], '0 positions'), ([0.1] * 6, [], [], '6 positions'),
    (SEVEN, [0.1] * 8, [], '8 velocities'), (SEVEN, [], [0.1] * 3, '3 accelerations'),
    ([math.nan] * 7, [], [], 'positions not finite'),
    (SEVEN, [math.inf] * 7, [], 'velocities not finite')])
def test_a_malformed_point_says_what_is_wrong(positions, velocities, accelerations, words):
    error = check_feed_forward('right', positions, velocities, accelerations)
    assert error.reason == 'malformed feed-forward' and words in str(error)
