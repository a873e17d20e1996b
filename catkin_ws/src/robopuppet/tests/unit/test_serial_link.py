"""Unit tests of protocol.serial_link over pyserial's loop:// port (no device, no ROS)."""
import termios
import threading
import time

import serial

from robopuppet.protocol.serial_link import SerialLink


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
        assert wait_for(lambda: rec.connects == 1)
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
        assert wait_for(lambda: len(ports) == 2 and rec.connects == 2)
        assert any('lost' in w for w in rec.warnings)
    finally:
        link.stop()


class FailingFirst:
    """A port factory whose first `failures` opens raise `error` (from open or from
    reset_input_buffer, as pyserial's tcsetattr/tcflush can), then opens loop:// ports."""

    def __init__(self, error, failures=1, in_reset=False):
        self.error, self.failures, self.in_reset = error, failures, in_reset
        self.attempts = 0
        self.ports = []

    def __call__(self, url, baud, **kwargs):
        self.attempts += 1
        port = serial.serial_for_url('loop://', baud, **kwargs)
        self.ports.append(port)
        if self.attempts <= self.failures:
            if not self.in_reset:
                port.close()
                raise self.error

            def failing_reset():
                raise self.error
            port.reset_input_buffer = failing_reset
        return port


def connects_after(factory):
    """Run a link on factory; return (recorder, link) once it has connected and carried data."""
    rec = Recorder()
    link = rec.link(factory)
    link.start()
    try:
        assert wait_for(lambda: rec.connects == 1), (factory.attempts, rec.warnings)
        assert link.write(b'after')
        assert wait_for(lambda: bytes(rec.data) == b'after')
    finally:
        link.stop()
    return rec, link


def test_termios_error_on_open_is_retried_and_the_link_connects():
    factory = FailingFirst(termios.error(5, 'Input/output error'))
    rec, _ = connects_after(factory)
    assert factory.attempts == 2
    assert len(rec.warnings) == 1 and 'error' in rec.warnings[0], rec.warnings


def test_termios_error_from_reset_input_buffer_is_retried_and_the_port_closed():
    factory = FailingFirst(termios.error(22, 'Invalid argument'), in_reset=True)
    rec, _ = connects_after(factory)
    assert factory.attempts == 2
    assert not factory.ports[0].is_open  # the failed port was closed, not leaked
    assert len(rec.warnings) == 1, rec.warnings


def test_any_other_failure_to_open_is_logged_once_and_retried():
    factory = FailingFirst(RuntimeError('driver bug'), failures=4)
    rec, _ = connects_after(factory)
    assert factory.attempts == 5
    assert len(rec.warnings) == 1, rec.warnings
    assert 'RuntimeError: driver bug' in rec.warnings[0]


def test_reopen_closes_and_opens_the_port_again_without_a_warning():
    ports = []

    def loop(url, baud, **kwargs):
        ports.append(serial.serial_for_url('loop://', baud, **kwargs))
        return ports[-1]
    rec = Recorder()
    link = rec.link(loop)
    link.start()
    try:
        assert wait_for(lambda: rec.connects == 1)
        link.reopen()
        assert wait_for(lambda: rec.connects == 2)
        assert not ports[0].is_open
        assert link.write(b'again')
        assert wait_for(lambda: bytes(rec.data) == b'again')
    finally:
        link.stop()
    assert rec.warnings == []
    assert len(rec.infos) == 1  # the re-open is not news


def test_a_short_write_is_a_write_error():
    class ShortPort:
        def write(self, data):
            return len(data) - 1

    link = SerialLink("x", 115200, None, None, print, print)
    link._serial = ShortPort()  # pylint: disable=protected-access
    assert not link.write(b'\xa5\x10\x01\x01')
    assert link.write_errors == 1
