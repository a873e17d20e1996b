"""frame_rates: counts and rates between readings."""
import pytest

from robopuppet.cameras.frame_rates import FrameRates


def test_rates_are_per_second_since_the_last_reading():
    rates = FrameRates(['a', 'b'], now_s=10.0)
    for _ in range(30):
        rates.add('a')
    rates.add('b')
    assert rates.read(12.0) == ({'a': 30, 'b': 1}, {'a': pytest.approx(15.0), 'b': 0.5})
    rates.add('a')
    assert rates.read(13.0) == ({'a': 31, 'b': 1}, {'a': pytest.approx(1.0), 'b': 0.0})


def test_a_reading_right_after_another_does_not_divide_by_zero():
    rates = FrameRates(['a'], now_s=1.0)
    rates.add('a')
    counts, per_s = rates.read(1.0)
    assert counts == {'a': 1} and per_s['a'] == pytest.approx(1000.0)
