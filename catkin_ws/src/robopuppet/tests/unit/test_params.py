"""robopuppet.params: the nodes' numeric parameter checks."""
import math

import pytest

from robopuppet import params


@pytest.mark.parametrize('value, expected', [(100, 100.0), (0.2, 0.2), ('0.5', 0.5)])
def test_positive_accepts_positive_numbers(value, expected):
    assert params.positive('/baxter_sim/rate_hz', value) == expected


@pytest.mark.parametrize('value', [0, -1.0, 'fast', None, math.nan, math.inf, True, [1.0]])
def test_positive_names_the_parameter_when_refusing(value):
    with pytest.raises(ValueError, match='/baxter_sim/rate_hz'):
        params.positive('/baxter_sim/rate_hz', value)


@pytest.mark.parametrize('value', ['fast', None, math.nan, math.inf, 0.0, -1.0, 5.0])
def test_a_parameter_that_is_not_a_positive_number_of_at_least_its_minimum_is_refused(value):
    with pytest.raises(ValueError, match='~command_rate'):
        params.positive('~command_rate', value, minimum=10.0)


def test_a_good_parameter_is_returned_as_a_float():
    assert params.positive('~comm_rate', '2') == 2.0
    assert params.positive('~command_rate', 10, minimum=10.0) == 10.0
