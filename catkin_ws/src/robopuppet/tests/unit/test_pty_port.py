"""Unit tests of robopuppet.puppet_sim.pty_port on real pseudo-terminals (no ROS): the link, raw
bytes both ways, polling, writes that the pty does not take, and cleanup."""
import os
import signal
import subprocess
import sys
import time

import pytest

from robopuppet.puppet_sim.pty_port import LOCK_SUFFIX, LinkBusy, PtyPort


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
    assert not os.path.lexists(str(link) + LOCK_SUFFIX)


def test_open_makes_the_links_folder(tmp_path):
    port = PtyPort(str(tmp_path / 'ros_home' / 'robopuppet' / 'pty_arm_R'))
    try:
        name = port.open()
        assert os.readlink(port.link) == name
    finally:
        port.close()


def test_a_second_port_neither_takes_nor_removes_a_live_ports_link(port):
    port, host = port
    name = os.readlink(port.link)
    second = PtyPort(port.link)
    with pytest.raises(LinkBusy, match='pid %d' % os.getpid()):
        second.open()
    second.close()
    assert os.readlink(port.link) == name
    os.write(host, b'still ours')
    assert poll_until_data(port).data == b'still ours'


HOLDER = """
import sys, time
from robopuppet.puppet_sim.pty_port import PtyPort
PtyPort(sys.argv[1]).open()
print('open', flush=True)
time.sleep(60)
"""


@pytest.fixture(name='holder')
def fixture_holder(tmp_path):
    """Another process that owns tmp_path/arm_L; killed at the end."""
    link = str(tmp_path / 'arm_L')
    proc = subprocess.Popen([sys.executable, '-c', HOLDER, link], stdout=subprocess.PIPE,
                            env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    assert proc.stdout.readline() == b'open\n'
    yield proc, link
    proc.kill()
    proc.wait()


def test_another_process_keeps_its_link_until_it_ends_then_a_new_port_takes_it(holder):
    proc, link = holder
    theirs = os.readlink(link)
    with pytest.raises(LinkBusy, match='pid %d' % proc.pid):
        PtyPort(link).open()
    assert os.readlink(link) == theirs and proc.poll() is None
    proc.send_signal(signal.SIGKILL)  # a crash: its link stays behind, its lock goes
    proc.wait()
    port = PtyPort(link)
    try:
        name = port.open()  # the dead one's pty number may come back: compare the owner
        assert os.readlink(link) == name
        with open(link + LOCK_SUFFIX) as lock:
            assert lock.read() == 'pid %d\n' % os.getpid()
    finally:
        port.close()
    assert not os.path.lexists(link)


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
