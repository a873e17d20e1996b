"""Tests of robopuppet.baxter_sim.baxter_publish_rate: the rate taken and the cycles due."""
import pytest

from robopuppet.baxter_sim.baxter_publish_rate import JointStateRate
from robopuppet.baxter_sim.baxter_refusals import CommandError


def published(rate, seconds=10.0, loop_hz=100.0):
    return sum(rate.due(i / loop_hz) for i in range(int(seconds * loop_hz)))


def test_every_cycle_publishes_at_the_default_100_hz():
    rate = JointStateRate(100.0)
    assert rate.rate_hz == 100.0 and published(rate) == 1000


@pytest.mark.parametrize('asked', [500, 1000, 65535])   # the wobbler, joint_torque_springs
def test_more_than_the_loop_publishes_at_the_loop_rate_and_says_so(asked):
    rate = JointStateRate(100.0)
    with pytest.raises(CommandError, match='at 100 Hz') as refused:
        rate.request(asked)
    assert refused.value.reason == 'too fast' and str(asked) in str(refused.value)
    assert rate.rate_hz == 100.0 and published(rate) == 1000


@pytest.mark.parametrize('asked', [50, 30, 20, 1])
def test_a_lower_rate_is_published_on_average_without_gaps_longer_than_a_loop_period(asked):
    rate = JointStateRate(100.0)
    assert rate.request(asked) == '/robot/joint_states now published at %g Hz, as asked' % asked
    times = [i / 100.0 for i in range(2000) if rate.due(i / 100.0)]
    assert len(times) == pytest.approx(20.0 * asked, abs=1)
    gaps = [b - a for a, b in zip(times, times[1:])]
    assert max(gaps) <= 1.0 / asked + 0.0101


def test_zero_is_refused_and_keeps_the_rate():
    rate = JointStateRate(100.0)
    rate.request(50)
    with pytest.raises(CommandError, match='still 50 Hz') as refused:
        rate.request(0)
    assert refused.value.reason == 'zero rate' and rate.rate_hz == 50.0
    rate.request(100)
    assert published(rate) == 1000


def test_a_late_loop_does_not_burst_to_catch_up():
    rate = JointStateRate(100.0)
    rate.request(20)
    assert rate.due(0.0) and not rate.due(0.01)
    assert rate.due(1.0)             # a 1 s stall: one message, then on at 20 Hz
    assert not rate.due(1.01) and not rate.due(1.02) and rate.due(1.05)
