"""The operator host's clock measured by pings (robopuppet.arm.link_clock): offset within half
the shortest round trip whatever the delays, loss, echoes that do not count, ages and refusals."""
import math
import random

import pytest

from robopuppet.arm import link_clock
from robopuppet.arm.link_clock import (CLOCK_EXPIRY_S, ECHO_TIMEOUT_S, PING_PERIOD_S, LinkClock,
                                       Refused)

OFFSET_S = 37.5       # the operator clock minus the robot clock
START_S = 5000.0      # the robot clock at the start


class Network:
    """Pings out and echoes back with the given one-way delays (s)."""

    def __init__(self, clock, offset_s=OFFSET_S):
        self.clock, self.offset_s, self.now_s = clock, offset_s, START_S

    def exchange(self, out_s, back_s):
        """Send a ping now, echo it on the operator clock after out_s, take it back_s later;
        return the echo's (seq, sent, echoed)."""
        seq, sent_s = self.clock.ping(self.now_s)
        echoed_s = sent_s + out_s + self.offset_s
        assert self.clock.on_echo(sent_s + out_s + back_s, seq, sent_s, echoed_s) == ''
        self.now_s += PING_PERIOD_S
        return seq, sent_s, echoed_s


def test_the_offset_is_within_half_the_shortest_round_trip_whatever_the_delays():
    rng, clock = random.Random(7), LinkClock()
    net = Network(clock)
    for _ in range(40):   # a slow way out, a fast way back, and jitter on both
        net.exchange(0.030 + rng.expovariate(1 / 0.02), 0.001 + rng.expovariate(1 / 0.005))
    offset_s, error_s = clock.offset()
    assert abs(offset_s - OFFSET_S) <= error_s
    assert error_s == pytest.approx(clock.best().rtt_s / 2)
    assert error_s >= 0.0155   # asymmetric: the midpoint is off by (out - back) / 2
    assert abs(offset_s - OFFSET_S) > 0.01
    assert clock.clock_problem(net.now_s) == ''


def test_the_best_echo_is_the_one_with_the_shortest_round_trip_of_the_window():
    clock = LinkClock()
    net = Network(clock)
    net.exchange(0.040, 0.040)
    net.exchange(0.002, 0.002)   # the best, until it leaves the window
    for _ in range(link_clock.CLOCK_WINDOW - 2):
        net.exchange(0.040, 0.010)
    assert clock.offset() == pytest.approx((OFFSET_S, 0.002))
    net.exchange(0.040, 0.010)
    net.exchange(0.040, 0.010)   # the 0.002 s echo is 50 echoes old now
    assert clock.offset() == pytest.approx((OFFSET_S + 0.015, 0.025))


def test_pings_go_out_every_period_numbered_from_1_and_wrap_past_zero():
    clock, sent = LinkClock(), []
    for k in range(21):   # asked at twice the ping rate
        ping = clock.ping(START_S + k * PING_PERIOD_S / 2)
        sent += [ping] if ping else []
    assert [seq for seq, _ in sent] == list(range(1, 12))
    assert [s for _, s in sent] == pytest.approx([START_S + k * PING_PERIOD_S for k in range(11)])
    clock._seq = link_clock.SEQ_MODULO - 1
    assert clock.ping(START_S + 10.0)[0] == 1


def test_loss_counts_pings_not_answered_within_the_timeout_over_the_last_seconds():
    clock, now_s = LinkClock(), START_S
    assert clock.loss(now_s) is None
    for k in range(50):   # 5 s of pings: 1 in 5 unanswered, 1 in 10 answered too late
        seq, sent_s = clock.ping(now_s)
        if k % 5 == 4:
            pass
        elif k % 10 == 3:
            clock.on_echo(sent_s + ECHO_TIMEOUT_S + 0.05, seq, sent_s, sent_s + OFFSET_S)
        else:
            clock.on_echo(sent_s + 0.004, seq, sent_s, sent_s + OFFSET_S)
        now_s += PING_PERIOD_S
    # At the last ping + the timeout, every ping of the window is decided: 10 + 5 of 50.
    assert clock.loss(now_s - PING_PERIOD_S + ECHO_TIMEOUT_S) == pytest.approx(15 / 50)
    # Just after the last ping, those of the last 0.5 s are still on their way: not counted.
    decided = [k for k in range(50) if k * PING_PERIOD_S <= 4.95 - ECHO_TIMEOUT_S]
    lost = [k for k in decided if k % 5 == 4 or k % 10 == 3]
    assert (len(lost), len(decided)) == (14, 45)
    assert clock.loss(START_S + 4.95) == pytest.approx(14 / 45)
    assert clock.loss(now_s + 20.0) is None   # nothing in the window any more


@pytest.mark.parametrize('change, why', [
    (lambda e: (e[0] + 1000, e[1], e[2]), 'no ping 1001 was sent'),
    (lambda e: (e[0], e[1] + 0.001, e[2]), 'the echo says'),
    (lambda e: (e[0], e[1], math.nan), 'not finite'),
    (lambda e: (e[0], e[1], math.inf), 'not finite'),
    (lambda e: (math.nan, e[1], e[2]), 'not finite'),
    (lambda e: (e[0], e[1], -3.0), 'is not a time'),
    (lambda e: (e[0], e[1], 0.0), 'is not a time'),
    (lambda e: (e[0], None, e[2]), 'not finite'),
])
def test_unknown_and_garbage_echoes_are_ignored_and_counted(change, why):
    clock, now_s = LinkClock(), START_S
    seq, sent_s = clock.ping(now_s)
    bad = change((seq, sent_s, sent_s + OFFSET_S))
    problem = clock.on_echo(now_s + 0.01, *bad)
    assert why in problem and '(1 so far)' in problem
    assert (clock.echoes, clock.ignored_echoes, clock.offset()) == (0, 1, None)
    assert clock.on_echo(now_s + 0.01, seq, sent_s, sent_s + OFFSET_S) == ''   # the real one
    assert 'answered already' in clock.on_echo(now_s + 0.02, seq, sent_s, sent_s + OFFSET_S)
    assert 'before ping' in clock.on_echo(now_s - 1.0, *clock.ping(now_s + 0.1),
                                          now_s + OFFSET_S)
    assert (clock.echoes, clock.ignored_echoes) == (1, 3)
    assert clock.offset()[0] == pytest.approx(OFFSET_S - 0.005)


def test_the_clock_is_trusted_only_after_an_echo_and_while_echoes_come_and_agree():
    clock = LinkClock()
    net = Network(clock)
    assert 'waiting for' in clock.clock_problem(START_S)
    net.exchange(0.08, 0.08)   # known to 0.08 s only: trusted, ages count that error
    assert clock.clock_problem(net.now_s) == ''
    assert clock.age(net.now_s, net.now_s - 0.1 + OFFSET_S) == pytest.approx(0.18)
    net.exchange(0.004, 0.004)
    assert clock.clock_problem(net.now_s) == ''
    last_echo_s = net.now_s - PING_PERIOD_S + 0.008
    assert clock.clock_problem(last_echo_s + CLOCK_EXPIRY_S) == ''
    assert 'no echo from the operator host for 3.0 s' in clock.clock_problem(
        last_echo_s + CLOCK_EXPIRY_S + 0.01)
    assert clock.silence_s(last_echo_s + 1.0) == pytest.approx(1.0)


def test_a_step_of_the_operator_clock_restarts_the_estimate_once_echoes_confirm_it():
    clock = LinkClock()
    net = Network(clock)
    for _ in range(10):
        net.exchange(0.002, 0.002)
    net.offset_s += 1.0   # NTP steps the operator clock
    for k in range(link_clock.STEP_CONFIRM):
        seq, sent_s = clock.ping(net.now_s)
        why = clock.on_echo(sent_s + 0.02, seq, sent_s, sent_s + 0.01 + net.offset_s)
        net.now_s += PING_PERIOD_S
        if k < link_clock.STEP_CONFIRM - 1:
            assert 'set aside' in why and clock.clock_steps == 0
            assert clock.offset() == pytest.approx((OFFSET_S, 0.002))
        if k == 1:   # two in a row: in doubt, no age is trusted
            assert 'may have stepped' in clock.clock_problem(net.now_s)
    assert why == '' and clock.clock_steps == 1 and clock.clock_problem(net.now_s) == ''
    assert clock.offset() == pytest.approx((OFFSET_S + 1.0, 0.01))
    net.exchange(0.02, 0.02)
    assert clock.clock_steps == 1


@pytest.mark.parametrize('forged_s', [1.7e9, 2 ** 32 - 1.0, 1.0, -5.0 + OFFSET_S])
def test_one_echo_with_a_forged_time_does_not_move_the_estimate(forged_s):
    """An echo that answers a ping we sent but with a forged `echoed` time (anyone may publish
    on link_echo) is set aside: the estimate stays, a sample stamped as its offset would allow
    is refused as future, and the next real echo is taken."""
    clock = LinkClock()
    net = Network(clock)
    for _ in range(10):
        net.exchange(0.002, 0.002)
    seq, sent_s = clock.ping(net.now_s)
    assert 'set aside (1 so far)' in clock.on_echo(sent_s + 0.001, seq, sent_s, forged_s)
    net.now_s += PING_PERIOD_S
    assert clock.offset() == pytest.approx((OFFSET_S, 0.002))
    assert clock.clock_problem(net.now_s) == ''
    if forged_s > 1e9:
        with pytest.raises(Refused) as refused:
            clock.age(net.now_s, net.now_s + forged_s - sent_s)
        assert refused.value.kind == 'future'
    net.exchange(0.002, 0.002)
    assert (clock.clock_steps, clock.outliers) == (0, 1)


def test_outliers_that_disagree_among_themselves_never_make_a_step():
    clock = LinkClock()
    net = Network(clock)
    for _ in range(5):
        net.exchange(0.002, 0.002)
    for forged_s in (1.7e9, 3.0e9, 1.0, 2.5e9, 4.0e9):
        seq, sent_s = clock.ping(net.now_s)
        assert 'set aside' in clock.on_echo(sent_s + 0.004, seq, sent_s, forged_s)
        net.now_s += PING_PERIOD_S
    assert clock.clock_steps == 0 and clock.offset() == pytest.approx((OFFSET_S, 0.002))


def test_an_echo_answered_after_the_expiry_is_lost_and_does_not_keep_the_clock_trusted():
    clock, now_s = LinkClock(), START_S
    seq, sent_s = clock.ping(now_s)
    assert clock.on_echo(now_s + 0.004, seq, sent_s, sent_s + 0.002 + OFFSET_S) == ''
    late = [clock.ping(now_s + k * PING_PERIOD_S) for k in range(1, 41)]   # 4 s unanswered
    end_s = now_s + 4.0 + 0.01
    for seq, sent_s in late[:5]:   # answered 3.5 s and more late: no news of the clock now
        assert 'longer than an estimate is trusted' in clock.on_echo(end_s, seq, sent_s,
                                                                     sent_s + OFFSET_S)
    assert 'no echo from the operator host' in clock.clock_problem(end_s)
    assert clock.offset() == pytest.approx((OFFSET_S - 0.0, 0.002))
    seq, sent_s = late[-1]   # 0.01 s round trip: taken
    assert clock.on_echo(end_s, seq, sent_s, sent_s + 0.005 + OFFSET_S) == ''
    assert clock.loss(end_s + 1.0) == pytest.approx(39 / 41)   # the late 5 count as lost


def test_a_stamp_long_before_now_is_garbage_not_an_age():
    clock = LinkClock()
    net = Network(clock)
    net.exchange(0.002, 0.002)
    assert clock.age(net.now_s, net.now_s - 500.0 + OFFSET_S) == pytest.approx(500.002)
    for stamp_s in (1.0, net.now_s - 700.0 + OFFSET_S):
        with pytest.raises(Refused, match='not a time a sample was taken') as refused:
            clock.age(net.now_s, stamp_s)
        assert refused.value.kind == 'stamp'


def test_the_age_of_a_sample_is_on_the_robot_clock_and_bad_stamps_are_refused():
    clock = LinkClock()
    net = Network(clock)
    with pytest.raises(Refused, match='waiting for') as refused:
        clock.age(net.now_s, net.now_s + OFFSET_S)
    assert refused.value.kind == 'clock'
    net.exchange(0.003, 0.003)
    now_s = net.now_s   # the offset is known to 0.003 s: ages are upper bounds, 0.003 s more
    assert clock.age(now_s, now_s - 0.25 + OFFSET_S) == pytest.approx(0.253)
    assert clock.age(now_s, now_s + 0.005 + OFFSET_S) == 0.0   # within the error: not negative
    for stamp in (math.nan, math.inf, 0.0, -1.0, None):
        with pytest.raises(Refused, match='not a time') as refused:
            clock.age(now_s, stamp)
        assert refused.value.kind == 'stamp'
    with pytest.raises(Refused, match='ahead of the robot clock') as refused:
        clock.age(now_s, now_s + 0.1 + OFFSET_S)
    assert refused.value.kind == 'future'
