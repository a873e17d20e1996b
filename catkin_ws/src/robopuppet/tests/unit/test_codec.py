"""Unit tests of robopuppet.protocol.codec: the puppet's serial frames (docs/serial.md)."""
import math
import struct

import pytest
from hypothesis import given, settings as hsettings, strategies as st

from robopuppet.protocol import codec

# One valid example of every message type (floats exact in float32).
EXAMPLES = [
    codec.Heartbeat(),
    codec.Opmode(codec.HOLD),
    codec.JointState(6, codec.UNCALIBRATED, -1.25, 7.25),
    codec.JointConfig(3, 11, -1.0),
    codec.JointSetpoint(0, 0.5),
    codec.Gripper(3, 0.25),
    codec.Buttons(4),
]
A5_FLOAT = struct.unpack('<f', bytes((0xA5, 0xA5, 0x20, 0x3F)))[0]  # 0xA5 twice in its bytes


def decode_all(data, chunk=None):
    decoder = codec.Decoder()
    if chunk is None:
        return decoder.feed(data), decoder
    out = []
    for i in range(0, len(data), chunk):
        out.extend(decoder.feed(data[i:i + chunk]))
    return out, decoder


def test_table_matches_design_ids_and_lengths():
    layout = {t.__name__: (t.ID, t.STRUCT.size) for t in codec.MESSAGE_TYPES}
    assert layout == {'Heartbeat': (0x00, 0), 'Opmode': (0x10, 1), 'JointState': (0x20, 10),
                      'JointConfig': (0x30, 6), 'JointSetpoint': (0x31, 5),
                      'Gripper': (0x40, 5), 'Buttons': (0x41, 1)}


def test_encode_matches_hand_made_frame():
    payload = bytes((2, 1)) + struct.pack('<ff', 0.5, -3.0)
    expected = bytes((0xA5, 0x20)) + payload + bytes((sum(payload) % 256,))
    assert codec.encode(codec.JointState(2, 1, 0.5, -3.0)) == expected
    assert codec.encode(codec.Heartbeat()) == b'\xa5\x00\x00'


@pytest.mark.parametrize('message', EXAMPLES, ids=lambda m: type(m).__name__)
def test_every_message_round_trips(message):
    decoded, decoder = decode_all(codec.encode(message))
    assert decoded == [message]
    assert decoder.frames == 1 and decoder.pending == 0


def test_whole_and_byte_by_byte_give_the_same_messages():
    stream = b''.join(codec.encode(m) for m in EXAMPLES * 3)
    whole, _ = decode_all(stream)
    for size in (1, 2, 5, 13):
        assert decode_all(stream, size)[0] == whole == EXAMPLES * 3


def test_leading_garbage_is_dropped_and_counted():
    garbage = b'\x00\x01\xa5\xff\x7f\xa5'
    decoded, decoder = decode_all(garbage + codec.encode(codec.Buttons(2)))
    assert decoded == [codec.Buttons(2)]
    assert decoder.dropped_bytes == len(garbage)
    assert decoder.unknown_ids == 2  # 0xA5 0xFF, and 0xA5 0xA5 (the second 0xA5 starts over)


def test_bad_checksum_drops_the_frame_only():
    bad = bytearray(codec.encode(codec.Gripper(1, 0.5)))
    bad[-1] ^= 0x01
    good = codec.encode(codec.Gripper(2, 0.75))
    decoded, decoder = decode_all(bytes(bad) + good)
    assert decoded == [codec.Gripper(2, 0.75)]
    assert decoder.bad_checksums == 1


def test_unknown_id_is_dropped():
    decoded, decoder = decode_all(b'\xa5\x99\x01\x02' + codec.encode(codec.Heartbeat()))
    assert decoded == [codec.Heartbeat()]
    assert decoder.unknown_ids == 1


def test_decoder_ignores_ids_of_the_other_direction():
    decoder = codec.Decoder(codec.types_sent_by(codec.TO_HOST))
    stream = codec.encode(codec.Opmode(1)) + codec.encode(codec.Heartbeat())
    assert decoder.feed(stream) == [codec.Heartbeat()]
    assert decoder.unknown_ids == 1


def test_start_byte_inside_payload_is_data():
    message = codec.JointState(5, 0, A5_FLOAT, A5_FLOAT)
    frame = codec.encode(message)
    assert frame.count(0xA5) >= 5
    assert decode_all(frame, 1)[0] == [message]


def test_false_start_does_not_swallow_the_next_frame():
    # A stray 0xA5 0x20 claims the next 11 bytes, which begin a real frame.
    real = codec.encode(codec.JointState(1, 0, 0.125, 0.375))
    decoded, decoder = decode_all(b'\xa5\x20' + real + real)
    assert decoded == [codec.JointState(1, 0, 0.125, 0.375)] * 2
    assert decoder.bad_checksums == 1


def test_truncated_frame_then_a_real_one():
    real = codec.encode(codec.Gripper(0, 1.0))
    truncated = codec.encode(codec.JointState(0, 0, 1.0, 1.0))[:6]
    for size in (None, 1):
        decoded, _ = decode_all(truncated + real + real, size)
        assert decoded == [codec.Gripper(0, 1.0)] * 2


def test_incomplete_frame_waits_for_the_rest():
    frame = codec.encode(codec.JointSetpoint(4, -0.5))
    decoder = codec.Decoder()
    assert decoder.feed(frame[:-1]) == []
    assert decoder.pending == len(frame) - 1
    assert decoder.feed(frame[-1:]) == [codec.JointSetpoint(4, -0.5)]


def test_out_of_range_fields_are_dropped_as_invalid():
    payload = bytes((7, 0)) + struct.pack('<ff', 0.0, 0.0)  # joint 7 does not exist
    frame = bytes((0xA5, 0x20)) + payload + bytes((sum(payload) % 256,))
    nan = struct.pack('<f', math.nan)
    nan_frame = bytes((0xA5, 0x40, 0)) + nan + bytes((sum(bytes((0,)) + nan) % 256,))
    decoded, decoder = decode_all(frame + nan_frame + codec.encode(codec.Buttons(0)))
    assert decoded == [codec.Buttons(0)]
    assert decoder.invalid_frames == 2


def test_invalid_frames_say_what_was_wrong():
    decoder = codec.Decoder()
    assert decoder.feed(bytes((0xA5, 0x41, 5, 5))) == []
    assert decoder.last_invalid == 'Buttons.button = 5 is outside 0..4'


def test_feed_frames_counts_the_bytes_skipped_before_each_frame():
    beat = codec.encode(codec.Heartbeat())
    bad = bytearray(codec.encode(codec.Gripper(1, 0.5)))
    bad[-1] ^= 0x01
    stream = beat + beat + b'\x01\x02' + beat + bytes(bad) + beat
    expected = [(codec.Heartbeat(), 0), (codec.Heartbeat(), 0), (codec.Heartbeat(), 2),
                (codec.Heartbeat(), len(bad))]
    for size in (None, 1, 2, 7):
        decoder = codec.Decoder()
        if size is None:
            assert decoder.feed_frames(stream) == expected
        else:
            assert [f for i in range(0, len(stream), size)
                    for f in decoder.feed_frames(stream[i:i + size])] == expected


@pytest.mark.parametrize('message', [codec.JointState(7, 0, 0.0, 0.0), codec.Opmode(2),
                                     codec.JointSetpoint(0, math.inf),
                                     codec.JointConfig(0, 12, 1.0), codec.Buttons(5),
                                     codec.Gripper(0, math.nan), codec.JointSetpoint(0, 1e39)])
def test_encode_refuses_invalid_messages(message):
    with pytest.raises(codec.CodecError):
        codec.encode(message)


def test_buffer_stays_bounded_on_endless_noise():
    decoder = codec.Decoder()
    for _ in range(100):
        decoder.feed(b'\xa5\x20' + b'\x00' * 9)  # a start that never completes with a checksum
        assert decoder.pending < codec.MAX_FRAME_LEN
    assert decoder.dropped_bytes > 1000


# Property: valid frames mixed with garbage that holds no complete valid frame.
floats = st.floats(width=32, allow_nan=False, allow_infinity=False)
messages = st.one_of(
    st.builds(codec.Heartbeat),
    st.builds(codec.Opmode, st.integers(0, 1)),
    st.builds(codec.JointState, st.integers(0, 6), st.integers(0, 2), floats, floats),
    st.builds(codec.JointConfig, st.integers(0, 6), st.integers(0, 11), floats),
    st.builds(codec.JointSetpoint, st.integers(0, 6), floats),
    st.builds(codec.Gripper, st.integers(0, 3), floats),
    st.builds(codec.Buttons, st.integers(0, 4)))


garbage = st.one_of(st.binary(max_size=20),  # and garbage rich in start bytes and real ids:
                    st.lists(st.sampled_from((0xA5, 0x00, 0x20, 0x30, 0x41, 0xFF)),
                             max_size=20).map(bytes))


@hsettings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(garbage, messages), max_size=20), st.integers(1, 17))
def test_fuzz_frames_survive_garbage(items, chunk):
    """Garbage never costs a real frame that follows it, whatever the chunk size."""
    # A false start inside the garbage claims at most MAX_FRAME_LEN bytes; zero padding of that
    # length keeps such a claim inside garbage, as a real line's quiet gap between frames does.
    gap = bytes(codec.MAX_FRAME_LEN - 1)
    stream = b''.join(garbage + gap + codec.encode(message) for garbage, message in items)
    decoded, _ = decode_all(stream, chunk)
    # Every real frame is found, in order; garbage may add chance frames in between.
    remaining = iter(decoded)
    assert all(any(m == d for d in remaining) for _, m in items)
    assert decode_all(stream)[0] == decoded
