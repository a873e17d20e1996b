"""Unit tests of protocol.feel_watch: feel's wait for its gains (setpoints kept meanwhile) and the
watchdog that ends feel when the gains or the setpoints do not come."""
import pytest

from robopuppet.protocol import codec
from robopuppet.protocol.feel_watch import FeelWatch


def test_the_feel_watch_times_out_only_in_feel_counting_from_the_last_setpoint():
    watch = FeelWatch(0.5)
    assert watch.on_setpoint(1.0, 3, 0.2)   # outside feel: sent at once
    assert not watch.active and watch.expired(100.0) == '' and watch.due_s == float('inf')
    watch.start(10.0)
    assert watch.active and watch.due_s == 10.5
    assert watch.gains_loaded() == [] and not watch.waiting
    assert watch.on_setpoint(10.4, 3, 0.2)
    assert watch.expired(10.8) == ''
    assert 'no joint setpoint for 0.50 s in feel mode' in watch.expired(10.9)
    assert watch.stop() == []
    assert watch.expired(20.0) == '' and not watch.active
    for bad in (0.0, -1.0, float('nan')):
        with pytest.raises(ValueError):
            FeelWatch(bad)


def test_feel_waits_for_its_gains_keeping_the_newest_setpoint_of_each_joint():
    watch = FeelWatch(0.5)
    watch.start(10.0)
    assert watch.waiting
    assert not watch.on_setpoint(10.1, 5, 0.3)
    assert not watch.on_setpoint(10.2, 2, -0.1)
    assert not watch.on_setpoint(10.3, 5, 0.4)
    assert watch.expired(10.49) == ''
    assert watch.gains_loaded() == [codec.JointSetpoint(2, -0.1), codec.JointSetpoint(5, 0.4)]
    assert not watch.waiting and watch.active
    assert watch.on_setpoint(10.4, 5, 0.5) and watch.gains_loaded() == []
    assert watch.due_s == 10.9   # the watchdog counts from the newest setpoint


def test_feel_that_waits_too_long_for_its_gains_expires_and_stop_hands_back_the_kept():
    watch = FeelWatch(0.5)
    watch.start(10.0)
    watch.on_setpoint(10.3, 1, 0.7)   # arm_X streams on: the setpoint watchdog alone is content
    assert watch.due_s == 10.5
    assert 'feel gains' in watch.expired(10.6) and '0.60 s' in watch.expired(10.6)
    assert watch.stop() == [codec.JointSetpoint(1, 0.7)]
    assert not watch.active and watch.expired(20.0) == '' and watch.stop() == []
