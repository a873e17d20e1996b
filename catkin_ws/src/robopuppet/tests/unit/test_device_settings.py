"""Unit tests of robopuppet.protocol.device_settings with a fake get_config and link (no ROS master)."""
import math
import threading
import time

import rospy

from robopuppet import settings
from robopuppet.config import config_store
from robopuppet.protocol import codec, device_settings
from robopuppet_msgs.srv import GetConfigResponse

ID = settings.CONFIG_ID


class FakeConfigNode:
    """Serves get_config from a dict; can be down, or hung (a call blocks until released)."""

    def __init__(self):
        self.config = config_store.defaults()
        self.config[3]['home_angle'] = 0.5
        self.up = True
        self.running = threading.Event()  # cleared: hung, like a SIGSTOPped node
        self.running.set()
        self.calls = 0

    def wait_for_service(self, timeout):
        if not self.up:
            raise rospy.ROSException('timeout exceeded while waiting for service')

    def __call__(self, joint):
        self.running.wait()
        self.calls += 1
        return GetConfigResponse(**self.config[joint])


class Device:
    """The link: decodes what is written; write() fails while disconnected."""

    def __init__(self):
        self.decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        self.received = []
        self.writes = []  # (monotonic time, data) of every write
        self.connected = True
        self.on_write = None

    def write(self, data):
        if not self.connected:
            return False
        self.writes.append((time.monotonic(), data))
        self.received.extend(self.decoder.feed(data))
        if self.on_write is not None:
            self.on_write()
        return True

    def take(self):
        received, self.received = self.received, []
        return received


def make():
    device = Device()
    node = FakeConfigNode()
    sync = device_settings.DeviceSettings('/puppet/arm_L', device.write, '/serial_L', 'pty')
    sync._get_config = node  # pylint: disable=protected-access
    sync._caller = device_settings.TimedCaller(0.3, 2)  # pylint: disable=protected-access
    return sync, device, node


def step_until(sync, predicate, timeout_s=3.0):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        sync.step(True)
        if predicate():
            return True
        time.sleep(0.02)
    return False


def test_a_connect_loads_all_84_settings_then_limp():
    sync, device, _ = make()
    assert not sync.loaded
    sync.unload(load=True)
    sync.step(True)
    received = device.take()
    assert sync.loaded
    assert len(received) == 85 and received[-1] == codec.Opmode(codec.LIMP)
    assert codec.JointConfig(3, ID['home_angle'], 0.5) in received
    assert {(m.joint, m.config_id) for m in received[:-1]} == {
        (j, i) for j in settings.JOINTS for i in range(len(settings.NAMES))}


def test_no_load_while_the_config_node_is_down_and_a_retry_after_it_is_up():
    sync, device, node = make()
    node.up = False
    sync.unload(load=True)
    sync.step(True)
    assert not sync.loaded and device.take() == []
    node.up = True
    sync.step(True)  # the retry waits about a second
    assert not sync.loaded
    assert step_until(sync, lambda: sync.loaded)
    assert len(device.take()) == 85


def test_a_reconnect_during_the_load_means_not_loaded_and_load_again():
    sync, device, _ = make()
    sync.unload(load=True)
    device.on_write = lambda: sync.unload(load=True)  # the port is re-opened meanwhile
    sync.step(True)
    assert not sync.loaded
    device.on_write = None
    sync.step(True)
    assert sync.loaded


def test_a_silent_device_gets_no_load_until_asked():
    sync, device, _ = make()
    sync.unload(load=False)
    sync.step(True)
    assert not sync.loaded and device.take() == []


def test_a_marked_joint_gets_what_the_config_node_stored_not_the_message():
    sync, device, node = make()
    sync.unload(load=True)
    sync.step(True)
    device.take()
    calls = node.calls
    node.config[2]['pid_kp'] = 4.0  # stored by the config node
    for _ in range(5):  # a burst of messages: one read
        sync.mark(2)
    marked = time.monotonic()
    sync.step(True)
    assert device.take() == []  # not yet: the config node may not have stored it
    assert step_until(sync, lambda: device.received)
    assert time.monotonic() - marked >= device_settings.RESYNC_AFTER_S[0]
    assert device.take() == [codec.JointConfig(2, ID['pid_kp'], 4.0)]
    assert node.calls == calls + 1
    # A refused value: the config node still has the old one, so nothing is sent.
    sync.mark(2)
    assert step_until(sync, lambda: node.calls == calls + 2)
    assert device.take() == []


def test_a_marked_joint_is_read_again_later_for_a_slow_config_node():
    sync, device, node = make()
    sync.unload(load=True)
    sync.step(True)
    device.take()
    sync.mark(5)
    calls = node.calls
    assert step_until(sync, lambda: node.calls == calls + 1)
    node.config[5]['sign_motor'] = -1.0  # stored only after the first read
    assert step_until(sync, lambda: device.received, device_settings.RESYNC_AFTER_S[1] + 1.0)
    assert device.take() == [codec.JointConfig(5, ID['sign_motor'], -1.0)]


class FirmwareAngles:
    """The 2020 firmware's angle (DESIGN section 3): sign_angle x wrap(raw - stored_home), where
    stored_home = home_angle x the sign_angle in force when the home frame arrived."""

    def __init__(self):
        self.sign = [1.0] * settings.NUM_JOINTS
        self.stored_home = [0.0] * settings.NUM_JOINTS

    def feed(self, messages):
        for m in messages:
            if isinstance(m, codec.JointConfig) and m.config_id == ID['sign_angle']:
                self.sign[m.joint] = m.value
            elif isinstance(m, codec.JointConfig) and m.config_id == ID['home_angle']:
                self.stored_home[m.joint] = m.value * self.sign[m.joint]

    def angle(self, joint, raw_rad):
        wrapped = math.remainder(raw_rad - self.stored_home[joint], 2 * math.pi)
        return self.sign[joint] * wrapped


def loaded(sync, device):
    sync.unload(load=True)
    sync.step(True)
    assert sync.loaded
    return device.take()


def test_signs_go_before_home_angle_for_every_joint():
    sync, device, _ = make()
    received = loaded(sync, device)
    for joint in settings.JOINTS:
        ids = [m.config_id for m in received
               if isinstance(m, codec.JointConfig) and m.joint == joint]
        assert ids.index(ID['sign_angle']) < ids.index(ID['home_angle'])
        assert ids.index(ID['sign_motor']) < ids.index(ID['home_angle'])


def test_loading_the_same_settings_twice_gives_the_same_angles():
    sync, device, node = make()
    node.config[1].update(home_angle=-0.22, sign_angle=-1.0)
    firmware = FirmwareAngles()
    firmware.feed(loaded(sync, device))
    first = firmware.angle(1, 0.5)
    firmware.feed(loaded(sync, device))  # a reconnect: the device still holds sign -1
    assert firmware.angle(1, 0.5) == first
    assert abs(first - (-1.0) * (0.5 - 0.22)) < 1e-6


def test_a_change_of_sign_angle_alone_re_sends_home_angle_after_it():
    sync, device, node = make()
    node.config[1].update(home_angle=-0.25, sign_angle=-1.0)
    firmware = FirmwareAngles()
    firmware.feed(loaded(sync, device))
    node.config[1]['sign_angle'] = 1.0  # the GUI changes the sign only
    sync.mark(1)
    assert step_until(sync, lambda: device.received)
    sent = device.take()
    assert sent == [codec.JointConfig(1, ID['sign_angle'], 1.0),
                    codec.JointConfig(1, ID['home_angle'], -0.25)]
    firmware.feed(sent)
    fresh = FirmwareAngles()
    fresh.feed(loaded(sync, device))
    assert firmware.angle(1, 0.5) == fresh.angle(1, 0.5)


def test_a_load_is_whole_frames_in_writes_of_at_most_64_bytes_with_pauses():
    sync, device, _ = make()
    loaded(sync, device)
    decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
    for _, data in device.writes:
        assert len(data) <= 64
        decoder.feed(data)
        assert decoder.pending == 0  # the write ends on a frame boundary
    assert decoder.frames == 85 and decoder.dropped_bytes == 0
    gaps = [b[0] - a[0] for a, b in zip(device.writes, device.writes[1:])]
    assert len(gaps) >= 12 and min(gaps) >= 0.0015


def test_the_epoch_rises_at_unload_and_after_the_loads_limp():
    sync, device, _ = make()
    epochs = []
    device.on_write = lambda: epochs.append(sync.epoch)
    start = sync.epoch
    sync.unload(load=True)
    assert sync.epoch == start + 1
    sync.step(True)
    assert epochs[-1] == start + 1  # the limp frame is written before the rise
    assert sync.epoch == start + 2


def test_a_hung_config_node_costs_each_step_at_most_the_timeout_and_a_reload_follows():
    sync, device, node = make()
    node.running.clear()  # SIGSTOP
    sync.unload(load=True)  # a replug during the freeze
    for _ in range(4):  # the first two calls hang; then no more are started
        began = time.monotonic()
        sync.step(True)
        assert time.monotonic() - began < 0.3 + 0.2
        assert not sync.loaded and device.take() == []
        assert sync.config_status == device_settings.UNREACHABLE
        sync._next_load_s = 0.0  # pylint: disable=protected-access  # retry at once
    assert sync.stuck_calls == 2
    node.running.set()  # SIGCONT: the hanging calls return
    assert step_until(sync, lambda: sync.loaded)
    assert len(device.take()) == 85
    assert sync.stuck_calls == 0 and sync.config_status == device_settings.REACHABLE


def test_an_absent_config_node_is_not_running_and_a_loaded_node_probes_it():
    sync, device, node = make()
    node.up = False
    sync.unload(load=True)
    sync.step(True)
    assert sync.config_status == device_settings.ABSENT
    node.up = True
    assert step_until(sync, lambda: sync.loaded)
    node.running.clear()  # hangs while idle: the probe finds out
    sync._next_probe_s = 0.0  # pylint: disable=protected-access
    sync.step(True)
    assert sync.config_status == device_settings.UNREACHABLE
    node.running.set()


def test_timed_caller_returns_raises_and_times_out():
    caller = device_settings.TimedCaller(0.2, 1)
    assert caller.call(lambda x: x + 1, 1) == 2
    try:
        caller.call(lambda: 1 / 0)
        raise AssertionError('no ZeroDivisionError')
    except ZeroDivisionError:
        pass
    release = threading.Event()
    for _ in range(2):  # the second is not even started
        try:
            caller.call(release.wait)
            raise AssertionError('no timeout')
        except device_settings.CallTimeout:
            pass
    assert caller.stuck == 1
    release.set()
    deadline = time.monotonic() + 2.0
    while caller.stuck and time.monotonic() < deadline:
        time.sleep(0.01)
    assert caller.stuck == 0 and caller.call(lambda: 'ok') == 'ok'
