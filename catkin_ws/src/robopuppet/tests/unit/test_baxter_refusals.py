"""Tests of robopuppet.baxter_sim.baxter_refusals: number checks, short reprs, the refusal log
throttle."""
import math

import pytest

from robopuppet.baxter_sim.baxter_refusals import CommandError, RefusalThrottle, brief, finite


@pytest.mark.parametrize('value', [1, 0.25, -3.0, 1e300])
def test_finite_takes_real_numbers(value):
    assert finite(value, 'x') == float(value)


@pytest.mark.parametrize('value', [math.nan, math.inf, -math.inf, 10 ** 400, '0.5', 'nan',
                                   None, True, [1.0], {'a': 1}])
def test_finite_refuses_everything_else_with_its_reason(value):
    # 10 ** 400 (a JSON integer with 400 digits) raised OverflowError, not a refusal.
    with pytest.raises(CommandError, match='position') as caught:
        finite(value, 'position', 'bad position')
    assert caught.value.reason == 'bad position'


def test_brief_keeps_log_lines_short_whatever_the_value():
    nested = []
    for _ in range(900):
        nested = [nested]
    for value in ('x' * 10 ** 6, list(range(10 ** 5)), 10 ** 400, nested, {str(i): i for i in
                                                                           range(1000)}):
        assert len(brief(value)) < 200
    assert brief('left_s0') == "'left_s0'"


def test_throttle_allows_one_per_interval_per_key_and_counts_the_rest():
    throttle = RefusalThrottle(2.0)
    assert throttle.report('joint', 10.0) == 0
    assert throttle.report('joint', 10.01) is None
    assert throttle.report('joint', 11.99) is None
    assert throttle.report('gripper', 11.99) == 0     # another kind of refusal is still reported
    assert throttle.report('joint', 12.0) == 2        # with the count of repeats not logged
    assert not throttle.due('joint', 13.0)
    assert sum(throttle.due('flood', 20.0 + 0.01 * i) for i in range(1000)) == 5   # 100 Hz, 10 s
