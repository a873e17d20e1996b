"""Which puppet samples arm_X may use and how it reports the link (robopuppet.arm.link_watch),
and the bound on sample ages (robopuppet.arm.timing.sample_age_bound)."""
import math
import re

import pytest
from diagnostic_msgs.msg import DiagnosticStatus

from robopuppet import interface
from robopuppet.arm import link_clock, link_watch, timing
from robopuppet.arm.link_clock import PING_PERIOD_S, Refused
from robopuppet.arm.link_watch import ERROR, NETWORK, OK, OPERATOR, ROBOT, WARN, LinkWatch
from robopuppet_msgs.msg import LinkState

OFFSET_S = -12.25    # the operator clock runs behind
START_S = 700.0
BOUND = timing.sample_age_bound(timing.DEFAULT_MAX_SAMPLE_AGE_S)
SILENT_AFTER_S = 0.4   # the state timeout at 10 Hz
CLOCK_ERROR_S = 0.002  # half the 4 ms round trip of Link's pings: arm_X adds it to every age


class Link:
    """A LinkWatch, a robot clock and an operator host answering pings (2 ms each way, lost
    when `answer` is False)."""

    def __init__(self, bound=BOUND):
        self.watch, self.now_s = LinkWatch('L', bound, SILENT_AFTER_S), START_S
        self.answer = True

    def run(self, seconds, sample_age_s=None, answer_every=1):
        """Run the pings for `seconds`; with sample_age_s, a sample that old arrives each ping;
        only every answer_every-th ping is answered."""
        for k in range(int(round(seconds / PING_PERIOD_S))):
            self.now_s += PING_PERIOD_S
            seq, sent_s = self.watch.clock.ping(self.now_s)
            if self.answer and k % answer_every == 0:
                self.watch.clock.on_echo(sent_s + 0.004, seq, sent_s, sent_s + 0.002 + OFFSET_S)
            if sample_age_s is not None:
                try:
                    self.sample(sample_age_s)
                except Refused:
                    pass   # counted

    def sample(self, age_s):
        """Take a sample that arm_X counts age_s old (its true age plus the clock's error)."""
        return self.watch.take(self.now_s + 0.004,
                               self.now_s + 0.004 - (age_s - CLOCK_ERROR_S) + OFFSET_S)

    def report(self, robot_ok=True):
        self.watch._report_s = None
        return self.watch.report(self.now_s + 0.005, robot_ok)


def test_the_faults_and_levels_are_the_messages_constants():
    assert (link_watch.NONE, OPERATOR, NETWORK, ROBOT) == (
        LinkState.NONE, LinkState.OPERATOR, LinkState.NETWORK, LinkState.ROBOT)
    assert (OK, WARN, ERROR) == (DiagnosticStatus.OK, DiagnosticStatus.WARN,
                                 DiagnosticStatus.ERROR)


@pytest.mark.parametrize('max_age_s, late_s, in_time', [
    (0.35, 0.5, True),    # the default: Baxter follows at most 0.5 s late
    (0.2, 0.35, True),
    (1.0, 1.15, False),   # asked for, and told it is late
])
def test_the_bound_on_sample_ages(max_age_s, late_s, in_time):
    bound = timing.sample_age_bound(max_age_s)
    assert (bound.bound_s, bound.late_s) == pytest.approx((max_age_s, late_s))
    assert bound.meets_stop == in_time
    assert ('%.2f s late' % late_s in bound.describe())
    assert ('not within 0.50 s' in bound.describe()) == (not in_time)


def test_the_default_bound_is_what_the_half_second_stop_leaves():
    assert timing.DEFAULT_MAX_SAMPLE_AGE_S == pytest.approx(
        interface.STOP_WITHIN_S - timing.STOP_AFTER_TIMEOUT_S - timing.HANDLING_MARGIN_S)
    assert timing.DEFAULT_MAX_SAMPLE_AGE_S == 0.35


@pytest.mark.parametrize('value', [0.0, -0.3, math.nan, math.inf])
def test_a_bound_that_is_no_positive_number_is_refused(value):
    with pytest.raises(ValueError, match='max_sample_age must be a positive number'):
        timing.sample_age_bound(value)


def test_samples_are_refused_by_kind_and_counted():
    link = Link()
    with pytest.raises(Refused, match='waiting for'):
        link.sample(0.0)
    link.run(0.2)
    assert link.sample(0.1) == pytest.approx(0.1)   # stamped at now - 0.096
    link.now_s += 1.0
    with pytest.raises(Refused, match='0.400 s old, over the 0.35 s bound'):
        link.sample(0.4)
    assert link.watch.sample_age_s == pytest.approx(0.4)   # the newest, refused or not
    with pytest.raises(Refused, match='out of order: stamped 0.100 s before'):
        link.sample(1.2)
    with pytest.raises(Refused, match='ahead of the robot clock'):
        link.sample(-0.2)
    with pytest.raises(Refused, match='not a time'):
        link.watch.take(link.now_s, math.nan)
    assert dict(link.watch.refused) == {'clock': 1, 'old': 1, 'order': 1, 'future': 1,
                                        'stamp': 1}
    assert link.watch.since_usable_s(link.now_s + 0.004) == pytest.approx(1.0)


def test_after_a_step_of_the_operator_clock_samples_compare_afresh():
    link = Link()
    link.run(0.5, sample_age_s=0.01)
    global OFFSET_S
    saved, OFFSET_S = OFFSET_S, OFFSET_S - 5.0   # the operator clock steps back 5 s
    try:
        link.run(0.1 * link_clock.STEP_CONFIRM)   # the echoes show it, again and again
        assert link.watch.clock.clock_steps == 1
        assert link.sample(0.01) == pytest.approx(0.01)   # no longer "out of order"
    finally:
        OFFSET_S = saved


def test_a_healthy_link_reports_its_figures():
    link = Link()
    link.run(1.0, sample_age_s=0.02)
    r = link.report()
    assert (r.level, r.fault, r.detail, r.clock_known) == (OK, 'none', 'the link is healthy', True)
    assert (r.rtt_s, r.clock_offset_s, r.sample_age_s) == pytest.approx((0.004, OFFSET_S, 0.02))
    assert (r.max_sample_age_s, r.loss) == (0.35, 0.0)
    values = dict(r.values)
    assert values['clock_error_s'] == '0.0020' and values['follows_within_s'] == '0.50'
    assert r.diag_name == 'arm_L: ' + interface.DIAG_NETWORK
    assert r.hardware_id == interface.puppet_ns('L')


@pytest.mark.parametrize('answer_every, level', [(1, OK), (10, ERROR), (3, ERROR), (4, ERROR)])
def test_loss_warns_and_then_errs(answer_every, level):
    link = Link()
    link.run(6.0, sample_age_s=0.02, answer_every=answer_every)
    r = link.report()
    assert r.level == level and (r.fault == NETWORK) == (level != OK)
    if level != OK:
        assert '% of the pings of the last 5 s unanswered' in r.detail


def test_a_little_loss_only_warns():
    link = Link()
    for _ in range(6):
        link.run(0.9, sample_age_s=0.02)
        link.answer = False
        link.run(0.1, sample_age_s=0.02)
        link.answer = True
    r = link.report()
    assert (r.level, r.fault) == (WARN, NETWORK) and r.loss == pytest.approx(0.1, abs=0.021)


def test_waiting_for_the_first_echo_warns_then_errs_and_nothing_else_is_blamed():
    link = Link()
    link.answer = False
    link.run(0.3, sample_age_s=0.0)   # the samples are refused: their age is unknown
    r = link.report()
    assert (r.level, r.fault, r.clock_known) == (WARN, NETWORK, False)
    assert "waiting for the operator host's echo" in r.detail and 'operator host answers' \
        not in r.detail
    link.run(0.5, sample_age_s=0.0)
    r = link.report(robot_ok=False)
    assert (r.level, r.fault) == (ERROR, NETWORK)
    assert r.detail.startswith('pings unanswered: no echo from the operator host for 0.')
    assert r.detail.endswith('; Baxter is absent or not enabled')


def test_samples_that_arrive_late_then_stop_are_the_networks_and_none_at_all_the_operators():
    link = Link()
    link.run(1.0, sample_age_s=0.25)
    assert (link.report().level, link.report().fault) == (WARN, NETWORK)
    link.run(0.5)   # nothing more arrives after a late one
    r = link.report()
    assert (r.level, r.fault) == (ERROR, NETWORK) and 'newer ones are late' in r.detail
    link = Link()
    link.run(1.0, sample_age_s=0.0)
    link.run(0.5)
    r = link.report()
    assert (r.level, r.fault) == (ERROR, OPERATOR)
    assert 'its puppet sends no joint states (no usable puppet sample for 0.50 s)' in r.detail


def test_a_late_sample_is_dropped_with_a_warning_and_late_ones_alone_are_the_networks_error():
    link = Link()
    link.run(1.0, sample_age_s=0.2)
    link.now_s += 0.3   # a TCP retransmission holds one back, 0.4 s old
    with pytest.raises(Refused, match='0.400 s old'):
        link.sample(0.4)
    r = link.report()   # usable samples came within the state timeout: Baxter follows
    assert (r.level, r.fault) == (WARN, NETWORK)
    assert r.detail == ('1 puppet sample of the last 5 s dropped: arrived over the 0.35 s bound, '
                        'the newest 0.40 s old')
    assert (dict(r.values)['late_dropped_last_5s'], dict(r.values)['refused_old']) == ('1', '1')
    link.run(0.5, sample_age_s=0.38)   # nothing usable for the state timeout, late ones only
    r = link.report()
    assert (r.level, r.fault) == (ERROR, NETWORK)
    assert re.fullmatch(r'puppet samples arrive too late: no usable puppet sample for 0\.80 s, '
                        r'the newest 0\.380 s old, over the 0\.35 s bound \(max_sample_age\): '
                        r'Baxter does not follow', r.detail), r.detail
    assert dict(r.values)['late_dropped_last_5s'] == '6'
    link.run(0.1, sample_age_s=0.0)   # fresh again: the drops of the last 5 s still warn
    assert (link.report().level, link.report().fault) == (WARN, NETWORK)
    link.run(5.0, sample_age_s=0.0)
    assert link.report().level == OK
    link.run(0.5, sample_age_s=1.0 + OFFSET_S)   # stamped by another clock, 'in the future'
    r = link.report()
    assert (r.level, r.fault) == (ERROR, OPERATOR)
    assert 'refused: stamped' in r.detail and 'ahead of the robot clock' in r.detail


def test_a_round_trip_over_100_ms_warns_and_an_uncertain_clock_makes_samples_older():
    link = Link()
    link.run(0.5, sample_age_s=0.0)
    clock = link.watch.clock
    seq, sent_s = clock.ping(link.now_s + 0.1)
    clock.on_echo(sent_s + 0.12, seq, sent_s, sent_s + 0.06 + OFFSET_S)
    link.now_s += 0.12
    r = link.report()
    assert (r.level, r.fault) == (WARN, NETWORK) and 'round trip 0.120 s' in r.detail
    slow = Link()
    seq, sent_s = slow.watch.clock.ping(slow.now_s)
    slow.watch.clock.on_echo(sent_s + 0.2, seq, sent_s, sent_s + 0.1 + OFFSET_S)
    slow.now_s += 0.2
    # Known to 0.1 s only: trusted, but every age counts 0.1 s more.
    with pytest.raises(Refused, match='0.400 s old, over the 0.35 s bound'):
        slow.watch.take(slow.now_s, slow.now_s - 0.3 + OFFSET_S)
    assert slow.watch.take(slow.now_s, slow.now_s - 0.05 + OFFSET_S) == pytest.approx(0.15)
    r = slow.report()
    assert (r.level, r.fault, r.clock_known) == (WARN, NETWORK, True)
    assert 'round trip 0.200 s' in r.detail


def test_garbage_stamped_long_ago_is_a_bad_stamp_not_out_of_order_and_real_ones_go_on():
    """topic_garbage: samples of another publisher stamped 1..1e9 s (long before now) were
    refused "out of order: stamped 1.7e9 s before one already used", which read as if the real
    samples were refused. They are bad stamps (the operator's), and the real ones are used."""
    link = Link()
    link.run(0.5, sample_age_s=0.01)
    for garbage in (1.0, 40.0, 80.0):   # the robot clock is 700 s here, 1.8e9 s in the run
        with pytest.raises(Refused, match='not a time a sample was taken') as refused:
            link.watch.take(link.now_s, garbage)
        assert refused.value.kind == 'stamp'
        link.run(PING_PERIOD_S)
        assert link.sample(0.01) == pytest.approx(0.01)
    assert dict(link.watch.refused) == {'stamp': 3}


def test_a_used_stamp_the_estimate_no_longer_allows_does_not_make_real_samples_out_of_order():
    """A garbage sample stamped 0.24 s ahead passes while the offset is known to 0.25 s only (a
    slow first echo); once fast echoes pin the offset down, it is in the future: forgotten, and
    the real samples after it are used, not refused as out of order."""
    link = Link()
    seq, sent_s = link.watch.clock.ping(link.now_s)
    link.watch.clock.on_echo(sent_s + 0.5, seq, sent_s, sent_s + 0.25 + OFFSET_S)
    link.now_s += 0.5
    ahead_s = link.now_s + 0.24 + OFFSET_S
    assert link.watch.take(link.now_s, ahead_s) == pytest.approx(0.01)   # within the error
    link.run(0.1)   # a 4 ms round trip: the offset is known to 2 ms
    assert link.sample(0.01) == pytest.approx(0.01)
    assert link.watch.reanchored == 1 and not link.watch.refused
    assert dict(link.report().values)['reanchored'] == '1'
