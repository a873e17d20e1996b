"""Unit tests of feel mode in serial_X's core: the device's hold, on the feel gains only (the
order on the wire entering and leaving feel), and the setpoint watchdog that sends limp (on the
wire) and announces it (on <ns>/opmode) when arm_X stops streaming."""
from robopuppet import interface, settings
from robopuppet.float32 import to_float32
from robopuppet.protocol import codec

from test_serial_core import STORED, Rig, set_bytes

TIMEOUT_S = 0.5
FEEL = interface.FEEL_PROFILE
# config_X's feel profile of STORED (pid_kp 2.0 x 0.25, voltage limits +-2 V).
GENTLE = [(j, dict(values, pid_kp=0.5, voltage_min=-2.0, voltage_max=2.0))
          for j, values in STORED]
CONFIG_NAME = {config_id: name for name, config_id in settings.CONFIG_ID.items()}


def feeling_rig():
    """A loaded rig whose device reported its angles (0.5 rad) and holds the feel profile,
    just put in feel mode; what went out is left to take()."""
    rig = Rig(feel_timeout_s=TIMEOUT_S)
    rig.connect_and_load()
    rig.feed(set_bytes(0.5), 0.1)
    rig.core.on_stored(2, GENTLE, FEEL)
    rig.settle()
    rig.core.on_opmode(interface.FEEL)
    return rig


class Device:
    """What the device holds, frame by frame: its settings per joint (from `joints`, as
    STORED), setpoints and opmode; at each opmode frame, a snapshot."""

    def __init__(self, joints=STORED):
        self.config = {j: dict(values) for j, values in joints}
        self.setpoints, self.opmodes = {}, []   # [(mode, config, setpoints) at each opmode]

    def run(self, frames):
        for m in frames:
            if isinstance(m, codec.JointConfig):
                self.config[m.joint][CONFIG_NAME[m.config_id]] = m.value
            elif isinstance(m, codec.JointSetpoint):
                self.setpoints[m.joint] = m.angle_rad
            else:
                self.opmodes.append((m.mode, {j: dict(c) for j, c in self.config.items()},
                                     dict(self.setpoints)))
        return self

    def gains(self, config=None):
        config = self.config if config is None else config
        return {(c['pid_kp'], c['voltage_min'], c['voltage_max']) for c in config.values()}


def test_feel_is_the_devices_hold_with_the_same_plan():
    rig = feeling_rig()
    assert rig.take()[-8:] == [codec.JointSetpoint(j, 0.5) for j in settings.JOINTS] + [
        codec.Opmode(codec.HOLD)]
    assert rig.step().opmode is None
    rig.core.on_opmode(interface.FEEL)  # a repeat (e.g. the GUI echoing arm_X) changes nothing
    assert rig.take() == []


def test_setpoints_stopping_in_feel_send_limp_once_and_announce_it():
    rig = feeling_rig()
    rig.take()
    rig.clock.now += TIMEOUT_S - 0.01
    actions = rig.step()
    assert rig.take() == [] and actions.opmode is None
    assert actions.next_s <= rig.clock.now + 0.01 + 1e-9  # the worker wakes at the deadline
    rig.clock.now += 0.02
    actions = rig.step()
    assert rig.take() == [codec.Opmode(codec.LIMP)]
    assert actions.opmode == interface.LIMP
    assert 'no joint setpoint for 0.51 s in feel mode' in rig.warnings[-1]
    rig.clock.now += 5.0
    assert rig.step().opmode is None and rig.take() == []  # once
    rig.core.on_opmode(interface.LIMP)  # our own announcement coming back: harmless
    assert rig.take() == [codec.Opmode(codec.LIMP)]
    assert rig.step().opmode is None


def test_setpoints_flowing_keep_feel_mode():
    rig = feeling_rig()
    rig.take()
    for _ in range(50):  # 5 s at 10 Hz, each gap under the timeout
        rig.clock.now += 0.1
        rig.core.on_setpoint(3, 0.25)
        assert rig.step().opmode is None
    assert codec.Opmode(codec.LIMP) not in rig.take()
    rig.clock.now += TIMEOUT_S
    assert rig.step().opmode == interface.LIMP  # measured from the last setpoint


def test_hold_is_never_timed_out_and_ends_feel():
    rig = feeling_rig()
    rig.core.on_opmode(interface.HOLD)  # feel -> hold: the device stays in hold
    assert rig.take()[-1] == codec.Opmode(codec.HOLD)
    rig.clock.now += 60.0
    actions = rig.step()
    assert actions.opmode is None and rig.take() == []
    rig.core.on_opmode(interface.FEEL)  # hold -> feel: the watchdog starts again
    rig.take()
    rig.clock.now += TIMEOUT_S
    assert rig.step().opmode == interface.LIMP


def test_limp_ends_feel_without_an_announcement():
    rig = feeling_rig()
    rig.take()
    rig.core.on_opmode(interface.LIMP)
    assert rig.take() == [codec.Opmode(codec.LIMP)]
    rig.clock.now += 10.0
    assert rig.step().opmode is None and rig.take() == []


def test_a_reconnect_in_feel_sends_limp_and_announces_it():
    rig = feeling_rig()
    rig.take()
    rig.core.on_connect()
    assert rig.take()[0] == codec.Opmode(codec.LIMP)
    assert rig.core.step_due()  # the node steps at once to publish it
    assert rig.step().opmode == interface.LIMP
    assert 'port %s was re-opened' % rig.core._port in rig.warnings[-1]


def test_a_refused_feel_is_limp_and_announced():
    rig = Rig(feel_timeout_s=TIMEOUT_S)
    rig.core.on_connect()
    rig.core.on_stored(1, STORED)
    rig.settle()
    rig.take()
    rig.core.on_opmode(interface.FEEL)  # no angles reported yet: a hold would drive to 0 rad
    assert rig.take() == [codec.Opmode(codec.LIMP)]
    assert 'feel refused' in rig.warnings[-1]
    assert rig.step().opmode == interface.LIMP


def test_the_feel_profile_reaches_the_device_as_a_settings_change_without_limp():
    rig = feeling_rig()
    sent = rig.take()
    assert codec.Opmode(codec.LIMP) not in sent
    assert {(m.joint, m.config_id, m.value) for m in sent if isinstance(m, codec.JointConfig)} \
        == {(j, settings.CONFIG_ID[name], value) for j in settings.JOINTS
            for name, value in (('pid_kp', 0.5), ('voltage_min', -2.0), ('voltage_max', 2.0))}
    assert any("profile 'feel'" in info for info in rig.infos)
    softer = [(j, dict(values, pid_kp=0.25)) for j, values in GENTLE]
    rig.core.on_stored(3, softer, FEEL)   # a stored change while in feel: its feel profile
    rig.settle()
    assert rig.take() == [codec.JointConfig(j, settings.CONFIG_ID['pid_kp'], 0.25)
                          for j in settings.JOINTS]


def test_entering_feel_the_device_holds_the_feel_gains_before_its_hold_frame():
    """Whichever comes first to serial_X, the opmode feel or config_X's feel profile, the
    device gets the gentle gains, then feel's setpoints, then the hold: its first control
    tick in feel already runs on the feel gains."""
    for opmode_first in (True, False):
        rig = Rig(feel_timeout_s=TIMEOUT_S)
        rig.connect_and_load()
        rig.feed(set_bytes(0.5), 0.1)
        if opmode_first:
            rig.core.on_opmode(interface.FEEL)
            rig.core.on_setpoint(3, 0.25)   # arm_X's feel pose: kept while the gains load
            assert rig.take() == [], 'nothing before the gains'
        rig.core.on_stored(2, GENTLE, FEEL)
        rig.settle()
        if not opmode_first:
            rig.core.on_opmode(interface.FEEL)   # the gains are on the device: hold at once
            rig.core.on_setpoint(3, 0.25)
        device = Device().run(rig.take())
        [(mode, config, setpoints)] = device.opmodes
        assert mode == codec.HOLD
        assert device.gains(config) == {(0.5, -2.0, 2.0)}, opmode_first
        kept = 0.25 if opmode_first else 0.5   # else the setpoint comes after the hold
        assert setpoints == {j: kept if j == 3 else 0.5 for j in settings.JOINTS}
        assert device.setpoints[3] == 0.25


def test_from_hold_feel_setpoints_wait_until_the_device_holds_the_feel_gains():
    """In hold on the stored gains, a feel setpoint must not reach the device before the
    gentle gains: it would pull on the stored ones."""
    rig = Rig(feel_timeout_s=TIMEOUT_S)
    rig.connect_and_load()
    rig.feed(set_bytes(0.5), 0.1)
    rig.core.on_opmode(interface.HOLD)
    device = Device().run(rig.take())
    rig.core.on_opmode(interface.FEEL)
    for j in settings.JOINTS:
        rig.core.on_setpoint(j, 0.5 + 0.125 * j)
    assert rig.take() == []
    rig.core.on_stored(2, GENTLE, FEEL)
    rig.settle()
    frames = rig.take()
    device.run(frames)
    first_setpoint = min(i for i, m in enumerate(frames) if isinstance(m, codec.JointSetpoint))
    assert all(isinstance(m, codec.JointConfig) for m in frames[:first_setpoint])
    assert device.gains(Device().run(frames[:first_setpoint]).config) == {(0.5, -2.0, 2.0)}
    assert frames[first_setpoint:] == [codec.JointSetpoint(j, 0.5 + 0.125 * j)
                                       for j in settings.JOINTS] + [codec.Opmode(codec.HOLD)]
    assert device.gains(device.opmodes[-1][1]) == {(0.5, -2.0, 2.0)}


def test_leaving_feel_the_stored_gains_follow_the_limp_or_hold_frame():
    """config_X's stored profile may reach serial_X before the opmode that ends feel: it waits,
    so that the stored gains never pull toward a feel setpoint; after the hold (the GUI's,
    its setpoints first) or the limp they go out."""
    for mode, device_mode in ((interface.HOLD, codec.HOLD), (interface.LIMP, codec.LIMP)):
        rig = feeling_rig()
        device = Device().run(rig.take())
        rig.core.on_stored(3, STORED, '')
        rig.settle()
        assert rig.take() == []   # the stored gains wait
        if mode == interface.HOLD:
            rig.core.on_setpoint(2, 0.75)   # the GUI's Hold: the current angles first
        rig.core.on_opmode(mode)
        rig.settle()
        frames = rig.take()
        configs = [i for i, m in enumerate(frames) if isinstance(m, codec.JointConfig)]
        assert configs and frames.index(codec.Opmode(device_mode)) < configs[0]
        device.run(frames)
        assert device.gains(device.opmodes[-1][1]) == {(0.5, -2.0, 2.0)}   # at the opmode
        assert device.gains() == {(2.0, to_float32(-7.2), to_float32(7.2))}   # then stored
        assert any("profile '' (as stored)" in info for info in rig.infos)


def test_feel_whose_gains_do_not_come_goes_limp_and_says_why():
    rig = Rig(feel_timeout_s=TIMEOUT_S)
    rig.connect_and_load()
    rig.feed(set_bytes(0.5), 0.1)
    rig.core.on_opmode(interface.FEEL)
    actions = rig.step()
    assert actions.next_s <= rig.clock.now + TIMEOUT_S + 1e-9   # woken at the deadline
    for _ in range(4):   # arm_X streams, config_X says nothing
        rig.clock.now += 0.1
        rig.core.on_setpoint(1, 0.3)
        assert rig.step().opmode is None
    rig.clock.now += 0.11
    assert rig.step().opmode == interface.LIMP
    assert rig.take() == [codec.Opmode(codec.LIMP)]   # the kept setpoints never went out
    assert 'feel gains' in rig.warnings[-1] and '0.51 s' in rig.warnings[-1]
    rig.core.on_stored(2, GENTLE, FEEL)   # late: the device takes them, limp
    rig.settle()
    assert codec.Opmode(codec.HOLD) not in rig.take()


def test_the_watchdog_needs_a_positive_timeout():
    for bad in (0.0, -1.0, float('nan')):
        try:
            Rig(feel_timeout_s=bad)
        except ValueError:
            continue
        raise AssertionError('feel_timeout_s=%r accepted' % bad)
