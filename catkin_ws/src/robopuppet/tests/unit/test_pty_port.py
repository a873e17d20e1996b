"""Unit tests of robopuppet.puppet_sim.pty_port on real pseudo-terminals (no ROS): the link, raw
bytes both ways, polling, writes that the pty does not take, and cleanup."""
import os
import time

import pytest

from robopuppet.puppet_sim.pty_port import PtyPort


@pytest.fixture(name='port')
def fixture_port(tmp_path):
    """An open PtyPort and the host's end of it (the link opened like a serial port)."""
    port = PtyPort(str(tmp_path / 'arm_L'))
    port.open()
    host = os.open(port.link, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
    yield port, host
    os.close(host)
    port.close()


def poll_until_data(port, deadline_s=5.0):
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        chunk = port.poll(0.05, False)
        if chunk is not None and chunk.data:
            return chunk
    raise AssertionError('no bytes from the host within %g s' % deadline_s)


def test_open_points_the_link_at_the_pty_and_replaces_a_stale_one(tmp_path):
    link = tmp_path / 'arm_R'
    os.symlink('/dev/null-gone', str(link))
    port = PtyPort(str(link))
    name = port.open()
    try:
        assert os.readlink(str(link)) == name and name.startswith('/dev/pts/')
        assert not [p for p in os.listdir(str(tmp_path)) if p.endswith('.tmp')]
    finally:
        port.close()
    assert not os.path.lexists(str(link))


def test_bytes_cross_unchanged_both_ways(port):
    port, host = port
    raw = b'\xa5\r\n\x03\x04\x11\x13\x7f\x00'   # CR, LF, ^C, ^D, XON, XOFF, DEL: no tty magic
    os.write(host, raw)
    chunk = poll_until_data(port)
    assert chunk.data == raw and chunk.drained and chunk.start_s <= chunk.end_s
    assert port.write_some(raw) == len(raw)
    deadline = time.monotonic() + 5.0
    received = b''
    while len(received) < len(raw) and time.monotonic() < deadline:
        try:
            received += os.read(host, 64)
        except BlockingIOError:
            time.sleep(0.001)
    assert received == raw


def test_poll_returns_none_when_nothing_arrives(port):
    port, _ = port
    start = time.monotonic()
    assert port.poll(0.05, False) is None
    assert time.monotonic() - start >= 0.04


def test_write_some_takes_nothing_when_the_host_does_not_read(port):
    port, _ = port
    taken = [port.write_some(b'y' * 4096) for _ in range(1000)]
    assert taken[-1] == 0 and sum(taken) < 1000 * 4096


def test_close_leaves_a_link_that_someone_else_replaced(tmp_path):
    port = PtyPort(str(tmp_path / 'arm_L'))
    port.open()
    os.unlink(port.link)
    os.symlink('/dev/null', port.link)
    port.close()
    assert os.readlink(port.link) == '/dev/null'
