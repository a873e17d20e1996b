"""Unit tests of robopuppet.protocol.link_health: the silence watch and the diagnostics level."""
import math

import pytest
from diagnostic_msgs.msg import DiagnosticStatus

from robopuppet import interface
from robopuppet.protocol import link_health as lh


def test_levels_are_diagnostic_msgs_levels():
    assert (lh.OK, lh.WARN, lh.ERROR) == (DiagnosticStatus.OK, DiagnosticStatus.WARN,
                                          DiagnosticStatus.ERROR)


def test_silence_is_not_watched_before_a_connect_nor_while_the_port_is_closed():
    watch = lh.SilenceWatch(3.0)
    assert watch.due_s(True) == math.inf and watch.check(100.0, True) is None
    watch.on_connect(0.0)
    assert watch.due_s(False) == math.inf and watch.check(100.0, False) is None


def test_silence_re_opens_after_the_timeout_then_every_wake_period_until_frames_come():
    watch = lh.SilenceWatch(3.0, wake_s=1.0)
    watch.on_connect(10.0)
    watch.on_frames(11.0)
    assert watch.due_s(True) == 14.0
    assert watch.check(13.9, True) is None and not watch.silent
    assert watch.check(14.2, True) == pytest.approx(3.2)
    assert watch.silent and watch.due_s(True) == pytest.approx(15.2)
    watch.on_connect(14.3)  # the re-open: still silent
    assert watch.silent and watch.check(15.0, True) is None
    assert watch.check(15.3, True) == pytest.approx(1.0)
    assert watch.on_frames(15.5) is True  # it talks again
    assert not watch.silent and watch.on_frames(15.6) is False
    assert watch.due_s(True) == pytest.approx(18.6)


def health(**changes):
    fields = dict(connected=True, port='/dev/ttyACM0', silent=False, loaded=True, revision=3,
                  publishers=1, heartbeat_age_s=0.5, rate_problem=None, new_errors=0,
                  last_error='')
    fields.update(changes)
    return lh.Health(**fields)


@pytest.mark.parametrize('changes, level, text', [
    ({}, lh.OK, 'link up'),
    (dict(connected=False, silent=True, loaded=False), lh.ERROR, 'link down: /dev/ttyACM0'),
    (dict(silent=True, loaded=False), lh.ERROR, 'device silent'),
    (dict(loaded=False, revision=None, publishers=0), lh.WARN,
     'waiting for settings: none received on %s yet (0 publishers)' % interface.ACTIVE_SETTINGS),
    (dict(loaded=False, heartbeat_age_s=None), lh.WARN, 'loading settings (revision 3)'),
    (dict(heartbeat_age_s=interface.HEARTBEAT_TIMEOUT_S + 0.1, publishers=0), lh.WARN,
     'no heartbeat'),
    (dict(heartbeat_age_s=None), lh.WARN, 'no heartbeat'),
    (dict(publishers=0, rate_problem='too slow'), lh.WARN,
     'setting changes do not reach the puppet'),
    (dict(rate_problem='too slow', new_errors=2), lh.WARN, 'link up; too slow'),
    (dict(new_errors=2, last_error='worker: KeyError: 3'), lh.WARN, '2 callback errors'),
])
def test_the_worst_problem_decides_level_and_message(changes, level, text):
    got_level, message = lh.level_and_message(health(**changes))
    assert got_level == level and text in message, message
