"""Teleop with refused puppet samples: one of unknown age makes the stream stale, a silent
puppet at once; a late one (too old) is dropped, and only the state timeout without a usable one
is a silent puppet, named stale with the newest late age; any refusal explains why nothing
follows or why a fault goes on."""
import re

from robopuppet.interface import BUTTON_RIGHT, CALIBRATING, FAULT, FOLLOWING, READY
from test_teleop import NEUTRAL, STATE_TIMEOUT_S, Rig

OLD = '0.400 s old, over the 0.35 s bound (max_sample_age)'
UNKNOWN = ('no echo from the operator host for 3.0 s: its clock is no longer trusted, the age '
           'of puppet samples is unknown')


def stream(rig, seconds, angles=None):
    """Feed usable joint states every 0.1 s, stepping at 100 Hz; return the steps' commands."""
    commands = []
    for k in range(int(round(seconds / 0.01))):
        rig.t += 0.01
        if k % 10 == 9:
            rig.feed(angles=angles)
        commands.append(rig.tp.step(rig.t).commands)
    return commands


def following():
    rig = Rig()
    rig.robot()
    rig.step()
    rig.press(BUTTON_RIGHT)
    assert rig.tp.state == FOLLOWING
    return rig


def test_a_sample_of_unknown_age_is_a_silent_puppet_at_once_and_baxter_stays_where_it_is():
    rig = following()
    stream(rig, 0.3)
    rig.t += 0.01
    rig.tp.on_refused(rig.t, UNKNOWN, stale=True)
    result = rig.tp.step(rig.t)
    assert rig.tp.state == FAULT and rig.tp.detail == 'puppet joint states refused: ' + UNKNOWN
    assert result.commands == {'right': NEUTRAL['right']}   # stay where Baxter is
    assert not rig.step(feed=False).commands


def test_a_late_sample_among_usable_ones_is_only_dropped():
    rig = following()
    for _ in range(5):
        stream(rig, 0.3)
        rig.tp.on_refused(rig.t, OLD, late=True)
    stream(rig, 0.3)
    assert rig.tp.state == FOLLOWING


def test_late_samples_for_the_state_timeout_are_a_stale_stream_named_by_the_newest_age():
    rig = following()
    stream(rig, 0.3)
    last_t, steps = rig.t, []
    for k in range(45):   # late samples every 0.1 s, the newest 0.4xx s old: none usable
        rig.t += 0.01
        if k % 10 == 9:
            rig.tp.on_refused(rig.t, '0.4%d0 s old, over the 0.35 s bound (max_sample_age)'
                              % (k // 10), late=True)
        steps.append((rig.t, rig.tp.step(rig.t).commands, rig.tp.state))
    fault_t = next(t for t, _, state in steps if state == FAULT)
    assert all(state == FOLLOWING for t, _, state in steps if t < fault_t)
    assert STATE_TIMEOUT_S < fault_t - last_t <= STATE_TIMEOUT_S + 0.01 + 1e-9
    assert re.fullmatch(r'puppet joint states refused: stale, none usable for 0\.4\d s: the '
                        r'newest 0\.430 s old, over the 0\.35 s bound \(max_sample_age\)',
                        rig.tp.detail)
    assert [c for t, c, _ in steps if t == fault_t] == [{'right': NEUTRAL['right']}]


def test_a_sample_that_is_refused_but_not_stale_is_only_ignored():
    rig = following()
    for _ in range(3):
        stream(rig, 0.1)
        rig.tp.on_refused(rig.t, 'out of order: stamped 0.050 s before one already used')
    stream(rig, 0.1)
    assert rig.tp.state == FOLLOWING


def test_refused_samples_say_why_nothing_follows_yet():
    rig = Rig()
    rig.robot()
    rig.tp.on_refused(rig.t, "waiting for the operator host's echo", stale=True)
    rig.tp.on_button(BUTTON_RIGHT)
    assert not rig.step(feed=False).commands
    assert rig.tp.state == CALIBRATING
    assert rig.tp.detail == "no usable puppet joint states yet: waiting for the operator " \
                            "host's echo"


def test_silence_names_the_samples_refused_meanwhile_and_a_fault_says_once_why_it_goes_on():
    rig = following()
    stream(rig, 0.3)
    rig.t += 0.01
    rig.tp.on_refused(rig.t, 'out of order: stamped 0.050 s before one already used')
    for _ in range(50):
        rig.t += 0.01
        rig.tp.step(rig.t)
    assert rig.tp.state == FAULT
    assert re.fullmatch(r'no joint states from the puppet for 0\.4\d s; newer ones refused: '
                        'out of order: stamped 0.050 s before one already used', rig.tp.detail)
    assert STATE_TIMEOUT_S == 0.4
    for late in (OLD, '0.410 s old'):   # late samples keep coming; the detail changes once
        rig.t += 0.1
        rig.tp.on_refused(rig.t, late, late=True)
        rig.tp.step(rig.t)
        assert rig.tp.detail.endswith('; puppet joint states refused since: ' + OLD)


def test_after_a_stale_fault_only_fresh_data_and_a_press_follow_again_from_where_baxter_is():
    rig = following()
    rig.tp.on_refused(rig.t, UNKNOWN, stale=True)
    rig.step(feed=False)
    assert rig.tp.state == FAULT
    hand = list(NEUTRAL['right'])
    hand[3] += 0.4
    assert not any(stream(rig, 1.0, hand))
    assert rig.tp.state == READY
    rig.tp.on_button(BUTTON_RIGHT)
    commands = [c['right'] for c in stream(rig, 0.5, hand)]
    assert rig.tp.state == FOLLOWING and len(commands) == 50
    previous = NEUTRAL['right']   # where Baxter is
    for command in commands:
        assert max(abs(c - p) for c, p in zip(command, previous)) <= 0.5 * 0.01 + 1e-9
        previous = command
