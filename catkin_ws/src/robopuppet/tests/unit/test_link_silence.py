"""link_silence: which connections across the link count as stuck, and the retries of a
reconnection that brought nothing."""
import pytest

from robopuppet.link_silence import RETRY_SILENCES_S, StuckConnections, host_of

KEY = ('/puppet/arm_R/joint_states', 'http://10.77.0.1:40001/')


def test_a_connection_silent_after_data_is_stuck_once_the_bound_has_passed():
    stuck = StuckConnections(silent_s=1.0)
    assert stuck.update(0.0, {KEY: (1, 100)}) == {}
    assert stuck.update(0.5, {KEY: (1, 200)}) == {}
    assert stuck.update(1.4, {KEY: (1, 200)}) == {}
    assert stuck.update(1.5, {KEY: (1, 200)}) == {KEY: pytest.approx(1.0)}
    assert stuck.update(3.0, {KEY: (1, 200)}) == {KEY: pytest.approx(2.5)}


def test_data_again_clears_the_silence():
    stuck = StuckConnections(silent_s=1.0)
    stuck.update(0.0, {KEY: (1, 100)})
    assert stuck.update(2.0, {KEY: (1, 100)}) == {KEY: pytest.approx(2.0)}
    assert stuck.update(2.1, {KEY: (1, 150)}) == {}
    assert stuck.update(3.0, {KEY: (1, 150)}) == {}


def test_a_new_connection_is_not_watched_until_something_arrives_on_it():
    # A new connection this node did not make by a reconnection (rospy's own).
    stuck = StuckConnections(silent_s=1.0)
    stuck.update(0.0, {KEY: (1, 100)})
    assert KEY in stuck.update(1.5, {KEY: (1, 100)})
    assert stuck.update(1.6, {KEY: (2, 0)}) == {}
    assert stuck.update(9.0, {KEY: (2, 0)}) == {}
    stuck.update(9.1, {KEY: (2, 40)})
    assert KEY in stuck.update(10.2, {KEY: (2, 40)})


def test_a_connection_that_never_received_anything_is_never_stuck():
    stuck = StuckConnections(silent_s=1.0)
    for t in range(10):
        assert stuck.update(float(t), {KEY: (1, 0)}) == {}


def test_a_closed_connection_is_forgotten():
    stuck = StuckConnections(silent_s=1.0)
    stuck.update(0.0, {KEY: (1, 100)})
    assert stuck.update(2.0, {}) == {}
    assert stuck.update(2.5, {KEY: (1, 100)}) == {}   # back: a new start, not 2.5 s silent


def test_host_of_a_node_uri():
    assert host_of('http://10.77.0.1:40001/') == '10.77.0.1'
    assert host_of('http://robot-pc:11311') == 'robot-pc'
    assert host_of('') == ''


def test_a_reconnection_that_brings_nothing_is_tried_again_after_growing_silences():
    # The link came back, this node reconnected, and the new connection delivers nothing (made
    # while the link was not quite back): it is stuck again after each retry silence in turn.
    stuck = StuckConnections(silent_s=1.0)
    stuck.update(0.0, {KEY: (1, 100)})
    assert KEY in stuck.update(30.0, {KEY: (1, 100)})
    t, identity = 30.0, 1
    for silence in RETRY_SILENCES_S:
        stuck.reconnected([KEY])
        identity += 1
        assert stuck.update(t + 0.1, {KEY: (identity, 0)}) == {}
        assert stuck.update(t + 0.1 + silence - 0.01, {KEY: (identity, 0)}) == {}
        assert stuck.update(t + 0.1 + silence, {KEY: (identity, 0)}) == {
            KEY: pytest.approx(silence)}
        t += 0.1 + silence
    # After the last retry a quiet publisher costs no more reconnections.
    stuck.reconnected([KEY])
    assert stuck.update(t + 0.1, {KEY: (identity + 1, 0)}) == {}
    assert stuck.update(t + 100.0, {KEY: (identity + 1, 0)}) == {}


def test_data_ends_the_retries():
    stuck = StuckConnections(silent_s=1.0)
    stuck.update(0.0, {KEY: (1, 100)})
    stuck.reconnected([KEY])
    assert stuck.update(1.0, {KEY: (2, 0)}) == {}
    assert stuck.update(1.5, {KEY: (2, 30)}) == {}     # the new connection delivers
    assert KEY in stuck.update(2.6, {KEY: (2, 30)})    # then the plain bound again
    assert stuck.update(2.7, {KEY: (3, 0)}) == {}      # and rospy's own new one is unarmed
    assert stuck.update(20.0, {KEY: (3, 0)}) == {}
