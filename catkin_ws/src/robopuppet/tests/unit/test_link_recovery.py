"""link_recovery: which connections count as stuck, and the probe of a publisher's node (the
reconnection itself runs on the two-host bed: tests/network/test_teleop_remote.py)."""
import socket
import threading
from xmlrpc.server import SimpleXMLRPCServer

import pytest

from robopuppet.link_recovery import StuckConnections, answers, host_of

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
    # A publisher that went quiet of its own accord: its new connection stays silent and must
    # not be reconnected again and again.
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


@pytest.fixture
def node_uri():
    """A minimal ROS slave API (getPid) on a free local port."""
    server = SimpleXMLRPCServer(('127.0.0.1', 0), logRequests=False)
    server.register_function(lambda caller_id: [1, '', 4242], 'getPid')
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield 'http://127.0.0.1:%d/' % server.server_address[1]
    server.shutdown()
    server.server_close()


def test_answers_when_the_node_answers(node_uri):
    assert answers(node_uri, timeout_s=1.0)


def test_no_answer_from_a_closed_port():
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        port = sock.getsockname()[1]
    assert not answers('http://127.0.0.1:%d/' % port, timeout_s=0.5)


def test_no_answer_within_the_timeout_from_a_node_that_accepts_but_never_replies():
    # A stopped node (SIGSTOP) or a link that swallows the reply: the probe gives up in time.
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        sock.listen(1)
        assert not answers('http://127.0.0.1:%d/' % sock.getsockname()[1], timeout_s=0.3)
