"""Unit tests of robopuppet.puppet_sim.puppet_wire: the firmware's receive logic and the USB
packet model."""
import math
import random

import pytest

from robopuppet import settings
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_model import PuppetFirmware
from robopuppet.puppet_sim.puppet_wire import (SINGLE_WRITE_SPAN_S, FirmwareReceiver,
                                               OutputQueue, ReadSpan, UsbPacketModel,
                                               device_frame)

ID = settings.CONFIG_ID
PACKET = 64


def config_frame(joint, name, value):
    return codec.encode(codec.JointConfig(joint, ID[name], value))


def load_frames():
    """The 84 settings of a load, each value unique: (joint, name) -> frame."""
    return {(j, n): config_frame(j, n, 10.0 * j + i + 0.5)
            for j in settings.JOINTS for i, n in enumerate(settings.NAMES)}


def received(frames_by_key, firmware):
    """Return how many of the settings the firmware holds."""
    return sum(firmware.config[j][n] == 10.0 * j + settings.NAMES.index(n) + 0.5
               for j, n in frames_by_key)


def pty_reads(writes, poll_times):
    """Play a pty and the simulator's reader: return (chunk, span bound) of each read.

    writes: (time, bytes) of each host write, in order. At each poll time the reader reads
    everything that has arrived (a pty keeps no write boundaries) and, as puppet_sim does,
    bounds the arrival span by the last poll that found nothing or drained the input.
    """
    reads, span, pending = [], ReadSpan(), list(writes)
    for poll in poll_times:
        chunk = b''
        while pending and pending[0][0] <= poll:
            chunk += pending.pop(0)[1]
        if chunk:
            reads.append((chunk, span.span(poll)))
        span.empty(poll)
    assert not pending, 'poll until every write has been read'
    return reads


def deliver(writes, poll_times, packet_size=PACKET):
    """Return the firmware after the host's writes went through the pty and packet model."""
    firmware = PuppetFirmware()
    receiver = FirmwareReceiver(firmware)
    model = UsbPacketModel(packet_size)
    for chunk, span in pty_reads(writes, poll_times):
        for packet in model.packets(chunk, span):
            receiver.receive(packet)
    return firmware


def prompt_polls(end_s, period_s=0.001):
    return [i * period_s for i in range(int(end_s / period_s) + 2)]


def grouped_writes(frames, per_write, gap_s, start_s=0.0025):
    """Write the frames per_write at a time, gap_s apart."""
    frames = list(frames)
    return [(start_s + k * gap_s, b''.join(frames[i:i + per_write]))
            for k, i in enumerate(range(0, len(frames), per_write))]


# Receive logic -------------------------------------------------------------------------------
def test_whole_frames_are_obeyed_in_order():
    firmware = PuppetFirmware()
    receiver = FirmwareReceiver(firmware)
    receiver.receive(config_frame(2, 'pid_kp', 3.0) + codec.encode(codec.JointSetpoint(2, 0.5))
                     + codec.encode(codec.Opmode(codec.HOLD)))
    assert receiver.frames == 3
    assert firmware.config[2]['pid_kp'] == 3.0
    assert firmware.setpoint_rad[2] == 0.5 and firmware.opmode == codec.HOLD


def test_a_frame_split_across_two_receives_is_garbage_and_its_tail_flushes_the_rest():
    firmware = PuppetFirmware()
    receiver = FirmwareReceiver(firmware)
    first, second = config_frame(1, 'pid_kp', 1.0), config_frame(1, 'pid_ki', 2.0)
    receiver.receive(first[:4])
    receiver.receive(first[4:] + second)  # starts mid-frame: everything here is flushed
    assert receiver.cut_frames == 1 and receiver.flushes == 1
    assert firmware.config[1]['pid_kp'] == 0.0 and firmware.config[1]['pid_ki'] == 0.0
    receiver.receive(second)
    assert firmware.config[1]['pid_ki'] == 2.0


def test_unknown_id_flushes_and_bad_checksum_drops_only_its_frame():
    firmware = PuppetFirmware()
    receiver = FirmwareReceiver(firmware)
    bad = bytearray(config_frame(0, 'pid_kp', 1.0))
    bad[-1] ^= 0xFF
    receiver.receive(bytes(bad) + config_frame(0, 'pid_kd', 4.0))
    assert receiver.bad_checksums == 1 and firmware.config[0]['pid_kd'] == 4.0
    # A device->host id is unknown to the firmware: the rest of the input goes.
    receiver.receive(codec.encode(codec.Heartbeat()) + config_frame(0, 'pid_ki', 5.0))
    assert receiver.flushes == 1 and firmware.config[0]['pid_ki'] == 0.0


def test_fields_are_not_range_checked_but_nothing_crashes():
    firmware = PuppetFirmware()
    receiver = FirmwareReceiver(firmware)
    raw = codec.JointConfig.STRUCT
    for joint, config_id, value in ((7, 0, 1.0), (255, 3, 1.0), (2, 12, 9.0),
                                    (2, ID['pid_kp'], math.nan)):
        payload = raw.pack(joint, config_id, value)
        receiver.receive(bytes((codec.START, codec.JointConfig.ID)) + payload
                         + bytes((sum(payload) & 0xFF,)))
    receiver.receive(bytes((codec.START, codec.Opmode.ID, 2, 2)))  # opmode 2: limp
    assert receiver.frames == 5 and firmware.ignored_frames == 2
    assert math.isnan(firmware.config[2]['pid_kp'])
    assert firmware.opmode == codec.LIMP


# USB packet model ----------------------------------------------------------------------------
def test_the_2020_host_writing_12_frames_per_write_loses_35_of_84_settings():
    frames = load_frames()
    writes = grouped_writes(frames.values(), 12, 0.01)  # 108 bytes per write
    firmware = deliver(writes, prompt_polls(0.1))
    assert received(frames, firmware) == 84 - 35
    # Without the model, the same writes lose nothing.
    assert received(frames, deliver(writes, prompt_polls(0.1), packet_size=0)) == 84


def test_large_writes_back_to_back_lose_settings_too():
    frames = load_frames()
    writes = grouped_writes(frames.values(), 12, 0.0001)
    assert received(frames, deliver(writes, prompt_polls(0.01))) < 84


@pytest.mark.parametrize('per_write', [1, 3, 7])
def test_whole_frames_in_writes_of_at_most_64_bytes_lose_nothing_however_late_the_reader(
        per_write):
    frames = load_frames()
    writes = grouped_writes(frames.values(), per_write, 0.002)  # 9 x 7 = 63 bytes at most
    end = writes[-1][0]
    rng = random.Random(per_write)
    for _ in range(200):
        polls, t = [], -0.001
        while t <= end:  # prompt polls, with stalls of up to 30 ms (a loaded machine)
            t += rng.choice((0.0011, 0.0012, 0.0015, 0.003, 0.006, rng.uniform(0.0, 0.03)))
            polls.append(t)
        assert received(frames, deliver(writes, polls)) == 84


def test_packet_model_cuts_only_reads_that_must_be_one_write():
    model = UsbPacketModel(PACKET)
    data = bytes(range(130))
    assert model.packets(data[:64], 0.0) == [data[:64]]
    assert model.packets(data, SINGLE_WRITE_SPAN_S) == [data[:64], data[64:128], data[128:]]
    assert model.packets(data, SINGLE_WRITE_SPAN_S * 1.01) == [data]
    assert UsbPacketModel(0).packets(data, 0.0) == [data]
    with pytest.raises(ValueError):
        UsbPacketModel(-1)


def test_read_span_is_bounded_by_the_last_evidence_of_emptiness():
    span = ReadSpan()
    assert span.span(5.0) == math.inf
    span.empty(1.0)
    span.empty(0.5)  # older evidence does not move the bound back
    assert span.span(1.25) == 0.25


# Device frames -------------------------------------------------------------------------------
def test_device_frames_match_the_codec_and_carry_nan_like_the_firmware():
    state = codec.JointState(3, codec.WORKING, 0.25, -1.5)
    assert device_frame(state) == codec.encode(state)
    frame = device_frame(codec.JointState(3, codec.WORKING, math.nan, 1e39))
    angle, volts = codec.JointState.STRUCT.unpack(frame[2:-1])[2:]
    assert math.isnan(angle) and volts == math.inf
    assert sum(frame[2:-1]) & 0xFF == frame[-1]


# Output queue --------------------------------------------------------------------------------
def test_large_noise_is_written_in_full_as_the_line_takes_it_while_frames_drop():
    queue = OutputQueue(1024)
    noise = bytes(random.Random(1).getrandbits(8) for _ in range(100000))
    assert queue.add(b'F' * 50) == 0
    assert queue.add(noise, droppable=False) == 0
    line = bytearray()

    def pty(data):
        line.extend(data[:4096])
        return min(len(data), 4096)
    for _ in range(40):  # the host does not read: frames beyond 1 KiB are dropped, noise kept
        queue.add(b'S' * 120)
        queue.write(lambda data: 0)
    assert queue.dropped_bytes > 0 and queue.noise_waiting() == len(noise)
    while queue.waiting():  # the host reads 4 KiB at a time
        assert queue.write(pty) > 0
    assert bytes(line[:50]) == b'F' * 50 and bytes(line[50:50 + len(noise)]) == noise
