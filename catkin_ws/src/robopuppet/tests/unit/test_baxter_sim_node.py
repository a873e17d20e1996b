"""Tests of the pure helpers of robopuppet.baxter_sim_node (parameter checks, log throttle)."""
import math

import pytest

from robopuppet.baxter_sim_node import WarnThrottle, positive_param


@pytest.mark.parametrize('value, expected', [(100, 100.0), (0.2, 0.2), ('0.5', 0.5)])
def test_positive_param_accepts_positive_numbers(value, expected):
    assert positive_param('/baxter_sim/rate_hz', value) == expected


@pytest.mark.parametrize('value', [0, -1.0, 'fast', None, math.nan, math.inf, True, [1.0]])
def test_positive_param_names_the_parameter_when_refusing(value):
    with pytest.raises(ValueError, match='/baxter_sim/rate_hz'):
        positive_param('/baxter_sim/rate_hz', value)


def test_warn_throttle_allows_one_per_interval_per_key():
    throttle = WarnThrottle(2.0)
    assert throttle.due('joint', 10.0)
    assert not throttle.due('joint', 10.01)
    assert not throttle.due('joint', 11.99)
    assert throttle.due('gripper', 11.99)        # another kind of refusal is still reported
    assert throttle.due('joint', 12.0)
    assert not throttle.due('joint', 13.0)
    assert sum(throttle.due('flood', 20.0 + 0.01 * i) for i in range(1000)) == 5   # 100 Hz, 10 s
