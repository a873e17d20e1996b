"""Unit tests of protocol.state_set: plausible, whole state sets and healthy heartbeats."""
import math
import random
import struct

import pytest
from hypothesis import given, settings as hsettings, strategies as st

from robopuppet import interface, settings
from robopuppet.protocol import codec, state_set

HEARTBEAT = codec.encode(codec.Heartbeat())
LIMITS = {j: (-7.0 + 0.5 * j, 7.0 - 0.5 * j) for j in settings.JOINTS}  # one per joint


def voltage_limits(joint):
    return LIMITS[joint]


def receiver():
    return state_set.Receiver(voltage_limits)


def set_messages(seq=0, button=0):
    """A plausible state set whose values depend on seq (exact in float32)."""
    joints = [codec.JointState(j, j % 3, (seq % 50) / 16.0 - 1.5, 0.25 * j - 1.0)
              for j in settings.JOINTS]
    grippers = [codec.Gripper(g, 0.25 * g) for g in range(interface.NUM_GRIPPERS)]
    return joints + grippers + [codec.Buttons(button)]


def encode(messages):
    return b''.join(codec.encode(m) for m in messages)


def expected_set(seq=0, button=0, start_s=0.0):
    messages = set_messages(seq, button)
    return state_set.StateSet(start_s, tuple(messages[:7]), tuple(m.reading for m in
                                                                  messages[7:11]), button)


def raw_frame(msg_id, payload):
    """A frame that the encoder would refuse, with a good checksum."""
    return bytes((codec.START, msg_id)) + payload + bytes((sum(payload) & 0xFF,))


def feed(rx, data, chunk=None, now_s=0.0):
    if chunk is None:
        return rx.feed(data, now_s)
    events = []
    for i in range(0, len(data), chunk):
        events.extend(rx.feed(data[i:i + chunk], now_s))
    return events


def test_clean_sets_come_out_whole_in_order():
    rx = receiver()
    events = feed(rx, encode(set_messages(1, 2)) + encode(set_messages(2, 0)))
    assert events == [expected_set(1, 2), expected_set(2, 0)]
    assert (rx.sets, rx.dropped_sets, rx.stray_frames, rx.implausible_frames) == (2, 0, 0, 0)


def test_a_set_is_out_only_with_its_buttons_frame():
    rx = receiver()
    stream = encode(set_messages(3))
    assert rx.feed(stream[:-4], 0.0) == []  # all but the buttons frame
    assert rx.feed(stream[-4:], 0.01) == [expected_set(3, 0, start_s=0.0)]


@pytest.mark.parametrize('chunk', [1, 2, 5, 13, 64])
def test_whole_and_byte_by_byte_give_the_same_events(chunk):
    rng = random.Random(7)
    stream = b''
    for seq in range(30):
        stream += HEARTBEAT if seq % 3 == 0 else b''
        stream += bytes(rng.randrange(256) for _ in range(rng.randrange(20)))
        stream += encode(set_messages(seq, seq % 5))
    whole_rx, split_rx = receiver(), receiver()
    whole = feed(whole_rx, stream)
    assert feed(split_rx, stream, chunk) == whole
    assert len(whole) > 20
    counters = ('sets', 'dropped_sets', 'stray_frames', 'implausible_frames', 'heartbeats',
                'refused_heartbeats')
    assert ([getattr(whole_rx, c) for c in counters]
            == [getattr(split_rx, c) for c in counters])


@pytest.mark.parametrize('index, bad, what', [
    (2, codec.JointState(2, 0, 3.5, 0.0), 'JointState.angle_rad'),
    (2, codec.JointState(2, 0, -3.2, 0.0), 'JointState.angle_rad'),
    (4, codec.JointState(4, 0, 0.0, LIMITS[4][1] + 0.75), 'JointState.voltage_v'),
    (4, codec.JointState(4, 0, 0.0, LIMITS[4][0] - 0.75), 'JointState.voltage_v'),
    (6, codec.JointState(6, 0, 0.0, -1.6e29), 'JointState.voltage_v'),
    (8, codec.Gripper(1, 1.5), 'Gripper.reading'),
    (10, codec.Gripper(3, -0.01), 'Gripper.reading'),
])
def test_an_implausible_field_drops_the_set_and_says_what(index, bad, what):
    messages = set_messages(4)
    messages[index] = bad
    rx = receiver()
    events = feed(rx, encode(messages) + encode(set_messages(5)))
    assert events == [expected_set(5)]
    assert rx.implausible_frames == 1 and rx.dropped_sets == 1
    assert what in rx.last_problem


def test_voltage_limits_are_those_of_the_joint_plus_the_margin():
    rx = receiver()
    messages = set_messages(6)
    messages[5] = codec.JointState(5, 0, 0.0, LIMITS[5][1] + state_set.VOLTAGE_MARGIN_V - 0.125)
    messages[6] = codec.JointState(6, 0, 0.0, LIMITS[6][0] - state_set.VOLTAGE_MARGIN_V + 0.125)
    assert len(feed(rx, encode(messages))) == 1
    assert rx.implausible_frames == 0


def test_0_volts_is_plausible_whatever_the_limits():
    # A limp device reports 0 V; limits such as [-1.5, -0.5] V (allowed) must not make every
    # set implausible (found by test_topic_garbage: the link then re-opened every 4 s).
    rx = state_set.Receiver(lambda joint: (-1.5, -0.5) if joint == 2 else (1.0, 1.0))
    messages = [codec.JointState(m.joint, m.status, m.angle_rad, 0.0)
                if type(m) is codec.JointState else m for m in set_messages(7)]
    assert len(feed(rx, encode(messages))) == 1
    assert rx.implausible_frames == 0
    messages[2] = codec.JointState(2, 0, 0.0, 0.75)   # beyond 0 V plus the margin
    assert feed(rx, encode(messages)) == [] and rx.implausible_frames == 1


def test_float32_pi_is_a_plausible_angle():
    messages = set_messages(0)
    pi32 = struct.unpack('<f', struct.pack('<f', math.pi))[0]
    messages[0] = codec.JointState(0, 0, pi32, 0.0)
    messages[1] = codec.JointState(1, 0, -pi32, 0.0)
    assert len(feed(receiver(), encode(messages))) == 1


@pytest.mark.parametrize('msg_id, payload, what', [
    (0x41, bytes((5,)), 'Buttons.button = 5'),
    (0x41, bytes((0xA5,)), 'Buttons.button = 165'),
    (0x20, bytes((7, 0)) + struct.pack('<ff', 0.0, 0.0), 'JointState.joint = 7'),
    (0x20, bytes((3, 3)) + struct.pack('<ff', 0.0, 0.0), 'JointState.status = 3'),
    (0x40, bytes((0,)) + struct.pack('<f', math.nan), 'Gripper.reading = nan'),
])
def test_an_out_of_range_index_is_not_ignored_silently(msg_id, payload, what):
    # The buttons frame 5 used to vanish without a word: now it drops the set and says why.
    messages = set_messages(1)
    frames = [codec.encode(m) for m in messages]
    position = {0x41: 11, 0x20: 3, 0x40: 7}[msg_id]
    frames[position] = raw_frame(msg_id, payload)
    rx = receiver()
    events = feed(rx, b''.join(frames) + encode(set_messages(2)))
    assert events == [expected_set(2)]
    assert what in rx.last_problem
    assert rx.dropped_sets == 1


@pytest.mark.parametrize('order', [
    [0, 1, 2, 4, 3, 5, 6, 7, 8, 9, 10, 11],  # swapped joints
    [0, 1, 2, 3, 4, 5, 6, 8, 7, 9, 10, 11],  # swapped grippers
    [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10],  # no buttons, next set follows
    [0, 1, 2, 3, 5, 6, 7, 8, 9, 10, 11],  # joint 4 lost
    [0, 1, 2, 3, 4, 5, 6, 11, 7, 8, 9, 10],  # buttons before the grippers
    [0, 1, 2, 3, 4, 5, 6, 6, 7, 8, 9, 10, 11],  # a joint twice
])
def test_a_set_out_of_order_or_incomplete_is_dropped(order):
    messages = set_messages(8)
    rx = receiver()
    events = feed(rx, encode(messages[i] for i in order) + encode(set_messages(9)))
    assert events == [expected_set(9)]
    assert rx.dropped_sets >= 1


def test_frames_outside_a_set_are_stray_and_never_published():
    rx = receiver()
    stray = encode([codec.Buttons(1), codec.Gripper(3, 0.0), codec.JointState(3, 0, 0.5, 0.0)])
    assert feed(rx, stray + encode(set_messages(1))) == [expected_set(1)]
    assert rx.stray_frames == 3 and rx.dropped_sets == 0


def test_a_byte_dropped_inside_a_set_drops_it_but_noise_before_joint_0_does_not():
    frames = [codec.encode(m) for m in set_messages(2)]
    inside = b''.join(frames[:5]) + b'\x17' + b''.join(frames[5:])
    before = b'\x00\x13\xa5' + bytes(codec.MAX_FRAME_LEN) + b''.join(frames)
    rx = receiver()
    assert feed(rx, inside + before) == [expected_set(2)]
    assert rx.dropped_sets == 1


def test_a_cut_off_frame_that_swallows_a_real_one_never_makes_a_set():
    # A fault seen on the line: a cut-off joint state whose false checksum happens to match the
    # real frame that follows; it decodes (plausibly or not) and eats that frame.
    frames = [codec.encode(m) for m in set_messages(3)]
    real = frames[3]
    tail = real[:6]  # the false frame's last 6 payload bytes, then real[6] as its checksum
    for angle_byte in range(256):
        head = bytes((3, 0, 0x00, angle_byte))
        if (sum(head) + sum(tail)) & 0xFF == real[6]:
            break
    cut_off = bytes((codec.START, 0x20)) + head
    stream = b''.join(frames[:3]) + cut_off + b''.join(frames[3:])
    decoded = codec.Decoder().feed(stream)
    assert codec.JointState(3, 0, 0.0, 0.0) not in decoded and len(decoded) == 12  # swallowed
    rx = receiver()
    assert feed(rx, stream + encode(set_messages(4))) == [expected_set(4)]
    assert rx.dropped_sets == 1


def test_a_set_spread_over_too_long_is_dropped():
    stream = encode(set_messages(1))
    rx = receiver()
    assert rx.feed(stream[:30], 10.0) == []
    assert rx.feed(stream[30:], 10.0 + state_set.SET_SPAN_S + 0.1) == []
    assert rx.dropped_sets == 1


def test_a_heartbeat_counts_after_a_whole_set_once():
    rx = receiver()
    assert rx.feed(HEARTBEAT, 0.0) == []  # no whole set yet
    assert rx.feed(encode(set_messages(1)) + HEARTBEAT, 0.1) == [expected_set(1, start_s=0.1),
                                                                  codec.Heartbeat()]
    assert rx.feed(HEARTBEAT, 0.7) == []  # a second one needs another whole set first
    assert (rx.heartbeats, rx.refused_heartbeats) == (1, 2)


def test_heartbeats_closer_than_the_spacing_count_once():
    rx = receiver()
    stream = encode(set_messages(1)) + HEARTBEAT
    assert rx.feed(stream, 0.0)[-1] == codec.Heartbeat()
    assert rx.feed(stream, state_set.HEARTBEAT_SPACING_S - 0.01)[-1] != codec.Heartbeat()
    assert rx.feed(stream, state_set.HEARTBEAT_SPACING_S + 0.01)[-1] == codec.Heartbeat()


def test_a_heartbeat_inside_or_before_a_set_counts():
    frames = [codec.encode(m) for m in set_messages(1)]
    rx = receiver()
    rx.feed(b''.join(frames), 0.0)
    events = rx.feed(b''.join(frames[:7]) + HEARTBEAT + b''.join(frames[7:]), 0.1)
    assert events == [codec.Heartbeat(), expected_set(1, start_s=0.1)]
    assert rx.feed(HEARTBEAT + b''.join(frames), 1.2)[0] == codec.Heartbeat()


UNCLEAN = [
    b'\x00',  # a dropped byte
    b'\xa5\x20\x01' + bytes(codec.MAX_FRAME_LEN),  # a false start
    codec.encode(codec.Gripper(0, 0.5)),  # a stray frame
    codec.encode(codec.JointState(0, 0, 9.0, 0.0)),  # an implausible frame
]


@pytest.mark.parametrize('before', UNCLEAN)
@pytest.mark.parametrize('after', UNCLEAN)
def test_a_heartbeat_between_unclean_bytes_is_refused(before, after):
    rx = receiver()
    rx.feed(encode(set_messages(1)), 0.0)
    assert rx.feed(before + HEARTBEAT + after + encode(set_messages(2)), 0.1) == [
        expected_set(2, start_s=0.1)]
    assert rx.heartbeats == 0 and rx.refused_heartbeats == 1
    # The next whole set and a clean heartbeat: healthy again.
    assert rx.feed(encode(set_messages(3)) + HEARTBEAT, 0.2)[-1] == codec.Heartbeat()


@pytest.mark.parametrize('noise', UNCLEAN)
def test_a_heartbeat_clean_on_one_side_counts(noise):
    # Noise right before a real heartbeat (it comes with the next frame), or right after it.
    rx = receiver()
    rx.feed(encode(set_messages(1)), 0.0)
    events = rx.feed(noise + HEARTBEAT, 0.1)
    assert events == []
    assert rx.feed(encode(set_messages(2)), 0.1) == [codec.Heartbeat(),
                                                      expected_set(2, start_s=0.1)]
    rx.feed(HEARTBEAT + noise, 1.0)
    assert rx.heartbeats == 2


def test_a_heartbeat_long_after_the_last_set_is_refused():
    rx = receiver()
    rx.feed(encode(set_messages(1)), 0.0)
    assert rx.feed(HEARTBEAT, state_set.HEARTBEAT_SET_WINDOW_S + 0.1) == []


def test_noise_alone_gives_no_heartbeat_and_no_set():
    rng = random.Random(3)
    palette = (0xA5, 0x00, 0x20, 0x40, 0x41, 0x01, 0x03)  # rich in starts, ids, small numbers
    noise = bytes(rng.choice(palette) for _ in range(200000))
    rx = receiver()
    decoded = codec.Decoder(codec.types_sent_by(codec.TO_HOST)).feed(noise)
    assert sum(isinstance(m, codec.Heartbeat) for m in decoded) > 100  # what used to count
    assert feed(rx, noise, 4096) == []


# Property: clean sets and heartbeats with garbage between sets (as a real line's quiet gap
# follows a noise burst, zeros after each burst keep a false start inside the garbage).
garbage = st.one_of(st.binary(max_size=30),
                    st.lists(st.sampled_from((0xA5, 0x00, 0x20, 0x40, 0x41, 0x03)),
                             max_size=30).map(bytes))


@hsettings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(garbage, st.booleans(), st.integers(0, 4)), min_size=1, max_size=12),
       st.integers(1, 17))
def test_fuzz_noise_between_sets_makes_no_false_set_and_loses_none(items, chunk):
    gap = bytes(codec.MAX_FRAME_LEN)
    stream = b''.join(noise + gap + (HEARTBEAT if beat else b'') + encode(set_messages(i, b))
                      for i, (noise, beat, b) in enumerate(items))
    rx = receiver()
    events = feed(rx, stream, chunk)
    sets = [e for e in events if isinstance(e, state_set.StateSet)]
    assert sets == [expected_set(i, b) for i, (_, _, b) in enumerate(items)]
    assert rx.heartbeats <= len(items) - 1  # never more than one per clean set before it
    assert feed(receiver(), stream) == events
