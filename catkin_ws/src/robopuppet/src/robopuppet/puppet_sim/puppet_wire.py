"""The simulated puppet's side of the wire: the 2020 firmware's receive logic and USB packets.

Pure: no I/O, no clock, no rospy. FirmwareReceiver reads bytes exactly as the firmware's
SerialServer::rx() does (doates625/RoboPuppet; docs/serial.md, "puppet_sim_X"): each call sees
only the bytes that have arrived; after a start byte it reads the rest of the frame at once,
without waiting (a missing byte reads as -1, so a frame cut short is garbage); a byte that is
not a start byte, or an unknown id, flushes everything that has arrived; a bad checksum drops
that frame. Field values are not checked: joints out of range, any opmode byte, config ids
above 11, NaN and infinite floats all reach the firmware model as they are.

UsbPacketModel cuts what the simulator reads from its pseudo-terminal into the USB packets the
firmware would see one at a time (see its docstring for how it copes with the pty losing the
host's write boundaries). device_frame() encodes a device->host message as the firmware does,
NaN and infinity included (the firmware sends whatever its floats hold).
"""
import collections
import math
import struct

from robopuppet.protocol import codec

# Host->device frames the firmware knows: id -> message type (layout from the codec's table).
RX_TYPES = {t.ID: t for t in codec.types_sent_by(codec.TO_DEVICE)}
MISSING = -1  # what the Teensy's Serial.read() returns when nothing has arrived
FLOAT32_MAX = struct.unpack('<f', b'\xff\xff\x7f\x7f')[0]

# A read whose bytes all arrived within this many seconds is taken as one host write. A host
# whose writes that add up to more than a packet are further apart than that (HOST_WRITE_GAP_S
# leaves a margin for the kernel's delivery jitter) can never have two of them cut as one.
SINGLE_WRITE_SPAN_S = 0.0015
HOST_WRITE_GAP_S = 0.005
POLL_PERIOD_S = 0.001  # how often the simulator looks at the pty while the model is on


class FirmwareReceiver:
    """Feed the firmware the bytes of each receive call as SerialServer::rx() reads them.

    Args:
        firmware: has set_opmode(byte), configure(joint, config_id, value) and
            set_setpoint(joint, angle_rad) (robopuppet.puppet_sim.puppet_model.PuppetFirmware).
    Counters: frames (obeyed), bad_checksums, cut_frames (missing bytes: garbage), flushes
        (a non-start byte or unknown id), flushed_bytes.
    """

    def __init__(self, firmware):
        self._firmware = firmware
        self.frames = self.bad_checksums = self.cut_frames = 0
        self.flushes = self.flushed_bytes = 0

    def receive(self, available):
        """Process the bytes available to one rx() call (everything that has arrived)."""
        data = bytes(available)
        pos, end = 0, len(data)
        while pos < end:
            start = data[pos]
            msg_id = data[pos + 1] if pos + 1 < end else MISSING & 0xFF
            if start != codec.START or msg_id not in RX_TYPES:
                self.flushes += 1
                self.flushed_bytes += end - pos
                return
            message_type = RX_TYPES[msg_id]
            size = message_type.STRUCT.size
            payload = data[pos + 2:pos + 2 + size]
            checksum = data[pos + 2 + size] if pos + 2 + size < end else MISSING
            pos = min(end, pos + 3 + size)
            if len(payload) < size or checksum == MISSING:
                self.cut_frames += 1  # a missing checksum (-1) never matches a u8 sum
            elif sum(payload) & 0xFF != checksum:
                self.bad_checksums += 1
            else:
                self.frames += 1
                self._obey(message_type, message_type.STRUCT.unpack(payload))

    def _obey(self, message_type, fields):
        if message_type is codec.Opmode:
            self._firmware.set_opmode(fields[0])
        elif message_type is codec.JointConfig:
            self._firmware.configure(*fields)
        elif message_type is codec.JointSetpoint:
            self._firmware.set_setpoint(*fields)


class UsbPacketModel:
    """Cut each read of the pseudo-terminal into the USB packets the firmware receives.

    On the real link each host write goes out in packets of at most packet_size bytes (64 on
    the Teensy's full-speed USB), and in the worst case the firmware processes each packet
    before the next arrives, so a frame that straddles a packet boundary is garbage. A pty
    keeps no write boundaries: one read may hold several writes. A read whose bytes provably
    arrived within SINGLE_WRITE_SPAN_S is taken as one write and cut every packet_size bytes
    from its start; a longer read may hold several writes whose boundaries are lost, and is
    given the benefit of the doubt (delivered whole). So a host that writes whole frames, at
    most packet_size bytes per write, and keeps writes that add up to more than packet_size
    bytes at least HOST_WRITE_GAP_S apart never loses a frame here, however loaded the machine
    (a late reader only makes reads longer); a host that writes more than packet_size bytes at
    once loses frames whenever the reader is prompt, as it usually is.

    Args:
        packet_size: bytes per USB packet; 0 turns the model off (each read is delivered whole).
    """

    def __init__(self, packet_size=0, single_write_span_s=SINGLE_WRITE_SPAN_S):
        if packet_size < 0:
            raise ValueError('USB packet size must be 0 (off) or positive, got %r'
                             % (packet_size,))
        self.packet_size = int(packet_size)
        self.single_write_span_s = single_write_span_s
        self.cut_reads = 0  # reads taken as one write and cut into packets

    def packets(self, chunk, span_s):
        """Return the byte strings the firmware receives, in order, for one read.

        Args:
            chunk: the bytes of one read.
            span_s: an upper bound of the time over which those bytes arrived (ReadSpan).
        """
        size = self.packet_size
        if not size or len(chunk) <= size or span_s > self.single_write_span_s:
            return [bytes(chunk)]
        self.cut_reads += 1
        return [bytes(chunk[i:i + size]) for i in range(0, len(chunk), size)]


class ReadSpan:
    """Bound the time over which the bytes of each read arrived, from evidence of emptiness.

    Call empty(t) with a time at or before which the reader saw no bytes waiting (the time
    taken just before a select() that timed out, or just before a read that drained the
    input), and span(t) with a time taken after a read returned: the read's bytes all arrived
    within span(t) seconds.
    """

    def __init__(self):
        self._empty_s = -math.inf

    def empty(self, t_s):
        """Record that no bytes were waiting at some moment at or after t_s."""
        self._empty_s = max(self._empty_s, t_s)

    def span(self, t_s):
        """Return an upper bound of the arrival span of a read that returned before t_s."""
        return t_s - self._empty_s


class OutputQueue:
    """What the device has to send, written to the line as it takes it.

    Device frames that wait while the host does not read are dropped once more than
    limit_bytes of them wait, as the real device drops what nobody reads rather than send old
    states late; a segment already partly written is finished first, so no frame is cut. Bytes
    added with droppable=False (test noise) are always written in full.
    Counters: dropped_bytes.
    """

    def __init__(self, limit_bytes):
        self._limit_bytes = limit_bytes
        self._segments = collections.deque()  # [bytes, droppable]
        self._written = 0  # bytes of the first segment already written
        self.dropped_bytes = 0

    def add(self, data, droppable=True):
        """Queue data after what waits; return the number of device bytes dropped now."""
        if data:
            self._segments.append((bytes(data), droppable))
        waiting = sum(len(d) for d, drop in list(self._segments)[1:] if drop)
        if waiting <= self._limit_bytes:
            return 0
        head = self._segments.popleft()
        kept = [seg for seg in self._segments if not seg[1]]
        self._segments = collections.deque([head] + kept)
        self.dropped_bytes += waiting
        return waiting

    def waiting(self):
        """Return the number of bytes not written yet."""
        return sum(len(d) for d, _ in self._segments) - self._written

    def noise_waiting(self):
        """Return the number of non-droppable bytes not written yet."""
        return sum(len(d) for d, drop in self._segments if not drop) - (
            self._written if self._segments and not self._segments[0][1] else 0)

    def write(self, write_some):
        """Write what the line takes: write_some(data) returns how many bytes it took (0 for
        none); stop at the first short write. Return the number of bytes written."""
        total = 0
        while self._segments:
            data = self._segments[0][0]
            taken = write_some(data[self._written:])
            total += taken
            self._written += taken
            if self._written < len(data):
                break
            self._segments.popleft()
            self._written = 0
        return total


def device_frame(message):
    """Return the frame bytes of a device->host message, as the firmware packs its fields.

    Unlike codec.encode, NaN and infinity are sent as they are (the firmware checks nothing);
    a float beyond float32's range becomes infinity, as the firmware's float arithmetic would.
    """
    values = []
    for (_, kind, _), value in zip(type(message).FIELDS, message):
        if kind == codec.F32 and math.isfinite(value) and abs(value) > FLOAT32_MAX:
            value = math.copysign(math.inf, value)
        values.append(value)
    payload = type(message).STRUCT.pack(*values)
    return bytes((codec.START, type(message).ID)) + payload + bytes((sum(payload) & 0xFF,))
