"""Teleop with refused puppet samples: a stale one (too old, or of unknown age) is a silent
puppet at once, any refusal explains why nothing follows or why a fault goes on."""
import re

from robopuppet.interface import BUTTON_RIGHT, CALIBRATING, FAULT, FOLLOWING, READY
from test_teleop import NEUTRAL, STATE_TIMEOUT_S, Rig

OLD = '0.400 s old, over the 0.35 s bound (max_sample_age)'


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


def test_a_stale_sample_is_a_silent_puppet_at_once_and_baxter_stays_where_it_is():
    rig = following()
    stream(rig, 0.3)
    rig.t += 0.01
    rig.tp.on_refused(rig.t, OLD, stale=True)
    result = rig.tp.step(rig.t)
    assert rig.tp.state == FAULT and rig.tp.detail == 'puppet joint states refused: ' + OLD
    assert result.commands == {'right': NEUTRAL['right']}   # stay where Baxter is
    assert not rig.step(feed=False).commands


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
    rig.tp.on_button(rig.t, BUTTON_RIGHT)
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
        rig.tp.on_refused(rig.t, late, stale=True)
        rig.tp.step(rig.t)
        assert rig.tp.detail.endswith('; puppet joint states refused since: ' + OLD)


def test_after_a_stale_fault_only_fresh_data_and_a_press_follow_again_from_where_baxter_is():
    rig = following()
    rig.tp.on_refused(rig.t, OLD, stale=True)
    rig.step(feed=False)
    assert rig.tp.state == FAULT
    hand = list(NEUTRAL['right'])
    hand[3] += 0.4
    assert not any(stream(rig, 1.0, hand))
    assert rig.tp.state == READY
    rig.tp.on_button(rig.t, BUTTON_RIGHT)
    commands = [c['right'] for c in stream(rig, 0.5, hand)]
    assert rig.tp.state == FOLLOWING and len(commands) == 50
    previous = NEUTRAL['right']   # where Baxter is
    for command in commands:
        assert max(abs(c - p) for c, p in zip(command, previous)) <= 0.5 * 0.01 + 1e-9
        previous = command
