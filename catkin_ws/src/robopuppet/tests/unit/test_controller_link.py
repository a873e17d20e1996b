"""arm_X with the puppet on another host (robopuppet.arm.controller with arm.link_watch): no
following before the operator clock is known, late samples dropped and a stream of them stale,
out-of-order samples, a burst after a delay spike, a lost clock, and the link's report. Fed as
the node feeds it (see test_controller.Rig: the operator clock runs 37.5 s ahead of the
robot's)."""
import pytest

from robopuppet import interface, settings
from robopuppet.arm import controller, link_watch, timing
from test_controller import LIMITS, PERIOD_S, POSE, Rig, ready

BOUND_S = timing.DEFAULT_MAX_SAMPLE_AGE_S


def commands(actions):
    return [a.angles for a in actions if isinstance(a, controller.ArmCommand)]


def moved(pose, joint, by_rad):
    pose = list(pose)
    pose[joint] += by_rad
    return pose


def following():
    rig = ready()
    rig.press(interface.BUTTON_RIGHT)
    assert rig.core.teleop.state == interface.FOLLOWING and rig.core.teleop.tracking['right']
    return rig


def link_report(rig):
    rig.core.link._report_s = None   # due now
    return rig.core.link_report(rig.now_s())


def test_nothing_follows_before_the_operator_host_has_answered_a_ping():
    rig = Rig(echo=False)
    for _ in range(60):
        out = rig.step()
    tp = rig.core.teleop
    assert tp.state == interface.CALIBRATING
    assert "waiting for the operator host's echo" in tp.detail
    assert not commands(rig.press(interface.BUTTON_RIGHT) + rig.step())
    assert tp.state == interface.CALIBRATING and not tp.following['right']
    report = link_report(rig)
    assert (report.clock_known, report.fault, report.level) == (False, 'network', 2)
    assert 'pings unanswered' in report.detail and report.rtt_s == -1.0
    assert dict(report.values)['refused_clock'] == '62'
    rig.echo = True
    for _ in range(10):
        out = rig.step()
    assert tp.state == interface.READY and not commands(out)
    assert commands(rig.press(interface.BUTTON_RIGHT))


class Operator:
    """The operator host: a sample every 0.1 s (10 Hz), which the network delivers `delay_s`
    later, in order (TCP); the rig steps at its command rate meanwhile. arrivals: [(t, age s
    counted, taken)] of every sample delivered."""

    def __init__(self, rig):
        self.rig, self.next_t, self.queue, self.delay_s = rig, rig.t, [], 0.0
        self.arrivals = []

    def run(self, seconds, grow_s=0.0, angles=None, hold_s=0.0, held_angles=None):
        """Run for `seconds`, the delay growing by grow_s per sample; return [(t, actions)].
        The run's first sample is held back hold_s more (a TCP retransmission: the samples
        behind it wait for it) and carries held_angles."""
        rig, outs, end_t = self.rig, [], self.rig.t + seconds - 1e-9
        held = hold_s > 0.0
        while rig.t < end_t:
            rig.t += PERIOD_S
            rig.baxter()
            rig.link()
            while self.next_t <= rig.t + 1e-9:
                arrive_t = max([self.next_t + self.delay_s + (hold_s if held else 0.0)]
                               + [q[1] for q in self.queue[-1:]])
                self.queue.append((self.next_t, arrive_t, held_angles if held else angles))
                self.next_t += 0.1
                self.delay_s += grow_s
                held = False
            while self.queue and self.queue[0][1] <= rig.t + 1e-9:
                stamp_t, _, pose = self.queue.pop(0)
                taken, _ = rig.puppet(angles=pose, age_s=rig.t - stamp_t)
                self.arrivals.append((rig.t, rig.core.link.sample_age_s, taken))
            outs.append((rig.t, rig.core.step(rig.t)))
            rig.core.done(rig.t)
        return outs


def faulted(outs):
    """Return the index in outs of the step whose report says fault."""
    return next(k for k, (_, out) in enumerate(outs)
                if any(isinstance(a, controller.Report) and a.state == interface.FAULT
                       for a in out))


def test_one_late_sample_among_fresh_ones_is_dropped_never_used_and_following_goes_on():
    rig = following()
    operator = Operator(rig)
    operator.delay_s = 0.1
    operator.run(1.0)
    operator.arrivals = []
    # A lost packet: TCP resends the sample 0.27 s later, the samples behind it wait. It comes
    # 0.372 s old (0.002 s of it the clock's error) with the hand far off, the next one 0.272 s.
    far = moved(POSE['right'], 3, 0.3)
    outs = operator.run(2.0, hold_s=0.27, held_angles=far)
    late = [a for a in operator.arrivals if not a[2]]
    assert len(late) == 1 and late[0][1] == pytest.approx(0.372)
    assert len(operator.arrivals) == 20   # the samples behind it are used
    tp = rig.core.teleop
    assert tp.state == interface.FOLLOWING
    assert not any(isinstance(a, controller.Report) and a.state != interface.FOLLOWING
                   for _, out in outs for a in out)
    sent = [c for _, out in outs for c in commands(out)]
    assert len(sent) == 200 and all(c == POSE['right'] for c in sent)   # never toward it
    assert tp.puppet.angles == POSE['right']
    report = link_report(rig)
    assert (report.fault, report.level) == ('network', 1)
    assert ('1 puppet sample of the last 5 s dropped: arrived over the 0.35 s bound, the newest '
            '0.37 s old') in report.detail
    values = dict(report.values)
    assert (values['late_dropped_last_5s'], values['refused_old']) == ('1', '1')
    operator.run(3.5)   # the drop leaves the 5 s window
    report = link_report(rig)
    assert (report.fault, dict(report.values)['late_dropped_last_5s']) == ('none', '0')


def test_late_samples_for_the_state_timeout_fault_naming_the_newest_age_as_stale():
    rig = following()
    operator = Operator(rig)
    operator.run(1.0)
    assert rig.core.teleop.state == interface.FOLLOWING
    operator.arrivals = []
    # The delay grows by 60 ms a sample: 0.06, 0.12, ... 0.30 s are used, 0.36 s and later are
    # dropped (each counted 2 ms older: half the rig's 4 ms round trip); they arrive 0.16 s
    # apart, so it is the state timeout since the last usable one that ends following.
    outs = operator.run(2.0, grow_s=0.06)
    fault_at = faulted(outs)
    fault_t, out = outs[fault_at]
    used_t = max(t for t, _, taken in operator.arrivals if taken)
    late = [(t, age_s) for t, age_s, taken in operator.arrivals if not taken and t < fault_t]
    assert len(late) >= 2 and late[0][1] == pytest.approx(0.362)   # dropped, no fault
    assert rig.core.timing.timeout_s < fault_t - used_t <= rig.core.timing.timeout_s + PERIOD_S
    assert rig.core.teleop.detail == (
        'puppet joint states refused: stale, none usable for %.2f s: the newest %.3f s old, '
        'over the 0.35 s bound (max_sample_age)' % (fault_t - used_t, late[-1][1]))
    assert commands(out) == [POSE['right']]   # stay where Baxter is, in the same step
    assert [c for _, out in outs[fault_at + 1:] for c in commands(out)] == []
    assert rig.core.teleop.state == interface.FAULT
    report = link_report(rig)
    assert (report.fault, report.level) == ('network', 2)
    assert report.detail.startswith('puppet samples arrive too late: no usable puppet sample '
                                    'for ')
    assert report.sample_age_s > BOUND_S and report.max_sample_age_s == BOUND_S
    assert int(dict(report.values)['refused_old']) >= 5

    # The delay is gone and the hand has moved on: ready again, but nothing moves until a press,
    # and then Baxter approaches slowly from where it is.
    hand = moved(POSE['right'], 3, 0.4)
    operator.queue, operator.delay_s = [], 0.0   # what was still on its way is lost
    outs = operator.run(1.0, angles=hand)
    assert rig.core.teleop.state == interface.READY
    assert [c for _, out in outs for c in commands(out)] == []
    assert link_report(rig).fault == 'network'   # the drops of the last 5 s: a warning
    rig.core.on_button(interface.BUTTON_RIGHT)
    approach = [c for _, out in operator.run(0.2, angles=hand) for c in commands(out)]
    previous = POSE['right']
    for command in approach:
        assert max(abs(c - p) for c, p in zip(command, previous)) <= 0.5 * PERIOD_S + 1e-9
        previous = command
    assert len(approach) == 20
    assert approach[-1][3] == pytest.approx(POSE['right'][3] + 0.5 * PERIOD_S * len(approach))


def test_a_delay_that_jumps_past_the_state_timeout_faults_on_silence_then_names_the_age():
    rig = following()
    operator = Operator(rig)
    operator.run(1.0)
    last_fresh_t = operator.next_t - 0.1   # its newest sample arrived at once
    operator.delay_s = 0.5
    outs = operator.run(1.5)
    fault_t, out = outs[faulted(outs)]
    assert rig.core.timing.timeout_s < fault_t - last_fresh_t <= rig.core.timing.timeout_s + 0.02
    assert commands(out) == [POSE['right']]
    detail = rig.core.teleop.detail
    assert detail.startswith('no joint states from the puppet for 0.4')
    assert detail.endswith('; puppet joint states refused since: 0.502 s old, over the 0.35 s '
                           'bound (max_sample_age)')   # why no fresh data came since
    assert link_report(rig).sample_age_s == pytest.approx(0.502)   # plus the clock's error


def test_a_sample_older_than_one_already_used_is_not_used():
    rig = following()
    ahead = moved(POSE['right'], 3, 0.2)
    rig.step(angles=ahead)
    stamp_s = rig.operator_s()
    back = moved(POSE['right'], 3, -0.2)
    for late_s in (0.05, 0.0):   # older, and the same stamp again
        taken, problem = rig.core.on_joint_states(rig.t, settings.JOINT_NAMES, back,
                                                  stamp_s - late_s, rig.now_s())
        assert not taken and 'out of order' in problem
    assert rig.core.teleop.puppet.angles == ahead
    assert dict(link_report(rig).values)['refused_order'] == '2'
    assert rig.core.teleop.state == interface.FOLLOWING


def test_a_burst_after_a_delay_spike_moves_baxter_no_faster_than_its_limits():
    rig = following()
    for _ in range(30):   # 0.3 s without samples: within the bound, no fault
        rig.step(puppet=False)
    assert rig.core.teleop.state == interface.FOLLOWING
    burst = []
    for age_s, by_rad in ((0.30, 0.5), (0.20, 1.0), (0.10, 1.5)):   # all at once, a far hand
        rig.puppet(angles=moved(POSE['right'], 3, by_rad), age_s=age_s)
        burst += commands(rig.core.step(rig.t))
    assert len(burst) == 3
    speed = [lim.velocity for lim in LIMITS['right']]
    for joint in range(7):
        travel = sum(abs(b[joint] - a[joint]) for a, b in zip([POSE['right']] + burst, burst))
        assert travel <= speed[joint] * PERIOD_S + 1e-9, joint
    assert burst[-1][3] > POSE['right'][3]   # it did move, within its budget


def test_an_operator_clock_no_echo_checks_for_3_s_is_no_longer_trusted():
    rig = following()
    rig.echo = False
    states = {}
    for _ in range(400):
        rig.step()
        states.setdefault(rig.core.teleop.state, rig.t)
        if rig.t - states[interface.FOLLOWING] == pytest.approx(1.0, abs=PERIOD_S / 2):
            report = link_report(rig)   # pings unanswered, the clock still trusted
            assert (report.fault, report.level, report.clock_known) == ('network', 2, True)
            assert 'pings unanswered' in report.detail
    assert rig.core.teleop.state == interface.FAULT
    # The first sample 3 s after the last echo (which arrived 4 ms after its step) is refused.
    assert 3.0 < states[interface.FAULT] - rig.echo_t <= 3.0 + 2 * PERIOD_S
    assert rig.core.teleop.detail.startswith(
        'puppet joint states refused: no echo from the operator host for 3.0 s')
    assert link_report(rig).clock_known is False


def test_the_link_report_names_where_the_fault_is():
    rig = ready()
    healthy = link_report(rig)
    assert (healthy.fault, healthy.level, healthy.detail) == ('none', 0, 'the link is healthy')
    values = dict(healthy.values)
    assert values['clock_offset_s'] == '37.5000' and values['rtt_s'] == '0.0040'
    assert healthy.hardware_id == interface.puppet_ns('R')
    assert healthy.diag_name == 'arm_R: ' + interface.DIAG_NETWORK
    rig.enabled = False
    for _ in range(150):   # Baxter's state times out after a second
        rig.step()
    robot = link_report(rig)
    assert (rig.core.teleop.state, robot.fault, robot.level) == (interface.NO_ROBOT, 'robot', 1)
    rig.enabled = True
    for _ in range(50):    # echoes come back, the puppet sends nothing
        rig.step(puppet=False)
    operator = link_report(rig)
    assert (operator.fault, operator.level) == ('operator', 2)
    assert 'sends no joint states' in operator.detail
    rig.step(age_s=0.25)   # usable, but late: a warning
    late = link_report(rig)
    assert (late.fault, late.level) == ('network', 1) and 'arrive 0.25 s old' in late.detail
    assert link_watch.LinkWatch.report(rig.core.link, rig.now_s(), True) is None   # 5 Hz
