"""Unit tests of robopuppet.protocol.serial_core: serial_X's decisions, fed bytes and a clock."""
import math

import pytest

from robopuppet import interface, settings
from robopuppet.protocol import codec, link_health, serial_core, state_output as out

PORT = '/dev/ttyACM0'
SOURCE = '/puppet/arm_L/active_settings'
STORED = [(j, dict(settings.DEFAULTS, home_angle=0.25, pid_kp=2.0)) for j in settings.JOINTS]


class Clock:
    def __init__(self):
        self.now = 50.0

    def __call__(self):
        return self.now


class Rig:
    """A SerialCore with a fake clock, a device that decodes what is written, and a log."""

    def __init__(self, **options):
        self.clock = Clock()
        self.decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        self.received, self.infos, self.warnings = [], [], []
        self.connected = True
        self.core = serial_core.SerialCore(self.write, self.clock, self.infos.append,
                                           self.warnings.append, PORT, SOURCE, **options)

    def write(self, data):
        if not self.connected:
            return False
        self.received.extend(self.decoder.feed(data))
        return True

    def take(self):
        received, self.received = self.received, []
        return received

    def facts(self, publishers=1):
        return link_health.LinkFacts(self.connected, 1, 0, 0, '', publishers)

    def step(self, publishers=1):
        return self.core.step(self.facts(publishers))

    def settle(self):
        """Step while the core has work due within 0.1 s, moving the clock (a load's writes)."""
        for _ in range(100):
            next_s = self.step().next_s
            if next_s > self.clock.now + 0.1:
                return
            self.clock.now = max(self.clock.now, next_s)
        raise AssertionError('the core never settles')

    def feed(self, data, dt_s=0.0):
        self.clock.now += dt_s
        return self.core.on_data(data)

    def connect_and_load(self):
        self.core.on_connect()
        self.core.on_stored(1, STORED)
        self.settle()
        assert self.core.loaded
        self.take()


def set_bytes(angle_rad=0.5, button=0, parts=slice(None)):
    messages = [codec.JointState(j, codec.WORKING, angle_rad, 1.0) for j in settings.JOINTS]
    messages += [codec.Gripper(g, 0.5) for g in range(interface.NUM_GRIPPERS)]
    messages += [codec.Buttons(button)]
    return b''.join(codec.encode(m) for m in messages[parts])


def of_type(outputs, kind):
    return [o for o in outputs if type(o) is kind]


def test_no_joint_states_until_the_stored_settings_are_loaded_after_the_connect():
    rig = Rig()
    rig.core.on_connect()
    rig.step()
    assert of_type(rig.feed(set_bytes(), 0.1), out.JointStates) == []
    assert any(SOURCE in w for w in rig.warnings)  # waiting, said once
    rig.core.on_stored(1, STORED)
    assert rig.core.step_due()
    rig.settle()
    assert rig.take()[-1] == codec.Opmode(codec.LIMP)
    assert of_type(rig.feed(set_bytes(0.75), 0.1), out.JointStates) == [
        out.JointStates((0.75,) * 7, (1.0,) * 7, settings.angle_tag(dict(STORED)))]


def test_a_set_begun_before_a_reconnect_is_never_published():
    rig = Rig()
    rig.connect_and_load()
    assert rig.feed(set_bytes(parts=slice(0, 4)), 0.1) == []  # joints 0-3 of a set...
    rig.core.on_connect()  # ... a reconnect, and the settings load again ...
    rig.settle()
    assert rig.core.loaded
    outputs = rig.feed(set_bytes(parts=slice(4, None)), 0.01)  # ... then the rest of that set
    assert of_type(outputs, out.Grippers), 'the set should complete'
    assert of_type(outputs, out.JointStates) == []
    assert of_type(rig.feed(set_bytes(), 0.1), out.JointStates)  # the next set is published


def test_a_silent_device_is_re_opened_and_reloaded_once_it_talks_again():
    rig = Rig(silence_timeout_s=3.0)
    rig.connect_and_load()
    rig.feed(set_bytes(), 0.1)
    rig.clock.now += 2.9
    assert not rig.step().reopen
    rig.clock.now += 0.2
    assert rig.step().reopen
    assert sum('no frame from %s' % PORT in w for w in rig.warnings) == 1
    rig.core.on_connect()  # the re-open: a silent device gets no load
    rig.settle()
    assert rig.take() == [] and not rig.core.loaded
    rig.clock.now += link_health.WAKE_S
    assert rig.step().reopen  # again every second, not logged again
    assert sum('no frame from' in w for w in rig.warnings) == 1
    rig.core.on_connect()
    assert of_type(rig.feed(set_bytes(), 0.1), out.JointStates) == []  # it talks again
    assert rig.core.step_due()
    rig.settle()
    assert len(rig.take()) == 85 and rig.core.loaded
    assert of_type(rig.feed(set_bytes(), 0.1), out.JointStates)


def test_noise_does_not_count_as_the_device_talking():
    rig = Rig(silence_timeout_s=3.0)
    rig.connect_and_load()
    for _ in range(4):
        rig.feed(b'\xa5\x00\x00' + bytes(range(40)), 1.0)  # a stray heartbeat and garbage
    assert rig.step().reopen


def test_a_hold_before_any_angle_is_refused_and_later_filled_from_the_joint_states():
    rig = Rig()
    rig.core.on_connect()
    rig.core.on_opmode(interface.HOLD)
    assert rig.take() == [] and 'hold refused' in rig.warnings[-1]
    rig.core.on_stored(1, STORED)
    rig.settle()
    rig.take()
    rig.feed(set_bytes(0.5), 0.1)
    rig.core.on_setpoint(2, -0.25)
    rig.core.on_opmode(interface.HOLD)
    sent = rig.take()
    assert sent[0] == codec.JointSetpoint(2, -0.25)
    assert sent[1:] == [codec.JointSetpoint(j, 0.5) for j in settings.JOINTS if j != 2] + [
        codec.Opmode(codec.HOLD)]


def test_limp_always_goes_out_and_an_unknown_opmode_is_ignored():
    rig = Rig()
    rig.core.on_connect()
    rig.core.on_opmode('float')
    assert rig.take() == [] and 'float' in rig.warnings[-1]
    rig.core.on_opmode(interface.LIMP)
    assert rig.take() == [codec.Opmode(codec.LIMP)]


def test_the_next_step_is_never_in_the_past_once_the_work_is_done():
    rig = Rig()
    rig.core.on_connect()
    rig.settle()
    actions = rig.step()
    assert rig.clock.now < actions.next_s < math.inf  # the diagnostics, then the silence watch
    rig.connected = False
    rig.clock.now += 10.0
    assert rig.step().next_s > rig.clock.now  # a closed port is not watched for silence


def values_of(diagnostics):
    return dict(diagnostics.values)


def test_diagnostics_say_whether_active_settings_arrived_their_revision_and_publishers():
    rig = Rig()
    rig.core.on_connect()
    diagnostics = rig.step(publishers=0).diagnostics
    values = values_of(diagnostics)
    assert diagnostics.level == link_health.WARN and 'waiting for settings' in diagnostics.message
    assert (values['port'], values['active settings'], values['active settings publishers'],
            values['settings loaded']) == (PORT, 'none yet', '0', 'False')
    rig.core.on_stored(7, STORED)
    rig.settle()
    rig.feed(set_bytes(), 0.05)
    rig.feed(codec.encode(codec.Heartbeat()), 0.01)
    rig.clock.now += 1.0
    diagnostics = rig.step().diagnostics
    values = values_of(diagnostics)
    assert (diagnostics.level, diagnostics.message) == (link_health.OK, 'link up')
    assert (values['active settings'], values['settings loaded']) == ('revision 7', 'True')
    assert rig.step().diagnostics is None  # at most once a second


def test_an_implausible_frame_is_logged_at_most_every_10_s():
    rig = Rig()
    rig.connect_and_load()
    bad = codec.encode(codec.JointState(0, codec.WORKING, 0.1, 50.0))  # 50 V
    for _ in range(3):
        rig.feed(bad, 1.0)
    assert sum('implausible' in w for w in rig.warnings) == 1
    rig.feed(bad, serial_core.IMPLAUSIBLE_LOG_S)
    assert sum('implausible' in w for w in rig.warnings) == 2


def test_bad_rates_are_refused():
    with pytest.raises(ValueError):
        Rig(topic_rate_hz=0.0)
    with pytest.raises(ValueError):
        Rig(comm_rate_hz=-1.0)
    with pytest.raises(ValueError):
        Rig(silence_timeout_s=0.0)
