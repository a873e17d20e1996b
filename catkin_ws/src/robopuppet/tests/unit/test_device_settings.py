"""Unit tests of robopuppet.device_settings with a fake get_config and link (no ROS master)."""
import time

import rospy

from robopuppet import codec, config_store, device_settings, settings
from robopuppet_msgs.srv import GetConfigResponse

ID = settings.CONFIG_ID


class FakeConfigNode:
    """Serves get_config from a dict; can be down."""

    def __init__(self):
        self.config = config_store.defaults()
        self.config[3]['home_angle'] = 0.5
        self.up = True
        self.calls = 0

    def wait_for_service(self, timeout):
        if not self.up:
            raise rospy.ROSException('timeout exceeded while waiting for service')

    def __call__(self, joint):
        self.calls += 1
        return GetConfigResponse(**self.config[joint])


class Device:
    """The link: decodes what is written; write() fails while disconnected."""

    def __init__(self):
        self.decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        self.received = []
        self.connected = True
        self.on_write = None

    def write(self, data):
        if not self.connected:
            return False
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
