"""Unit tests of robopuppet.serial_link over pyserial's loop:// port (no device, no ROS)."""
import threading
import time

import serial

from robopuppet.serial_link import SerialLink


def wait_for(predicate, timeout_s=3.0):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.01)
    return False


class Recorder:
    def __init__(self):
        self.data = bytearray()
        self.connects = 0
        self.infos, self.warnings = [], []
        self.lock = threading.Lock()

    def on_connect(self):
        self.connects += 1

    def on_data(self, data):
        with self.lock:
            self.data += data

    def link(self, factory, port='loop://', retry_s=0.05):
        return SerialLink(port, 115200, self.on_connect, self.on_data, self.infos.append,
                          self.warnings.append, retry_s=retry_s, serial_factory=factory)


def loop_port(url, baud, **kwargs):
    return serial.serial_for_url('loop://', baud, **kwargs)


def test_written_bytes_come_back_through_the_reader_thread():
    rec = Recorder()
    link = rec.link(loop_port)
    link.start()
    try:
        assert wait_for(lambda: link.connected)
        assert rec.connects == 1
        assert link.write(b'\xa5\x00\x00hello')
        assert wait_for(lambda: bytes(rec.data) == b'\xa5\x00\x00hello')
    finally:
        link.stop()
    assert not link.connected
    assert not link.write(b'x')


def test_missing_port_is_logged_once_and_retried():
    attempts = []

    def missing(url, baud, **kwargs):
        attempts.append(time.monotonic())
        raise serial.SerialException(2, 'could not open port %s: no such file' % url)
    rec = Recorder()
    link = rec.link(missing, port='/dev/none')
    link.start()
    try:
        assert wait_for(lambda: len(attempts) >= 5)
    finally:
        link.stop()
    assert len(rec.warnings) == 1
    assert '/dev/none' in rec.warnings[0] and 'retrying' in rec.warnings[0]


def test_lost_port_is_reopened_and_a_failing_handler_does_not_stop_the_reader():
    ports = []

    def flaky(url, baud, **kwargs):
        port = serial.serial_for_url('loop://', baud, **kwargs)
        ports.append(port)
        return port
    rec = Recorder()
    calls = []

    def bad_handler(data):
        calls.append(data)
        raise RuntimeError('handler bug')
    link = SerialLink('loop://', 115200, rec.on_connect, bad_handler, rec.infos.append,
                      rec.warnings.append, retry_s=0.05, serial_factory=flaky)
    link.start()
    try:
        assert wait_for(lambda: link.connected)
        link.write(b'one')
        assert wait_for(lambda: calls)
        assert link.callback_errors >= 1
        link.write(b'two')
        assert wait_for(lambda: len(calls) >= 2)  # still reading after the handler failed
        ports[0].close()  # the device vanishes under the reader
        assert wait_for(lambda: len(ports) == 2 and link.connected)
        assert rec.connects == 2
        assert any('lost' in w for w in rec.warnings)
    finally:
        link.stop()
