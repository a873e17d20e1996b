"""Input events of the study's devices and the one way to read them (pure but for the file).

An event is the kernel's `struct input_event` (evdev's types and codes, `evdev.ecodes`). A
device is read from one path: a character device (/dev/input/...) through python3-evdev,
spacenavd's socket (its SpaceMouse events turned into the same evdev events), or anything else
(a FIFO made with mkfifo, a recorded file) as raw RECORD records, which is how the tests, the
benchmark and the simulated participant inject events: encode()d records, each batch followed
by an EV_SYN/SYN_REPORT record.
"""
import collections
import math
import os
import socket
import stat
import struct
import time

from evdev import ecodes

InputEvent = collections.namedtuple('InputEvent', 't type code value')
InputEvent.__doc__ = """One input event: t (s, the writer's clock), evdev type, code, value."""
RECORD = struct.Struct('llHHi')   # seconds, microseconds, type, code, value
READ_BYTES = 64 * RECORD.size


def encode(event):
    """Return the 24 bytes of one InputEvent (t split into seconds and microseconds)."""
    seconds = math.floor(event.t)
    micros = min(int(round((event.t - seconds) * 1e6)), 999999)
    return RECORD.pack(int(seconds), micros, event.type, event.code, int(event.value))


def sync(t):
    """Return the EV_SYN/SYN_REPORT event that ends a batch written at t (s)."""
    return InputEvent(t, ecodes.EV_SYN, ecodes.SYN_REPORT, 0)


def decode(data):
    """Return ([InputEvent] of the whole records in data, the bytes of a partial last record)."""
    whole = len(data) - len(data) % RECORD.size
    events = [InputEvent(s + us * 1e-6, kind, code, value)
              for s, us, kind, code, value in RECORD.iter_unpack(data[:whole])]
    return events, bytes(data[whole:])


class RecordSource:
    """Raw RECORD records from a FIFO or a file, read without blocking.

    A FIFO is opened read-write, so that it never reads as ended while no writer has it open
    (a reader would else see end-of-file, readable, for ever) and a later writer is read.
    """

    def __init__(self, path):
        fifo = stat.S_ISFIFO(os.stat(path).st_mode)
        self._fd = os.open(path, (os.O_RDWR if fifo else os.O_RDONLY) | os.O_NONBLOCK)
        self._rest = b''

    def fileno(self):
        """Return the file descriptor (for select)."""
        return self._fd

    def ranges(self):
        """Return {} (a raw source knows no axis ranges: the defaults apply)."""
        return {}

    def read(self):
        """Return the InputEvents that have arrived ([] when none); a partial record waits."""
        data = self._rest
        while True:
            try:
                chunk = os.read(self._fd, READ_BYTES)
            except BlockingIOError:
                break
            if not chunk:
                break
            data += chunk
        events, self._rest = decode(data)
        return events

    def close(self):
        """Close the file."""
        os.close(self._fd)


class EvdevSource:
    """A character device read through python3-evdev: the same InputEvents."""

    def __init__(self, path):
        import evdev   # only for a real device
        self._device = evdev.InputDevice(path)

    def fileno(self):
        """Return the device's file descriptor (for select)."""
        return self._device.fileno()

    def ranges(self):
        """Return {ABS code: (min, max)} of the device's absolute axes."""
        absolute = self._device.capabilities().get(ecodes.EV_ABS, [])
        return {code: (info.min, info.max) for code, info in absolute}

    def read(self):
        """Return the InputEvents that have arrived ([] when none)."""
        try:
            return [InputEvent(e.sec + e.usec * 1e-6, e.type, e.code, e.value)
                    for e in self._device.read()]
        except BlockingIOError:
            return []

    def close(self):
        """Close the device."""
        self._device.close()


# spacenavd's socket (protocol 0: it sends, the client only listens): 8 native ints per event,
# [0, x, y, z, rx, ry, rz, period ms] for motion in its axes (x right, y up, z away; rx tilts
# the cap back, ry turns it left, rz rolls it right), [1 or 2 (press, release), button, ...].
SPACENAV = struct.Struct('8i')
SPACENAV_MOTION, SPACENAV_PRESS, SPACENAV_RELEASE = 0, 1, 2
# evdev axis <- (spacenavd value index, sign): the kernel's x right, y toward the user, z down
# (and its turns: pitch back, roll left, yaw right); spacenavd's default axis map, undone
SPACENAV_AXES = ((ecodes.REL_X, 1, 1), (ecodes.REL_Y, 3, -1), (ecodes.REL_Z, 2, -1),
                 (ecodes.REL_RX, 4, 1), (ecodes.REL_RY, 6, -1), (ecodes.REL_RZ, 5, -1))


def decode_spacenav(data, t):
    """Return ([InputEvent] at t (s) of spacenavd's whole packets in data, the bytes of a partial
    last one): a motion as six REL_ events, a button as BTN_0 + its number; each with SYN_REPORT.
    """
    whole = len(data) - len(data) % SPACENAV.size
    events = []
    for packet in SPACENAV.iter_unpack(data[:whole]):
        if packet[0] == SPACENAV_MOTION:
            events += [InputEvent(t, ecodes.EV_REL, code, sign * packet[index])
                       for code, index, sign in SPACENAV_AXES]
        elif packet[0] in (SPACENAV_PRESS, SPACENAV_RELEASE) and 0 <= packet[1] < 16:
            events.append(InputEvent(t, ecodes.EV_KEY, ecodes.BTN_0 + packet[1],
                                     1 if packet[0] == SPACENAV_PRESS else 0))
        else:
            continue
        events.append(sync(t))
    return events, bytes(data[whole:])


class SpacenavSource(RecordSource):
    """spacenavd's AF_UNIX socket (e.g. /var/run/spnav.sock): its events as evdev's.

    Args:
        path: the socket's path.
        clock: returns the time (s) given to the events read (time.time).
    """

    def __init__(self, path, clock=time.time):
        self._socket = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            self._socket.connect(path)
        except OSError:
            self._socket.close()
            raise
        self._socket.setblocking(False)
        self._fd, self._rest, self._clock = self._socket.fileno(), b'', clock

    def read(self):
        """Return the InputEvents of the packets that have arrived ([] when none).

        Raises:
            OSError: spacenavd closed the connection.
        """
        data = self._rest
        while True:
            try:
                chunk = self._socket.recv(16 * SPACENAV.size)
            except BlockingIOError:
                break
            if not chunk:
                if data == self._rest:
                    raise ConnectionResetError('spacenavd closed the connection')
                break
            data += chunk
        events, self._rest = decode_spacenav(data, self._clock())
        return events

    def close(self):
        """Close the connection."""
        self._socket.close()


def open_source(path):
    """Return a source of InputEvents at path: EvdevSource for a character device,
    SpacenavSource for a socket (spacenavd's), else RecordSource (OSError: it cannot be
    opened)."""
    mode = os.stat(path).st_mode
    if stat.S_ISCHR(mode):
        return EvdevSource(path)
    if stat.S_ISSOCK(mode):
        return SpacenavSource(path)
    return RecordSource(path)
