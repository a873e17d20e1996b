"""The puppet's serial protocol (docs/serial.md): encode frames and decode a byte stream.

Pure: no I/O, no clock, no rospy. A frame is START, id, payload (fixed length per id), checksum,
where checksum is the sum of the payload bytes modulo 256. Multi-byte fields are little-endian.

Every message type is defined once, in the table below, as a namedtuple class carrying its wire
id, direction, struct layout and the allowed values of each field. Encoding and decoding are
driven by that table only.
"""
import collections
import math
import struct

from robopuppet import interface, settings

START = 0xA5
TO_HOST = 'device->host'
TO_DEVICE = 'host->device'

# Wire codes: the opmode frame's mode indexes interface.DEVICE_OPMODES, a joint state's status
# interface.ENC_STATUS.
LIMP, HOLD = range(len(interface.DEVICE_OPMODES))
WORKING, DISCONNECTED, UNCALIBRATED = range(len(interface.ENC_STATUS))

U8 = 'B'
F32 = 'f'


class CodecError(ValueError):
    """A message that cannot be put on the wire (a field out of range or not finite)."""


def _message_type(class_name, msg_id, direction, *fields):
    """Define a message class from (field name, U8 or F32, number of allowed u8 values) rows.

    A U8 field accepts 0 .. count-1; an F32 field accepts any finite number.
    """
    cls = collections.namedtuple(class_name, [f[0] for f in fields])
    cls.ID = msg_id
    cls.DIRECTION = direction
    cls.FIELDS = tuple((f[0], f[1], f[2] if len(f) > 2 else None) for f in fields)
    cls.STRUCT = struct.Struct('<' + ''.join(f[1] for f in fields))
    return cls


# The message table: one row per frame the 2020 firmware sends or takes.
Heartbeat = _message_type('Heartbeat', 0x00, TO_HOST)
Opmode = _message_type('Opmode', 0x10, TO_DEVICE, ('mode', U8, len(interface.DEVICE_OPMODES)))
JointState = _message_type('JointState', 0x20, TO_HOST,
                           ('joint', U8, settings.NUM_JOINTS),
                           ('status', U8, len(interface.ENC_STATUS)),
                           ('angle_rad', F32), ('voltage_v', F32))
JointConfig = _message_type('JointConfig', 0x30, TO_DEVICE,
                            ('joint', U8, settings.NUM_JOINTS),
                            ('config_id', U8, len(settings.SETTINGS)),
                            ('value', F32))
JointSetpoint = _message_type('JointSetpoint', 0x31, TO_DEVICE,
                              ('joint', U8, settings.NUM_JOINTS), ('angle_rad', F32))
Gripper = _message_type('Gripper', 0x40, TO_HOST,
                        ('gripper', U8, interface.NUM_GRIPPERS), ('reading', F32))
Buttons = _message_type('Buttons', 0x41, TO_HOST, ('button', U8, interface.NUM_BUTTONS + 1))

MESSAGE_TYPES = (Heartbeat, Opmode, JointState, JointConfig, JointSetpoint, Gripper, Buttons)
MAX_FRAME_LEN = 3 + max(t.STRUCT.size for t in MESSAGE_TYPES)


def types_sent_by(direction):
    """Return the message types that travel in `direction` (TO_HOST or TO_DEVICE)."""
    return tuple(t for t in MESSAGE_TYPES if t.DIRECTION == direction)


def _field_problem(message_type, values):
    """Return why `values` are not valid fields of message_type, or None if they are."""
    for (name, kind, count), value in zip(message_type.FIELDS, values):
        if kind == U8 and not 0 <= value < count:
            return '%s.%s = %r is outside 0..%d' % (message_type.__name__, name, value, count - 1)
        if kind == F32 and not math.isfinite(value):
            return '%s.%s = %r is not finite' % (message_type.__name__, name, value)
    return None


def encode(message):
    """Return the frame bytes of a message (an instance of one of MESSAGE_TYPES).

    Raises:
        CodecError: a field is out of range, not finite, or too large for float32
            (struct refuses to round such a value to infinity).
    """
    cls = type(message)
    problem = _field_problem(cls, message)
    if problem:
        raise CodecError(problem)
    try:
        payload = cls.STRUCT.pack(*message)
    except (struct.error, OverflowError) as error:
        raise CodecError('%s: %s' % (cls.__name__, error)) from None
    return bytes((START, cls.ID)) + payload + bytes((sum(payload) & 0xFF,))


class Decoder:
    """Turn byte chunks of any size into messages; drop bad frames and resynchronise.

    A frame with an unknown id, a bad checksum or invalid fields (an index out of range, a
    non-finite float) is dropped by discarding only its start byte, so that a false start
    (0xA5 inside a payload or in line noise) never swallows a real frame that follows. At most
    MAX_FRAME_LEN - 1 bytes stay buffered between calls.

    Counters (totals since construction): frames, dropped_bytes, bad_checksums, unknown_ids,
    invalid_frames; last_invalid says what was wrong with the newest invalid frame.
    """

    def __init__(self, message_types=MESSAGE_TYPES):
        """Accept only message_types; any other id counts as unknown."""
        self._types = [None] * 256
        for message_type in message_types:
            self._types[message_type.ID] = message_type
        self._buffer = bytearray()
        self.frames = 0
        self.dropped_bytes = 0
        self.bad_checksums = 0
        self.unknown_ids = 0
        self.invalid_frames = 0
        self.last_invalid = ''
        self._skipped = 0  # bytes dropped since the last frame returned

    @property
    def pending(self):
        """Return the number of bytes held back waiting for the rest of a frame."""
        return len(self._buffer)

    def feed(self, data):
        """Add received bytes; return the list of messages completed by them, in order."""
        return [message for message, _ in self.feed_frames(data)]

    def feed_frames(self, data):
        """Add received bytes; return (message, skipped) pairs completed by them, in order.

        skipped is the number of bytes dropped (garbage, or frames refused for an unknown id, a
        bad checksum or invalid fields) between the previous frame returned and this one; 0
        means the frame sits on a clean frame boundary. It does not depend on how the stream
        is split into chunks.
        """
        buf = self._buffer
        buf += data
        types = self._types
        frames = []
        pos = 0
        end = len(buf)
        dropped_before = self.dropped_bytes
        while pos < end:
            start = buf.find(START, pos)
            if start < 0:
                self.dropped_bytes += end - pos
                pos = end
                break
            self.dropped_bytes += start - pos
            pos = start
            if pos + 1 >= end:
                break  # need the id
            message_type = types[buf[pos + 1]]
            if message_type is None:
                self.unknown_ids += 1
                self.dropped_bytes += 1
                pos += 1
                continue
            size = message_type.STRUCT.size
            stop = pos + 2 + size
            if stop >= end:
                break  # need the rest of the frame
            if sum(buf[pos + 2:stop]) & 0xFF != buf[stop]:
                self.bad_checksums += 1
                self.dropped_bytes += 1
                pos += 1
                continue
            values = message_type.STRUCT.unpack_from(buf, pos + 2)
            problem = _field_problem(message_type, values)
            if problem:
                self.invalid_frames += 1
                self.last_invalid = problem
                self.dropped_bytes += 1
                pos += 1
                continue
            skipped = self._skipped + self.dropped_bytes - dropped_before
            frames.append((message_type._make(values), skipped))
            self._skipped = 0
            dropped_before = self.dropped_bytes
            self.frames += 1
            pos = stop + 1
        self._skipped += self.dropped_bytes - dropped_before
        del buf[:pos]
        return frames
