"""Unit tests of protocol.device_commands: setting order, packing, the hold gate, rate check."""
import os
import xml.etree.ElementTree as ET

import pytest

from robopuppet import settings
from robopuppet.config import config_store
from robopuppet.protocol import codec, device_commands as dc

ID = settings.CONFIG_ID
LAUNCH_DIR = os.path.join(os.path.dirname(__file__), '..', '..', 'launch')


def test_a_full_load_sends_every_setting_with_the_signs_before_home_angle():
    stored = config_store.defaults()[0]
    names = [n for n, _ in dc.settings_to_send(stored)]
    assert sorted(names) == sorted(settings.NAMES)
    assert names.index('sign_angle') < names.index('home_angle')
    assert names.index('sign_motor') < names.index('home_angle')


def test_a_re_sync_sends_what_differs_and_home_again_after_a_sign_change():
    held = config_store.defaults()[2]
    stored = dict(held, pid_kp=3.0)
    assert dc.settings_to_send(stored, held) == [('pid_kp', 3.0)]
    stored = dict(held, sign_angle=-1.0, home_angle=held['home_angle'])
    assert dc.settings_to_send(stored, held) == [('sign_angle', -1.0),
                                                 ('home_angle', held['home_angle'])]
    assert dc.settings_to_send(held, held) == []  # the same settings again: nothing


def test_pack_keeps_whole_frames_in_order_in_writes_of_at_most_64_bytes():
    frames = [codec.encode(codec.JointConfig(j, i, 0.5)) for j in range(7) for i in range(12)]
    writes = dc.pack(frames)
    assert b''.join(writes) == b''.join(frames)
    assert all(len(w) <= 64 and len(w) % 9 == 0 for w in writes)
    assert len(writes) == 12  # 7 frames of 9 bytes fill a 64-byte packet
    assert dc.pack([]) == []
    with pytest.raises(ValueError):
        dc.pack([bytes(65)])


def test_a_hold_without_setpoints_and_without_angles_is_refused():
    gate = dc.HoldGate()
    plan = gate.plan_hold(1)
    assert plan.messages is None and '0 rad' in plan.refusal


def test_a_hold_fills_missing_setpoints_with_the_current_angles_first():
    gate = dc.HoldGate()
    angles = [0.1 * (j + 1) for j in settings.JOINTS]
    gate.on_angles(angles, 1)
    gate.record([codec.JointSetpoint(2, -0.5)], 1)
    plan = gate.plan_hold(1)
    assert plan.refusal is None
    assert plan.messages == [codec.JointSetpoint(j, angles[j]) for j in settings.JOINTS
                             if j != 2] + [codec.Opmode(codec.HOLD)]
    # Whole frames in one write of at most 64 bytes: nothing comes between them on the wire.
    assert len(dc.pack([codec.encode(m) for m in plan.messages])) == 1


def test_setpoints_given_to_a_hold_go_first_and_are_not_filled():
    gate = dc.HoldGate()
    angles = [0.1 * (j + 1) for j in settings.JOINTS]
    gate.on_angles(angles, 1)
    given = [codec.JointSetpoint(4, -0.25), codec.JointSetpoint(6, 0.75)]
    plan = gate.plan_hold(1, given)
    assert plan.messages == given + [codec.JointSetpoint(j, angles[j]) for j in settings.JOINTS
                                     if j not in (4, 6)] + [codec.Opmode(codec.HOLD)]
    assert len(dc.pack([codec.encode(m) for m in plan.messages])) == 1
    everything = [codec.JointSetpoint(j, 0.5) for j in settings.JOINTS]
    assert dc.HoldGate().plan_hold(1, everything).messages == everything + [
        codec.Opmode(codec.HOLD)]   # seven given: no angles needed


def test_seven_setpoints_make_a_bare_hold_and_limp_or_a_new_epoch_resets_them():
    gate = dc.HoldGate()
    gate.record([codec.JointSetpoint(j, 0.2) for j in settings.JOINTS], 1)
    assert gate.plan_hold(1).messages == [codec.Opmode(codec.HOLD)]
    gate.record([codec.Opmode(codec.LIMP)], 1)  # limp zeroes the firmware's setpoints
    assert gate.plan_hold(1).refusal
    gate.record([codec.JointSetpoint(j, 0.2) for j in settings.JOINTS], 1)
    assert gate.plan_hold(2).refusal  # a reconnect or a load's limp: forgotten
    gate.on_angles([0.0] * 7, 1)  # angles of an older epoch are no use
    assert gate.plan_hold(2).refusal


def test_a_setpoint_written_across_an_epoch_change_is_forgotten_not_believed():
    gate = dc.HoldGate()
    gate.on_angles([0.3] * 7, 2)
    gate.record([codec.JointSetpoint(j, 0.2) for j in settings.JOINTS], 1)  # epoch read before
    plan = gate.plan_hold(2)
    assert plan.messages[:7] == [codec.JointSetpoint(j, 0.3) for j in settings.JOINTS]


def test_rate_meter_needs_a_whole_window_and_restarts():
    meter = dc.RateMeter(window_s=2.0)
    assert meter.rate_hz(0.0) is None
    for i in range(40):
        meter.add(i * 0.1)  # 10 Hz for 4 s
    assert meter.rate_hz(4.0) == pytest.approx(10.0, abs=0.5)
    assert meter.rate_hz(10.0) == 0.0  # nothing for 6 s
    meter.restart(10.0)
    assert meter.rate_hz(11.0) is None


@pytest.mark.parametrize('measured, expected, warns', [
    (10.0, 10.0, False), (8.1, 10.0, False), (12.0, 10.0, False), (7.9, 10.0, True),
    (50.0, 10.0, True), (10.0, 50.0, True), (None, 10.0, False), (3.0, 0.0, False)])
def test_rate_problem_beyond_20_percent(measured, expected, warns):
    problem = dc.rate_problem(measured, expected)
    assert bool(problem) == warns
    if warns:
        assert 'comm_rate' in problem and 'compile-time' in problem
        assert 'simulated puppet' in problem and 'loaded' in problem  # no bad advice there


def test_launch_files_say_comm_rate_does_not_set_the_firmwares_rate():
    docs = {name: arg.get('doc') for name in sorted(os.listdir(LAUNCH_DIR))
            for arg in ET.parse(os.path.join(LAUNCH_DIR, name)).getroot().findall('arg')
            if arg.get('name') == 'comm_rate'}
    assert 'arm.launch' in docs
    assert all('compile-time' in (doc or '') for doc in docs.values()), docs


def test_arm_launch_passes_comm_rate_to_the_serial_node():
    arm = ET.parse(os.path.join(LAUNCH_DIR, 'arm.launch')).getroot()
    include = next(i for i in arm.iter('include') if i.get('file').endswith('/input.launch'))
    assert include.get('pass_all_args') == 'true'   # arm.launch's comm_rate reaches input.launch
    root = ET.parse(os.path.join(LAUNCH_DIR, 'input.launch')).getroot()
    serial = next(n for n in root.iter('node') if n.get('type') == 'serial_interface')
    params = {p.get('name'): p.get('value') for p in serial.iter('param')}
    assert params['comm_rate'] == '$(arg comm_rate)'


def paced_writes(writes, pacer):
    """Return (time, bytes) of writes wanted at their times, each delayed as pacer says."""
    out = []
    for wanted_s, data in writes:
        at_s = max([wanted_s] + [t for t, _ in out[-1:]])
        at_s += pacer.delay_s(at_s, len(data))
        pacer.wrote(at_s, len(data))
        out.append((at_s, data))
    return out


def test_paced_writes_never_lose_a_frame_to_merged_usb_packets():
    # A hold's 60 bytes (seven filled setpoints and the opmode), then arm_X's seven setpoints
    # from their topics at once: written back to back, a prompt reader of the pty gets 116
    # bytes that arrived within 1 ms, cut every 64 bytes, so one setpoint straddles two packets.
    from test_puppet_wire import deliver, prompt_polls
    plan = b''.join(codec.encode(codec.JointSetpoint(j, 0.0625)) for j in settings.JOINTS)
    plan += codec.encode(codec.Opmode(codec.HOLD))
    wanted = [0.125 + j / 64.0 for j in settings.JOINTS]
    writes = [(0.0102, plan)] + [(0.0103 + j * 1e-5, codec.encode(codec.JointSetpoint(j, a)))
                                 for j, a in enumerate(wanted)]
    assert deliver(writes, prompt_polls(0.05)).setpoint_rad != wanted, 'the bug this prevents'
    paced = paced_writes(writes, dc.WritePacer())
    assert paced[1][0] >= paced[0][0] + dc.LOAD_PAUSE_S  # the group of 60 bytes was full
    assert all(t == paced[1][0] for t, _ in paced[2:]), 'then no more waiting'
    firmware = deliver(paced, prompt_polls(0.05))
    assert firmware.setpoint_rad == wanted and firmware.opmode == codec.HOLD


def test_the_pacer_lets_small_or_spaced_writes_go_at_once():
    pacer = dc.WritePacer(packet_bytes=64, gap_s=0.005)
    for k in range(8):  # 8-byte writes 1 ms apart: 64 bytes, one packet
        assert pacer.delay_s(1.0 + k * 0.001, 8) == 0.0
        pacer.wrote(1.0 + k * 0.001, 8)
    assert pacer.delay_s(1.0075, 8) == pytest.approx(0.0045)  # the 65th byte: 5 ms after
    assert pacer.delay_s(1.012, 63) == 0.0  # 5 ms after the group's last write
    pacer.wrote(1.012, 63)
    assert pacer.delay_s(1.013, 1) == 0.0 and pacer.delay_s(1.013, 2) == pytest.approx(0.004)
