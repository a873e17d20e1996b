"""Teleoperation across the bed (docs/remote.md): robot.launch on the robot host, operator.launch with
the simulated puppet (comm_rate 10, the 2020 firmware's rate) on the operator host, the right
puppet driving Baxter's right arm over a delayed, lossy link that gets cut and slowed.

Both launch files start once per module (teleop_bed.System); each test starts from a calibrated
puppet with Baxter not following and a clean link. The hand is a helper on the operator host
(helpers/puppet_hand.py); what Baxter is told and does is recorded on the robot host, what the
operator would see (teleop_state, link_state) on the operator host (helpers/ros_node.py
listeners).

Needs root (skipped otherwise) and ROS (`. tools/env.sh`). Run: tools/run_tests.py network.
"""
import bisect
import math
import time

import pytest

from robopuppet import baxter_description, interface

from teleop_bed import (MAX_SAMPLE_AGE_S, POSE, System, held_past_the_timeout, link_figures,
                        machine_stall, max_error, stamp_s)

APPROACH_SPEED_RAD_S = 0.5
LIMITS = baxter_description.arm_limits('right')
RECEPTION_JITTER_S = 0.03   # a listener's reception times jitter on a loaded machine
SINE_S = 12.0               # the hand's trajectory: 120 samples, about one lost at 1 %
ATTEMPTS = 4                # trajectories, when a stop is the machine's or a lost resend's
LONG_CUT_S = 30.0           # by then TCP resends some 25 s apart
RECOVERY_BOUND_S = 3.0      # link_recovery: 1 s of silence, a probe each 0.25 s, reconnecting


def command_items(system, since_t, until_t=math.inf):
    return [(t, msg['command']) for t, msg in system.commands.since(since_t) if t <= until_t]


def assert_commands_safe(items, velocity=True):
    """Every JointCommand is in the joint limits, and (velocity) consecutive ones never move a
    joint faster than its velocity limit allows (over the time between their receptions, plus
    jitter)."""
    assert len(items) > 50
    for (t0, a), (t1, b) in zip([(None, None)] + items[:-1], items):
        for angle, limit in zip(b, LIMITS):
            assert limit.lower <= angle <= limit.upper, (angle, limit)
        if a is None or not velocity:
            continue
        dt = max(t1 - t0, 0.0) + RECEPTION_JITTER_S
        for x, y, limit in zip(a, b, LIMITS):
            assert abs(x - y) <= limit.velocity * dt + 1e-6, (
                'joint %s moved %.4f rad in %.3f s (limit %.2f rad/s)'
                % (limit.name, abs(x - y), t1 - t0, limit.velocity))


def interpolate(series, t):
    """Return the value of a series [(t, values)] at time t (linear between its points)."""
    times = [s[0] for s in series]
    i = bisect.bisect_right(times, t)
    if i <= 0 or i >= len(series):
        return series[min(max(i - 1, 0), len(series) - 1)][1]
    (t0, a), (t1, b) = series[i - 1], series[i]
    w = (t - t0) / (t1 - t0) if t1 > t0 else 1.0
    return [x + w * (y - x) for x, y in zip(a, b)]


@pytest.fixture(scope='module')
def system(shared_bed):
    return System(shared_bed)


@pytest.fixture
def teleop(system):
    """A calibrated puppet at POSE, Baxter's right arm not following, a clean link."""
    system.rb.reset_link()
    if not hasattr(system, 'calibrated'):
        system.wait(lambda: system.robot_state() == interface.CALIBRATING, 90,
                    'arm_R calibrating with Baxter enabled')
        system.do('calibrate', pose=POSE)
        system.calibrated = True
    system.stop_following()
    system.do('hand', pose=POSE)
    yield system
    system.rb.reset_link()
    system.stop_following()


def tracking(system, since_t, until_t):
    """Return (worst error rad, swing of s0 rad) of Baxter's right arm against the hand between
    since_t and until_t: at every measurement (after the first second), Baxter's pose is the
    puppet's pose (as serial_R published it on the operator host) of some 0.02-0.5 s earlier
    (the one-way delay and jitter, a state period of 100 ms, Baxter's command and motion lag;
    a sample TCP holds back for a resend is used late or dropped, the sample behind it comes
    with it), the worst error is the largest distance from that."""
    puppet = [(t, m['position']) for t, m in system.puppet.since(since_t - 1.0) if t <= until_t]
    measured = [m for m in system.baxter_arm(since_t + 1.0) if m[0] <= until_t]
    assert len(measured) > 100 and len(puppet) > 30
    lags = [i * 0.01 for i in range(2, 51)]
    worst = 0.0
    for t, pose in measured:
        worst = max(worst, min(max_error(pose, interpolate(puppet, t - lag)) for lag in lags))
    return worst, max(m[1][0] for m in measured) - min(m[1][0] for m in measured)


def follow_the_hand(system):
    """Press 3, let Baxter close in, swing the hand, let Baxter close in again; return (press_t,
    start_t and end_t of the swing, done_t, what went wrong: [text])."""
    s = system
    press_t = time.time()
    s.follow()
    s.wait(lambda: s.baxter_on(s.puppet_angles()) or s.robot_state() == interface.FAULT, 30,
           "Baxter's right arm on the puppet pose")
    start_t = time.time()
    # A hand trajectory: joints s0 and e1 swing 0.25 rad, at most 0.52 rad/s (under the
    # approach and velocity limits, so Baxter can keep up with it).
    if s.robot_state() == interface.FOLLOWING:
        s.do('sine', pose=POSE, joints=[0, 3], amplitude_rad=0.25, period_s=3.0,
             duration_s=SINE_S)
    end_t = time.time()
    s.wait(lambda: s.baxter_on(s.puppet_angles()) or s.robot_state() != interface.FOLLOWING, 30,
           "Baxter's right arm back on the puppet pose")
    done_t = time.time()
    # What the listeners on a starved machine have yet to write down, up to done_t.
    s.wait(lambda: s.puppet.since(done_t + 1.0) and s.robot_teleop.since(done_t + 0.6), 30,
           'the listeners catching up')
    states = [m for _, m in s.robot_teleop.since(press_t)]
    on = [m['state'] for m in states].index(interface.FOLLOWING)   # follow() saw it
    wrong = ['arm_R stopped following (%s: %s)' % (m['state'], m['detail'])
             for m in states[on:] if m['state'] != interface.FOLLOWING][:1]
    if not wrong:
        worst, swing = tracking(s, start_t, end_t)
        if worst >= 0.03:
            wrong.append('Baxter off the delayed hand trajectory by %.3f rad' % worst)
        if swing <= 0.4:
            wrong.append('Baxter did not follow the swing (s0 moved %.3f rad)' % swing)
    return press_t, start_t, end_t, done_t, wrong


# 50 +- 10 ms one way (round trips of about 0.1 s, so arm_X counts every sample some 0.05 s
# older than it is), without and with 1 % loss. TCP resends a lost sample of the
# firmware's 10 Hz stream a round trip after the next sample; one that then arrives over the
# 0.35 s bound is dropped, not followed, and arm_R goes on with the sample behind it.
# Baxter stops, rightly, when no usable sample comes for the state timeout: when the machine,
# which other work starves, stalls the puppet's stream, the bed's forwarder or arm_R itself, or
# when TCP holds a sample back longer (a lost resend: rare at 1 %). Such an attempt is run again
# (at most ATTEMPTS in all), saying why; the last must be clean, and any other stop fails.
@pytest.mark.parametrize('delay_ms, jitter_ms, loss', [(50, 10, 0.0), (50, 10, 0.01)])
def test_follows_over_a_delayed_lossy_link_within_limits(teleop, delay_ms, jitter_ms, loss):
    s = teleop
    s.rb.bed.set(delay_ms=delay_ms, jitter_ms=jitter_ms, loss=loss)
    first_t, attempts = time.time(), []
    for attempt in range(1, ATTEMPTS + 1):
        press_t, start_t, end_t, done_t, wrong = follow_the_hand(s)
        void = (machine_stall(s, press_t, done_t) or held_past_the_timeout(s, press_t)
                if wrong else '')
        attempts.append('attempt %d: %s; %s' % (attempt, link_figures(s, start_t, end_t),
                                                '; '.join(wrong + ['void: ' + void] if void
                                                          else wrong) or 'clean'))
        print(attempts[-1])
        if not void:
            break
    assert not wrong, '\n'.join(attempts)
    status = s.rb.bed.status()['links']
    assert (status['to-robot']['lost'] > 0) == (loss > 0), status['to-robot']
    assert s.robot_state() == interface.FOLLOWING
    assert_commands_safe(command_items(s, press_t))
    assert_commands_safe(command_items(s, first_t), velocity=False)   # any void attempts too


def test_cut_stops_baxter_and_restore_needs_a_new_press(teleop):
    s = teleop
    s.rb.bed.set(delay_ms=20, jitter_ms=5)
    s.follow()
    s.wait(lambda: s.baxter_on(s.puppet_angles()), 30,
           "Baxter's right arm on the puppet pose")
    moved = list(POSE)
    moved[0] += 0.2
    s.do('hand', pose=moved)
    time.sleep(1.0)
    # Cut while the hand moves back: arm_R's target changes until the cut.
    s.do('hand', pose=POSE)
    time.sleep(0.15)
    s.rb.bed.cut()
    cut_t = time.time()
    s.wait(lambda: s.robot_state() == interface.FAULT, 10, 'teleop FAULT on the robot host')
    far = list(POSE)
    far[0] -= 0.25
    s.do('hand', pose=far)  # the puppet moves on during the cut: a new target for later
    time.sleep(3.0)
    items = command_items(s, cut_t - 2.0)
    changes = [t for (t0, a), (t, b) in zip(items, items[1:]) if max_error(a, b) > 1e-9]
    assert changes and changes[0] < cut_t, 'Baxter was not being commanded before the cut'
    assert changes[-1] - cut_t < interface.STOP_WITHIN_S, (
        'a command moving Baxter came %.3f s after the cut' % (changes[-1] - cut_t))
    # What comes after is the stay command: Baxter's measured pose, and Baxter stays there.
    late = command_items(s, cut_t + interface.STOP_WITHIN_S)
    held = s.baxter_arm(time.time() - 0.5)[-1][1]
    for _, command in late:
        assert max_error(command, held) < 0.01
    detail = s.robot_teleop.last()['detail']
    assert 'joint states' in detail, detail

    # Restore: fresh data again, but nothing moves until a new press.
    s.rb.bed.restore()
    restore_t = time.time()
    s.wait(lambda: s.puppet_angles() and s.robot_teleop.since(restore_t), 10,
           'teleop_state after the restore')
    time.sleep(3.0)
    quiet = s.baxter_arm(restore_t)
    assert max(max_error(pose, held) for _, pose in quiet) < 0.005, 'Baxter moved unpressed'
    assert all(msg['state'] != interface.FOLLOWING for _, msg in s.robot_teleop.since(restore_t))
    assert all(max_error(c, held) < 0.01 for _, c in command_items(s, restore_t))

    # The press: a slow approach (at most ~approach_speed) to the puppet, then on it.
    target = s.puppet_angles()
    assert max_error(held, target) > 0.1, 'nothing to approach: the test moved too little'
    press_t = time.time()
    s.follow()
    s.wait(lambda: s.baxter_on(target), 30,
           "Baxter's right arm on the puppet pose after the press")
    approach = command_items(s, press_t)
    for (t0, a), (t1, b) in zip(approach, approach[1:]):
        speed = max_error(a, b) / (max(t1 - t0, 0.0) + RECEPTION_JITTER_S)
        assert speed <= APPROACH_SPEED_RAD_S * 1.05, 'approach at %.2f rad/s' % speed
    first = approach[0][1]
    assert max_error(first, held) < 0.05, 'the first command after the press jumped'


def test_growing_delay_stops_following_with_the_reason_on_both_hosts(teleop):
    # The delay grows within a few seconds, from a link where arm_R follows: arm_R's clock
    # estimate keeps the short round trips of the last 5 s (link_clock.CLOCK_WINDOW), so the
    # sample age is what tells (arm_R counts half the shortest round trip on top of it).
    s = teleop
    s.rb.bed.set(delay_ms=10)
    s.follow()
    start_t = time.time()
    for delay_ms in (150, 250):
        s.rb.bed.set(delay_ms=delay_ms)
        time.sleep(1.0)
        assert s.robot_state() == interface.FOLLOWING, (
            'stopped at %d ms one way (under the %.2f s bound): %s'
            % (delay_ms, MAX_SAMPLE_AGE_S, s.robot_teleop.last()))
    s.rb.bed.set(delay_ms=400)
    over_t = time.time()
    s.wait(lambda: s.robot_state() == interface.FAULT, 10, 'teleop FAULT on the robot host')
    fault_t = time.time()
    assert fault_t - over_t < 2.0
    detail = s.robot_teleop.last()['detail']
    # Late samples are dropped; none usable for the state timeout: stale, the newest one's age.
    assert 'stale' in detail and 'old' in detail, detail
    assert '%.2f s bound' % MAX_SAMPLE_AGE_S in detail, detail
    # The operator host (what the GUI shows) gets the FAULT and a link_state naming the network.
    s.wait(lambda: any(m['state'] == interface.FAULT for _, m in s.op_teleop.since(start_t)), 10,
           'teleop_state FAULT on the operator host')
    # The first late samples are dropped with a warning; then no usable one: ERROR.
    link = s.wait(lambda: [m for _, m in s.op_link.since(over_t)
                           if m['fault'] == 'network' and m['sample_age'] > MAX_SAMPLE_AGE_S
                           and m['level'] == 2], 10,
                  "link_state with fault 'network', level ERROR and the sample age over the "
                  'bound on the operator host')[-1]
    assert 'too late' in link['detail'], link
    assert link['max_sample_age'] == pytest.approx(MAX_SAMPLE_AGE_S)
    op_detail = [m for _, m in s.op_teleop.since(start_t) if m['state'] == interface.FAULT][-1]
    assert 'bound' in op_detail['detail'], op_detail


def test_after_a_long_cut_both_hosts_hear_each_other_again_within_a_bound(teleop):
    # A 30 s cut, then the link back: arm_R (robot host) takes the puppet's samples again (it
    # leaves its FAULT for ready) and the operator host hears arm_R again (a link_state stamped
    # after the restore, as gui_R would), each within RECOVERY_BOUND_S of the restore; TCP's
    # resends alone took some 25 s (link_recovery, docs/remote.md "After a cut").
    s = teleop
    s.rb.bed.set(delay_ms=20, jitter_ms=5)
    s.wait(lambda: s.robot_state() == interface.READY, 20, 'arm_R ready')
    s.rb.bed.cut()
    cut_t = time.time()
    s.wait(lambda: s.robot_state() == interface.FAULT, 10, 'teleop FAULT on the robot host')
    time.sleep(max(0.0, cut_t + LONG_CUT_S - time.time()))
    s.rb.bed.restore()
    restore_t = time.time()
    robot_t = s.wait(lambda: [t for t, m in s.robot_teleop.since(restore_t)
                              if m['state'] == interface.READY], 60,
                     'arm_R ready after the restore')[0]
    operator_t = s.wait(lambda: [t for t, m in s.op_link.since(restore_t)
                                 if stamp_s(m) > restore_t], 60,
                        'a fresh link_state on the operator host after the restore')[0]
    print('after a %.0f s cut: arm_R ready %.2f s after the restore; the operator host heard a '
          'fresh link_state %.2f s after it' % (LONG_CUT_S, robot_t - restore_t,
                                                operator_t - restore_t))
    assert robot_t - restore_t < RECOVERY_BOUND_S
    assert operator_t - restore_t < RECOVERY_BOUND_S
