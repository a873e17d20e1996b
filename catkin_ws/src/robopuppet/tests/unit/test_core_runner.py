"""Unit tests of robopuppet.protocol.core_runner: the core's lock is free while a write waits."""
import threading

from robopuppet import interface, settings
from robopuppet.protocol import codec, device_commands
from robopuppet.protocol.core_runner import CoreRunner
from robopuppet.protocol.serial_core import SerialCore

PACKET_FRAMES = device_commands.USB_PACKET_BYTES // len(codec.encode(codec.JointSetpoint(0, 0.0)))


class Link:
    """The port: decodes what is written; refuses writes while `refusing`."""

    def __init__(self):
        self.connected, self.connects, self.refusing = True, 1, False
        self.decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        self.received = []

    def write(self, data):
        if self.refusing:
            return False
        self.received.extend(self.decoder.feed(data))
        return True


class Sleep:
    """A pacing sleep that blocks until released, and says when it started."""

    def __init__(self):
        self.started, self.release = threading.Event(), threading.Event()

    def __call__(self, seconds):
        assert seconds > 0.0
        self.started.set()
        assert self.release.wait(5.0), 'never released'


def rig():
    """Return a runner of a real SerialCore whose writes all fall within one pacing gap (the
    runner's clock stands still), its link, its sleep and the core's warnings."""
    link, sleep, warnings = Link(), Sleep(), []
    runner = CoreRunner(link, lambda write: SerialCore(
        write, lambda: 10.0, lambda text: None, warnings.append, 'port', 'active'),
        clock=lambda: 5.0, sleep=sleep)
    return runner, link, sleep, warnings


def in_thread(function, *args):
    thread = threading.Thread(target=function, args=args, daemon=True)
    thread.start()
    return thread


def send_setpoints(runner, count):
    for k in range(count):
        runner.call(runner.core.on_setpoint, k % settings.NUM_JOINTS, k / 4.0)


def test_bytes_from_the_reader_reach_the_core_while_a_paced_write_sleeps():
    runner, link, sleep, _ = rig()
    writer = in_thread(send_setpoints, runner, PACKET_FRAMES + 1)   # the last one waits
    assert sleep.started.wait(5.0)
    reader = in_thread(runner.call, runner.core.on_data, codec.encode(codec.Buttons(1)))
    reader.join(2.0)
    assert not reader.is_alive(), 'the reader waited for the paced write (the core lock held)'
    assert runner.core.receiver.decoder.frames == 1
    assert len(link.received) == PACKET_FRAMES   # the paced write still waits
    sleep.release.set()
    writer.join(5.0)
    assert len(link.received) == PACKET_FRAMES + 1


def test_writes_leave_in_the_order_the_core_made_them():
    runner, link, sleep, _ = rig()
    writer = in_thread(send_setpoints, runner, PACKET_FRAMES + 1)
    assert sleep.started.wait(5.0)
    other = in_thread(runner.call, runner.core.on_opmode, interface.LIMP)   # queued behind
    other.join(0.2)
    sleep.release.set()
    writer.join(5.0)
    other.join(5.0)
    assert link.received == [codec.JointSetpoint(k % settings.NUM_JOINTS, k / 4.0)
                             for k in range(PACKET_FRAMES + 1)] + [codec.Opmode(codec.LIMP)]


class FakeCore:
    def __init__(self, write):
        self.write, self.failures = write, 0

    def step_due(self):
        return False

    def on_write_failed(self):
        self.failures += 1


def test_a_queued_write_the_port_refuses_is_reported_unless_the_port_was_re_opened():
    link = Link()
    runner = CoreRunner(link, FakeCore, clock=lambda: 0.0, sleep=None)
    link.refusing = True
    assert runner.call(runner.core.write, b'\x01') == (True, False)   # queued: taken
    assert runner.core.failures == 1
    link.connected = False
    assert runner.call(runner.core.write, b'\x01') == (False, False)  # closed: refused at once
    assert runner.core.failures == 1

    def reopened_meanwhile(data):
        link.connects += 1
        return False
    link.connected, link.write = True, reopened_meanwhile
    runner.call(runner.core.write, b'\x01')
    assert runner.core.failures == 1   # the new connection's on_connect unloaded already
