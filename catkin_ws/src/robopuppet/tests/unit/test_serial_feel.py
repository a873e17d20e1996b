"""Unit tests of feel mode in serial_X's core: the device's hold, and the setpoint watchdog that
sends limp (on the wire) and announces it (on <ns>/opmode) when arm_X stops streaming."""
from robopuppet import interface, settings
from robopuppet.protocol import codec, device_commands

from test_serial_core import STORED, Rig, set_bytes

TIMEOUT_S = 0.5


def feeling_rig():
    """A loaded rig whose device reported its angles, just put in feel mode."""
    rig = Rig(feel_timeout_s=TIMEOUT_S)
    rig.connect_and_load()
    rig.feed(set_bytes(0.5), 0.1)
    rig.core.on_opmode(interface.FEEL)
    return rig


def test_feel_is_the_devices_hold_with_the_same_plan():
    rig = feeling_rig()
    assert rig.take() == [codec.JointSetpoint(j, 0.5) for j in settings.JOINTS] + [
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
    rig.take()
    gentle = [(j, dict(values, pid_kp=0.5, voltage_max=2.0)) for j, values in STORED]
    rig.core.on_stored(2, gentle, 'feel')
    rig.settle()
    sent = rig.take()
    assert codec.Opmode(codec.LIMP) not in sent
    assert {(m.joint, m.config_id, m.value) for m in sent} == {
        (j, settings.CONFIG_ID[name], value) for j in settings.JOINTS
        for name, value in (('pid_kp', 0.5), ('voltage_max', 2.0))}
    assert any("profile 'feel'" in info for info in rig.infos)


def test_the_watchdog_needs_a_positive_timeout():
    for bad in (0.0, -1.0, float('nan')):
        try:
            device_commands.FeelWatch(bad)
        except ValueError:
            continue
        raise AssertionError('FeelWatch(%r) accepted' % bad)
