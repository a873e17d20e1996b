"""Unit tests of robopuppet.puppet_sim.puppet_device: operator input, where line noise goes, what
is published when, the host not reading, and host bytes in USB packets, all with time given."""
import math

import pytest

from robopuppet import settings
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_device import (NOISE_LIMIT_BYTES, PuppetDevice, check_params,
                                                 hand_targets)
from robopuppet.puppet_sim.pty_port import Chunk
from robopuppet.puppet_sim.puppet_model import POWER_ON_SETTINGS, REST_POSE_RAD
from robopuppet.puppet_sim.puppet_wire import device_frame

ID = settings.CONFIG_ID


class Line:
    """The host's side of the line: takes everything written, or nothing while `reading` is off."""

    def __init__(self):
        self.data, self.reading = b'', True

    def write_some(self, data):
        if not self.reading:
            return 0
        self.data += data
        return len(data)


def frames(*messages):
    return b''.join(codec.encode(m) for m in messages)


def delivered(device, data, t_s):
    """Give the device data read at t_s from a pty seen idle 0.5 ms before: one host write."""
    device.receive(None, t_s - 0.0005)
    device.receive(Chunk(data, t_s, t_s + 0.0001, True), t_s)


@pytest.mark.parametrize('missing, packet_size, wrong', [
    ((1,), 0, '~hall_disconnected'), ([1.0], 0, '~hall_disconnected'),
    ('1', 0, '~hall_disconnected'), ([], 64.0, '~usb_packet_size'), ([], '64', '~usb_packet_size')])
def test_parameters_of_the_wrong_type_are_named(missing, packet_size, wrong):
    with pytest.raises(ValueError, match=wrong):
        check_params(missing, packet_size)


def test_parameters_of_the_right_type_pass_and_a_bad_joint_or_rate_is_refused():
    check_params([1, 5], 64)
    with pytest.raises(ValueError, match='hall-encoder'):
        PuppetDevice(10.0, [2])
    with pytest.raises(ValueError, match='state rate'):
        PuppetDevice(0.0)


def test_hand_names_map_to_joints_and_bad_ones_are_refused():
    assert hand_targets(['joint_6', 'joint_0'], [0.5, -0.25]) == {6: 0.5, 0: -0.25}
    for names, positions in ((['joint_7'], [0.1]), (['wrist'], [0.1]),
                             (['joint_0', 'joint_1'], [0.1])):
        with pytest.raises(ValueError, match='joint_0..joint_6'):
            hand_targets(names, positions)


def test_hand_targets_beyond_pi_or_infinite_are_refused_whole_and_the_joint_stays():
    assert hand_targets(['joint_1', 'joint_2'], [math.pi, -math.pi]) == {1: math.pi, 2: -math.pi}
    assert math.isnan(hand_targets(['joint_3'], [math.nan])[3])  # NaN still lets go
    assert hand_targets(['joint_5'], [-3.142]) == {5: -3.142}  # the GUI slider's end
    device = PuppetDevice()
    device.advance(0.0, Line().write_some)
    for positions in ([0.2, 1e308], [0.2, math.inf], [0.2, -math.inf], [0.2, -3.15]):
        with pytest.raises(ValueError, match=r'\[-pi, pi\].*joint_4'):
            device.set_hand(['joint_0', 'joint_4'], positions)
    device.advance(2.0, Line().write_some)  # the hand holds the rest pose: nothing moved
    arm = device.firmware.arm
    assert list(arm.hand_goal_rad) == list(REST_POSE_RAD)
    assert arm.angle_rad[4] == pytest.approx(REST_POSE_RAD[4], abs=0.05)
    assert abs(arm.speed_radps[4]) < 0.1


def test_operator_input_reaches_the_firmware_and_bad_input_changes_nothing():
    device = PuppetDevice()
    device.set_hand(['joint_2'], [1.0])
    device.set_hand(['joint_3'], [math.nan])
    assert device.firmware.arm.hand_goal_rad[2] == 1.0
    assert not device.firmware.arm.hand_engaged[3] and device.firmware.arm.hand_engaged[2]
    device.set_button(3)
    device.set_grippers((0.2, 0.4, 0.6, 0.0))
    for bad in (lambda: device.set_button(5), lambda: device.set_grippers([0.5] * 3),
                lambda: device.set_hand(['joint_2', 'joint_9'], [0.0, 0.0])):
        with pytest.raises(ValueError):
            bad()
    assert device.firmware.button == 3
    assert device.firmware.grippers == pytest.approx([0.2, 0.4, 0.6, 0.0])
    assert device.firmware.arm.hand_goal_rad[2] == 1.0


def test_line_noise_goes_out_right_before_the_next_joint_state_frame():
    device, line = PuppetDevice(state_rate_hz=10.0), Line()
    device.advance(0.0, line.write_some)
    device.add_noise(b'\xa5noise')
    device.advance(0.05, line.write_some)        # nothing due but control ticks: it waits
    assert line.data == b''
    for i in range(6, 96):                       # state sets at 0.1 .. 0.9 s
        device.advance(0.01 * i, line.write_some)
    state_set = b''.join(device_frame(m) for m in device.firmware.state_messages())
    assert line.data.startswith(b'\xa5noise') and line.data.count(b'\xa5noise') == 1
    assert len(line.data) == len(b'\xa5noise') + 9 * len(state_set)
    line.data = b''
    device.add_noise(b'\x00\x01')
    device.advance(1.0, line.write_some)         # the heartbeat, then the noise, then a set
    heartbeat = frames(codec.Heartbeat())
    assert line.data[:len(heartbeat)] == heartbeat
    assert line.data[len(heartbeat):len(heartbeat) + 2] == b'\x00\x01'
    assert len(line.data) == len(heartbeat) + 2 + len(state_set)


def test_line_noise_beyond_the_limit_is_refused_until_it_is_written():
    device, line = PuppetDevice(), Line()
    line.reading = False
    device.advance(0.0, line.write_some)
    device.add_noise(b'x' * (NOISE_LIMIT_BYTES - 10))
    device.advance(0.2, line.write_some)         # queued behind the line, not written
    with pytest.raises(ValueError, match='at most %d bytes' % NOISE_LIMIT_BYTES):
        device.add_noise(b'y' * 11)
    device.add_noise(b'y' * 10)
    line.reading = True
    device.advance(0.4, line.write_some)
    x_end = line.data.index(b'x' * (NOISE_LIMIT_BYTES - 10)) + NOISE_LIMIT_BYTES - 10
    assert b'y' * 10 in line.data[x_end:]      # after the state set that followed the x's
    device.add_noise(b'z' * NOISE_LIMIT_BYTES)


def test_a_host_that_stops_reading_is_noted_once_and_its_return_with_the_bytes_dropped():
    device, line = PuppetDevice(state_rate_hz=50.0), Line()
    line.reading = False
    notes = []
    for i in range(100):
        notes += device.advance(0.02 * i, line.write_some).notes
    assert notes == ['the host is not reading; dropping frames']
    line.reading = True
    notes = device.advance(2.02, line.write_some).notes
    assert len(notes) == 1 and notes[0].startswith('the host reads again (')
    assert int(notes[0].split('(')[1].split()[0]) > 0   # bytes dropped so far
    decoder = codec.Decoder()
    assert decoder.feed(line.data) and decoder.dropped_bytes == decoder.pending == 0


def test_settings_are_published_on_change_at_most_every_100_ms():
    device, line = PuppetDevice(), Line()
    first = device.advance(0.0, line.write_some)
    assert first.config == tuple(POWER_ON_SETTINGS[n] for _ in settings.JOINTS
                                 for n in settings.NAMES)
    assert device.advance(0.01, line.write_some).config is None     # no change
    delivered(device, frames(codec.JointConfig(2, ID['pid_kp'], 7.5)), 0.05)
    assert device.advance(0.05, line.write_some).config is None     # within 100 ms
    config = device.advance(0.1, line.write_some).config
    assert config[2 * len(settings.NAMES) + ID['pid_kp']] == 7.5
    assert device.advance(0.3, line.write_some).config is None


def test_the_opmode_is_published_when_it_changes_and_ticks_only_in_hold():
    device, line = PuppetDevice(), Line()
    step = device.advance(0.0, line.write_some)
    assert step.opmode == 'limp' and step.ticks == []
    assert device.advance(0.1, line.write_some).opmode is None
    delivered(device, frames(codec.Opmode(codec.HOLD)), 0.1)
    step = device.advance(0.2, line.write_some)
    assert step.opmode == 'hold' and len(step.ticks) == 5            # 50 Hz for 0.1 s
    assert [t.time_s for t in step.ticks] == pytest.approx([0.12, 0.14, 0.16, 0.18, 0.2])


def test_hand_torque_comes_with_each_state_set_and_holds_the_limp_arm_up():
    device, line = PuppetDevice(state_rate_hz=10.0), Line()
    torques = [device.advance(0.01 * i, line.write_some).hand_torque for i in range(201)]
    sent = [i for i, torque in enumerate(torques) if torque is not None]
    assert len(sent) in (19, 20) and all(9 <= b - a <= 11 for a, b in zip(sent, sent[1:]))
    arm, last = device.firmware.arm, torques[sent[-1]]
    # Limp at rest: the hand alone holds the arm against gravity (up to static friction).
    for joint in settings.JOINTS:
        assert last[joint] == pytest.approx(-arm.gravity_nm[joint], abs=0.061)
    assert abs(last[1]) > 0.1  # joint 1 carries the arm: a torque stuck at 0 would fail
    device.set_hand(['joint_1'], [math.nan])
    torques = [device.advance(2.0 + 0.01 * i, line.write_some).hand_torque for i in range(1, 12)]
    assert {t[1] for t in torques if t is not None} == {0.0}  # let go: nothing


def test_frames_for_a_joint_out_of_range_are_counted_when_the_count_changes():
    device, line = PuppetDevice(), Line()
    assert device.advance(0.0, line.write_some).ignored is None
    payload = codec.JointSetpoint.STRUCT.pack(9, 0.1)   # the codec refuses to encode joint 9
    joint_9 = bytes((codec.START, codec.JointSetpoint.ID)) + payload + bytes((sum(payload) & 0xFF,))
    delivered(device, joint_9 * 2, 0.01)
    assert device.advance(0.02, line.write_some).ignored == 2
    assert device.advance(0.04, line.write_some).ignored is None
    delivered(device, joint_9, 0.05)
    assert device.advance(0.06, line.write_some).ignored == 3


def test_the_pty_is_waited_on_until_the_firmware_has_work_and_briefly_with_usb_packets():
    device, line = PuppetDevice(), Line()
    assert device.poll_timeout_s(5.0) == 0.0                        # not started
    device.advance(0.0, line.write_some)
    assert device.poll_timeout_s(0.0) == pytest.approx(0.02)        # the next control tick
    assert device.poll_timeout_s(0.015) == pytest.approx(0.005)
    assert device.poll_timeout_s(3.0) == 0.0                        # late: at once
    packets = PuppetDevice(usb_packet_size=64)
    packets.advance(0.0, line.write_some)
    assert packets.poll_timeout_s(0.0) == pytest.approx(0.001)


def test_one_host_write_over_64_bytes_is_cut_into_usb_packets_but_a_slow_read_is_not():
    load = frames(*(codec.JointConfig(1, i, 10.0 + i) for i in range(12)))   # 108 bytes
    cut, whole = PuppetDevice(usb_packet_size=64), PuppetDevice(usb_packet_size=64)
    delivered(cut, load, 1.0)                   # arrived within 0.1 ms: one write
    whole.receive(None, 1.0)
    whole.receive(Chunk(load, 1.02, 1.0201, True), 1.02)   # 20 ms since the pty was empty
    held = [sum(d.firmware.config[1][settings.NAMES[i]] == 10.0 + i for i in range(12))
            for d in (cut, whole)]
    # 64 bytes hold 7 frames of 9 and the start of the 8th; the rest of it flushes packet 2.
    assert held == [7, 12]
