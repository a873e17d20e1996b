"""link_recovery: the probe of a publisher's node (which connections count as stuck:
test_link_silence.py; the reconnection itself runs on the two-host bed:
tests/network/test_teleop_remote.py)."""
import socket
import threading
from xmlrpc.server import SimpleXMLRPCServer

import pytest

from robopuppet.link_recovery import answers


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
