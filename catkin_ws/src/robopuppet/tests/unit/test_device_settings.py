"""Unit tests of robopuppet.protocol.device_settings: a fake clock and a decoding fake device."""
import math

import pytest

from robopuppet import settings
from robopuppet.protocol import codec, device_commands, device_settings

ID = settings.CONFIG_ID
SOURCE = '/puppet/arm_L/stored_settings'
PAUSE_S = device_commands.LOAD_PAUSE_S


class Clock:
    """Monotonic seconds that move only when the test says so."""

    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


class Device:
    """The link: decodes every write; write() fails while `connected` is False."""

    def __init__(self, clock):
        self.clock = clock
        self.decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        self.received = []
        self.writes = []  # (clock time, data)
        self.connected = True
        self.on_write = None

    def write(self, data):
        if self.on_write is not None:
            self.on_write()
        if not self.connected:
            return False
        self.writes.append((self.clock(), data))
        self.received.extend(self.decoder.feed(data))
        return True

    def take(self):
        received, self.received = self.received, []
        return received


class Log:
    def __init__(self):
        self.infos, self.warnings = [], []


def stored_settings(**changes):
    """Return {joint: {name: value}}: the defaults, each joint's home_angle 0.125 x joint, and
    changes given as joint_name=value (e.g. j2_pid_kp=4.0)."""
    stored = {j: dict(settings.DEFAULTS, home_angle=0.125 * j) for j in settings.JOINTS}
    for key, value in changes.items():
        joint, name = key[1:].split('_', 1)
        stored[int(joint)][name] = value
    return stored


def make():
    clock, log = Clock(), Log()
    device = Device(clock)
    sync = device_settings.DeviceSettings(device.write, clock, log.infos.append,
                                          log.warnings.append, SOURCE)
    return sync, device, clock, log


def store(sync, stored, revision=1):
    sync.on_stored(revision, sorted(stored.items()))


def step_when_due(sync, clock):
    clock.now = max(clock.now, sync.next_step_s)
    sync.step()


def run(sync, clock, steps=100):
    """Step whenever the core has work, moving the clock to its due time; return the steps."""
    for count in range(steps):
        due = sync.next_step_s
        if due == math.inf:
            return count
        clock.now = max(clock.now, due)
        sync.step()
    raise AssertionError('still busy after %d steps' % steps)


def loaded(stored=None):
    """Return (sync, device, clock, log) with the device loaded with stored (default settings)."""
    sync, device, clock, log = make()
    store(sync, stored or stored_settings())
    sync.unload()
    run(sync, clock)
    assert sync.loaded_since_s is not None
    device.take()
    return sync, device, clock, log


def config(joint, name, value):
    return codec.JointConfig(joint, ID[name], value)


def test_nothing_is_written_before_the_first_connect():
    sync, device, clock, _ = make()
    store(sync, stored_settings())
    assert sync.next_step_s == math.inf
    sync.step()
    assert device.writes == [] and sync.loaded_since_s is None


def test_a_connect_loads_all_84_settings_then_limp_in_whole_frame_writes_with_pauses():
    sync, device, clock, _ = make()
    stored = stored_settings(j3_home_angle=0.5)
    store(sync, stored, revision=4)
    sync.unload()
    run(sync, clock)
    received = device.take()
    assert len(received) == 85 and received[-1] == codec.Opmode(codec.LIMP)
    assert {(m.joint, m.config_id): m.value for m in received[:-1]} == pytest.approx({
        (j, ID[n]): stored[j][n] for j in settings.JOINTS for n in settings.NAMES}, rel=1e-7)
    decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
    for _, data in device.writes:
        assert len(data) <= 64
        decoder.feed(data)
        assert decoder.pending == 0  # each write ends on a frame boundary
    times = [t for t, _ in device.writes]
    assert len(times) == 13 and min(b - a for a, b in zip(times, times[1:])) >= PAUSE_S - 1e-9
    assert sync.loaded_since_s == times[-1] and sync.revision == 4
    assert all(sync.held(j) == pytest.approx(stored[j], rel=1e-7) for j in settings.JOINTS)


def test_without_stored_settings_it_waits_says_so_once_and_loads_as_soon_as_they_arrive():
    sync, device, clock, log = make()
    sync.unload()
    for _ in range(3):
        sync.step()
        clock.now += 1.0
    assert device.writes == [] and sync.next_step_s == math.inf
    assert len(log.warnings) == 1 and SOURCE in log.warnings[0]
    store(sync, stored_settings())
    assert sync.next_step_s <= clock.now  # at once
    run(sync, clock)
    assert len(device.take()) == 85 and sync.loaded_since_s is not None


def test_a_new_revision_sends_at_once_only_what_differs():
    sync, device, clock, log = loaded()
    store(sync, stored_settings(j2_pid_kp=4.0, j5_voltage_max=6.5), revision=2)
    assert sync.next_step_s <= clock.now + PAUSE_S  # at once (after the pause of the last write)
    run(sync, clock)
    assert device.take() == [config(2, 'pid_kp', 4.0), config(5, 'voltage_max', 6.5)]
    assert sync.held(2)['pid_kp'] == 4.0 and 'revision 2' in log.infos[-1]
    store(sync, stored_settings(j2_pid_kp=4.0, j5_voltage_max=6.5), revision=3)  # no change
    run(sync, clock)
    assert device.take() == []


def test_a_newer_revision_during_a_load_follows_the_load():
    sync, device, clock, _ = make()
    store(sync, stored_settings())
    sync.unload()
    sync.step()  # the first of the load's writes
    store(sync, stored_settings(j6_pid_kd=0.5), revision=2)
    run(sync, clock)
    received = device.take()
    assert len(received) == 86 and received[84] == codec.Opmode(codec.LIMP)
    assert received[85] == config(6, 'pid_kd', 0.5)


class FirmwareAngles:
    """The 2020 firmware's angle (docs/serial.md): sign_angle x wrap(raw - stored_home), where
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


def reload(sync, device, clock):
    sync.unload()
    run(sync, clock)
    return device.take()


def test_signs_go_before_home_angle_for_every_joint():
    sync, device, clock, _ = make()
    store(sync, stored_settings())
    received = reload(sync, device, clock)
    for joint in settings.JOINTS:
        ids = [m.config_id for m in received
               if isinstance(m, codec.JointConfig) and m.joint == joint]
        assert ids.index(ID['sign_angle']) < ids.index(ID['home_angle'])
        assert ids.index(ID['sign_motor']) < ids.index(ID['home_angle'])


def test_loading_the_same_settings_twice_gives_the_same_angles():
    sync, device, clock, _ = make()
    store(sync, stored_settings(j1_home_angle=-0.22, j1_sign_angle=-1.0))
    firmware = FirmwareAngles()
    firmware.feed(reload(sync, device, clock))
    first = firmware.angle(1, 0.5)
    firmware.feed(reload(sync, device, clock))  # a reconnect: the device still holds sign -1
    assert firmware.angle(1, 0.5) == first
    assert first == pytest.approx((-1.0) * (0.5 - 0.22))


def test_a_change_of_sign_angle_alone_re_sends_home_angle_after_it():
    sync, device, clock, _ = make()
    store(sync, stored_settings(j1_home_angle=-0.25, j1_sign_angle=-1.0))
    firmware = FirmwareAngles()
    firmware.feed(reload(sync, device, clock))
    store(sync, stored_settings(j1_home_angle=-0.25), revision=2)  # the sign only
    run(sync, clock)
    sent = device.take()
    assert sent == [config(1, 'sign_angle', 1.0), config(1, 'home_angle', -0.25)]
    firmware.feed(sent)
    fresh = FirmwareAngles()
    fresh.feed(reload(sync, device, clock))
    assert firmware.angle(1, 0.5) == fresh.angle(1, 0.5)


def test_values_written_when_an_unload_comes_are_never_taken_as_held():
    # The port is re-opened while the write of a change is under way: the new device (or the
    # old one after a restart) may hold anything, not the change.
    sync, device, clock, _ = loaded(stored_settings(j2_voltage_max=7.0))
    store(sync, stored_settings(j2_voltage_max=1.0), revision=2)
    device.on_write = sync.unload
    step_when_due(sync, clock)
    device.on_write = None
    assert sync.held(2) is None
    assert sync.voltage_limits(2) == device_settings.VOLTAGE_BOUNDS_V
    assert sync.loaded_since_s is None
    run(sync, clock)  # and everything is loaded again
    assert len(device.take()) == 1 + 85 and sync.voltage_limits(2)[1] == 1.0


def test_an_unload_between_the_writes_of_a_load_starts_a_fresh_whole_load():
    sync, device, clock, _ = make()
    store(sync, stored_settings())
    sync.unload()
    sync.step()
    first = device.take()
    assert first and sync.loaded_since_s is None
    sync.unload()  # a reconnect in the pause between two writes
    run(sync, clock)
    received = device.take()
    assert received[:len(first)] == first  # from the start again
    assert len(received) == 85 and received[-1] == codec.Opmode(codec.LIMP)


def test_the_epoch_rises_at_unload_and_after_the_loads_limp():
    sync, device, clock, _ = make()
    store(sync, stored_settings())
    epochs = []
    device.on_write = lambda: epochs.append(sync.epoch)
    start = sync.epoch
    sync.unload()
    assert sync.epoch == start + 1
    run(sync, clock)
    assert epochs[-1] == start + 1  # the limp frame is written before the rise
    assert sync.epoch == start + 2


def test_a_silent_device_gets_no_load_until_asked():
    sync, device, clock, _ = make()
    store(sync, stored_settings())
    sync.unload(load=False)
    assert sync.next_step_s == math.inf
    sync.step()
    assert device.writes == []
    sync.unload(load=True)  # it talks again
    run(sync, clock)
    assert len(device.take()) == 85


def test_a_failed_write_loads_everything_again_after_the_retry_time():
    sync, device, clock, log = loaded()
    store(sync, stored_settings(j0_pid_ki=2.0), revision=2)
    device.connected = False
    step_when_due(sync, clock)
    failed_at = clock.now
    assert sync.loaded_since_s is None and sync.held(0) is None
    assert sync.next_step_s == failed_at + device_settings.RETRY_S
    sync.step()
    assert len(log.warnings) == 1 and 'revision 2' in log.warnings[0]
    device.connected = True
    run(sync, clock)
    received = device.take()
    assert len(received) == 85 and config(0, 'pid_ki', 2.0) in received
    assert clock.now >= failed_at + device_settings.RETRY_S


def test_a_write_that_fails_after_it_was_taken_loads_everything_again_after_the_retry_time():
    sync, device, clock, log = loaded()
    failed_at = clock.now
    sync.write_failed()   # e.g. the port refused a write the node had queued
    assert sync.loaded_since_s is None and sync.held(0) is None
    assert sync.next_step_s == failed_at + device_settings.RETRY_S
    assert len(log.warnings) == 1 and 'a write to the device failed' in log.warnings[0]
    run(sync, clock)
    assert len(device.take()) == 85 and clock.now >= failed_at + device_settings.RETRY_S


@pytest.mark.parametrize('joints, problem', [
    (lambda s: [(j, v) for j, v in s.items() if j != 3], 'joints'),
    (lambda s: list(s.items()) + [(3, s[3])], 'joints'),
    (lambda s: [(j, dict(v, pid_kd=math.nan) if j == 4 else v) for j, v in s.items()],
     'joint 4 pid_kd'),
    # Garbage on active_settings (test_topic_garbage): encodable, but outside the bounds.
    (lambda s: [(j, dict(v, sign_angle=4.4) if j == 2 else v) for j, v in s.items()],
     'joint 2 sign_angle = 4.4: a sign must be +1 or -1'),
    (lambda s: [(j, dict(v, pid_kp=-1.0) if j == 0 else v) for j, v in s.items()],
     'joint 0 pid_kp = -1.0: outside its bound'),
    (lambda s: [(j, dict(v, angle_min=1.0, angle_max=0.5) if j == 6 else v)
                for j, v in s.items()], 'joint 6 angle_min = 1.0: above angle_max = 0.5'),
    (lambda s: [(j, dict(v, velocity_min=-1.0, velocity_max=-0.5) if j == 1 else v)
                for j, v in s.items()],
     'joint 1 velocity_min..velocity_max = -1..-0.5: the range must hold 0'),
])
def test_bad_stored_settings_are_logged_and_the_previous_ones_kept(joints, problem):
    sync, device, clock, log = loaded()
    assert sync.on_stored(2, joints(stored_settings(j4_pid_kd=3.0))) is False
    assert sync.revision == 1 and problem in log.warnings[-1]
    run(sync, clock)
    assert device.take() == []


def test_the_device_holds_the_stored_settings_once_the_last_write_of_them_went_out():
    sync, device, clock, _ = make()
    store(sync, stored_settings())
    assert not sync.holds_stored   # not connected yet
    sync.unload()
    sync.step()
    assert not sync.holds_stored   # loading
    run(sync, clock)
    assert sync.holds_stored
    assert sync.on_stored(2, sorted(stored_settings(j1_pid_kp=3.0, j6_pid_kp=3.0).items()))
    assert not sync.holds_stored   # written in one step, not yet
    run(sync, clock)
    assert sync.holds_stored
    store(sync, stored_settings(j1_pid_kp=3.0, j6_pid_kp=3.0), revision=3)   # nothing new
    assert sync.holds_stored
    sync.unload()
    assert not sync.holds_stored


def test_the_angle_tag_changes_before_the_first_write_of_new_angle_settings():
    """serial_X tags joint_states with it: a state set read after a write began carries the
    tag of what the write carries (arm.angle_settings)."""
    sync, device, clock, log = make()
    assert sync.angle_tag == ''
    old = stored_settings()
    store(sync, old)
    sync.unload()
    seen = []
    device.on_write = lambda: seen.append(sync.angle_tag)
    run(sync, clock)
    tag = settings.angle_tag([old[j] for j in settings.JOINTS])
    assert set(seen) == {tag} and sync.angle_tag == tag
    new = stored_settings(j0_home_angle=0.5)
    store(sync, new, revision=2)
    assert sync.angle_tag == tag   # nothing written yet: the device reports the old meaning
    seen.clear()
    run(sync, clock)
    assert seen and set(seen) == {settings.angle_tag([new[j] for j in settings.JOINTS])}
    store(sync, stored_settings(j0_home_angle=0.5, j3_pid_kp=2.0), revision=3)
    run(sync, clock)
    assert sync.angle_tag == seen[0]   # a gain is no change of meaning
