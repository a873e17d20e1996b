"""The state timeout follows the puppet's comm_rate (robopuppet.arm.timing), and teleop with it."""
import math

import pytest

from robopuppet import baxter_description, interface
from robopuppet.arm import teleop, timing

LIMITS = {side: baxter_description.arm_limits(side) for side in interface.BAXTER_SIDES}
NEUTRAL = {side: [baxter_description.NEUTRAL_POSE[s] for s in baxter_description.ARM_JOINT_SUFFIXES]
           for side in interface.BAXTER_SIDES}


# Written out by hand: 4 state periods, at least 0.2 s; the stop adds 0.1 s.
@pytest.mark.parametrize('rate_hz, timeout_s, stop_s, in_time', [
    (2.0, 2.0, 2.1, False),    # one period is 0.5 s: silence cannot show within 0.5 s
    (10.0, 0.4, 0.5, True),    # the 2020 firmware
    (50.0, 0.2, 0.3, True),    # 4 periods (80 ms) would trip on a host hiccup: the floor holds
    (0.2, 20.0, 2.6, False),   # a dead puppet also stops beating: the heartbeat timeout stops it
])
def test_the_timeout_at_each_rate(rate_hz, timeout_s, stop_s, in_time):
    derived = timing.state_timeout(rate_hz)
    assert derived.timeout_s == pytest.approx(timeout_s)
    assert derived.stop_s == pytest.approx(stop_s)
    assert derived.meets_stop == in_time


def test_the_default_is_the_2020_firmwares_rate():
    assert timing.DEFAULT == timing.state_timeout(interface.DEFAULT_COMM_RATE_HZ)
    assert teleop.Teleop('R', LIMITS).puppet.state_timeout_s == timing.DEFAULT.timeout_s


@pytest.mark.parametrize('rate_hz', [1.0, 2.0, 5.0, 9.9, 10.0, 20.0, 50.0, 200.0, 1000.0])
def test_normal_sets_never_trip_it_and_the_stop_is_in_time_from_10_hz(rate_hz):
    derived = timing.state_timeout(rate_hz)
    assert derived.timeout_s >= 4.0 / rate_hz  # the set's own period plus three late or lost
    assert derived.meets_stop == (rate_hz >= 10.0)
    if derived.meets_stop:
        assert derived.stop_s <= interface.STOP_WITHIN_S


def test_a_late_stop_is_described_with_its_time_and_the_rate_that_avoids_it():
    text = timing.state_timeout(2.0).describe()
    assert 'comm_rate 2 Hz' in text and 'only after 2.10 s' in text and '10 Hz or more' in text
    assert 'within 0.50 s' in timing.state_timeout(10.0).describe()


@pytest.mark.parametrize('rate_hz', [0.0, -10.0, math.nan, math.inf])
def test_a_rate_that_is_not_a_positive_number_is_refused(rate_hz):
    with pytest.raises(ValueError, match='comm_rate'):
        timing.state_timeout(rate_hz)


class Puppet:
    """A Teleop fed as arm_X feeds it: steps every 10 ms, a heartbeat every second, joint
    states at the given times; records each change of state with its time."""

    def __init__(self, state_timeout_s):
        self.tp = teleop.Teleop('R', LIMITS, state_timeout_s=state_timeout_s)
        self.tp.on_robot(True)
        self.tp.on_robot_pose(0.0, NEUTRAL)
        self.t, self._beat_t = 0.0, 0.0
        self.seen = [(0.0, self.tp.state)]

    def run(self, until_s, set_times=()):
        sets = sorted(set_times)
        while self.t < until_s - 1e-9:
            self.t = round(self.t + 0.01, 6)
            if self.t >= self._beat_t:
                self.tp.on_heartbeat(self.t)
                self._beat_t += interface.HEARTBEAT_PERIOD_S
            while sets and sets[0] <= self.t + 1e-9:
                self.tp.on_joint_states(sets.pop(0), [interface.WORKING] * 7, NEUTRAL['right'])
            self.tp.step(self.t)
            if self.tp.state != self.seen[-1][1]:
                self.seen.append((self.t, self.tp.state))

    def states(self):
        return [state for _, state in self.seen]


def test_at_2_hz_jittery_sets_and_a_lost_one_keep_teleop_ready_and_silence_faults_it():
    puppet = Puppet(timing.state_timeout(2.0).timeout_s)
    # 10 s of sets every 0.5 s, every third 0.15 s late, and the set due at 5.0 s lost.
    times = [0.5 * k + (0.15 if k % 3 == 0 else 0.0) for k in range(1, 21) if k != 10]
    puppet.run(10.0, times)
    assert puppet.states() == [interface.NO_ROBOT, interface.CALIBRATING, interface.READY]
    # Then silence while the heartbeats go on: the fault comes 2 s after the last set.
    puppet.run(14.0)
    assert puppet.states()[-1] == interface.FAULT
    assert puppet.seen[-1][0] - times[-1] == pytest.approx(2.0, abs=0.011)


def test_at_2_hz_a_fixed_10_hz_timeout_would_flap():
    """The failure this module prevents: 0.4 s without a set is normal at 2 Hz."""
    puppet = Puppet(timing.state_timeout(10.0).timeout_s)
    puppet.run(4.0, [0.5 * k for k in range(1, 9)])
    assert puppet.states().count(interface.FAULT) >= 3
