"""The simulated puppet as its node drives it: firmware, wire and operator input, time passed in.

Pure: no rospy, no clock, no port. PuppetDevice takes the host's bytes as the pseudo-terminal
delivered them (pty_port.Chunk), cuts them into the USB packets the firmware would see
(puppet_wire), runs the firmware (puppet_model) up to a time, queues the frames it sends (test
line noise goes just before the next joint-state frame), writes them through a function it is
given, and says what the node publishes and logs. Times are monotonic seconds.
Not thread-safe: the node calls it under one lock.
"""
import collections
import math
import reprlib

from robopuppet import interface, settings
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_model import PuppetFirmware
from robopuppet.puppet_sim.puppet_wire import (POLL_PERIOD_S, FirmwareReceiver, OutputQueue,
                                               ReadSpan, UsbPacketModel, device_frame)

JOINT_INDEX = {name: j for j, name in enumerate(settings.JOINT_NAMES)}
# Device frames that the pty did not take yet are kept up to this much, about eight state sets;
# beyond it, like the real device, the simulator drops what nobody reads rather than deliver old
# states late.
PENDING_LIMIT_BYTES = 1024
NOISE_LIMIT_BYTES = 1 << 20  # line noise waiting to be written; more is refused
# A hand target beyond this is refused: pi, plus the GUI's 1 mrad slider step (its ends round
# outward to +-3.142 rad).
HAND_LIMIT_RAD = math.pi + 1e-3
MAX_WAIT_S = 0.1             # the pty is looked at least this often, whatever is due
CONFIG_PERIOD_S = 0.1        # the device's settings are published at most this often
# device_config's layout: (label, size, stride) of its rows (joints) and columns (settings).
CONFIG_DIMS = (('joint', settings.NUM_JOINTS, settings.NUM_JOINTS * len(settings.NAMES)),
               ('setting', len(settings.NAMES), len(settings.NAMES)))

Step = collections.namedtuple('Step', 'config opmode ticks ignored notes hand_torque')
Step.__doc__ = """What one step leads to: `config` the 7 x 12 settings the device holds (row per
joint, settings.NAMES order) to publish, or None; `opmode` 'limp' or 'hold' to publish, or None;
`ticks` the puppet_model.ControlTicks run in hold since the last step; `ignored` the count of
frames for a joint out of range when it changed, else None; `notes` lines to log about the host
(not) reading; `hand_torque` the 7 torques (N m) the operator's hand exerts on the joints now (0
where it lets go) when a state set went out in this step (so at the state rate), else None."""


def check_params(hall_disconnected, usb_packet_size):
    """Check the node's ~hall_disconnected (list of int) and ~usb_packet_size (int).

    Raises:
        ValueError: naming the parameter.
    """
    if not isinstance(hall_disconnected, list) or not all(
            isinstance(j, int) for j in hall_disconnected):
        raise ValueError('~hall_disconnected must be a list of joint numbers, got %r'
                         % (hall_disconnected,))
    if not isinstance(usb_packet_size, int):
        raise ValueError('~usb_packet_size must be an integer, got %r' % (usb_packet_size,))


def hand_targets(names, positions):
    """Return {joint: mechanical angle rad} of the hand topic's joint names and positions.

    NaN lets go of a joint; any other position must lie in [-pi, pi] (a human hand turns a
    joint no further; a target such as 1e308 rad would spin the joint for good).

    Raises:
        ValueError: a name is not joint_0..joint_6, the counts differ, or a position is
            infinite or outside [-pi, pi]; the whole message is refused.
    """
    if len(positions) != len(names) or any(n not in JOINT_INDEX for n in names):
        raise ValueError('need names from joint_0..joint_6 and one position each; got names %s '
                         'with %d positions' % (reprlib.repr(list(names)), len(positions)))
    wild = [(n, p) for n, p in zip(names, positions)
            if not (math.isnan(p) or abs(p) <= HAND_LIMIT_RAD)]
    if wild:
        raise ValueError('hand targets must lie in [-pi, pi] rad (NaN lets go), got %s'
                         % reprlib.repr(wild))
    return {JOINT_INDEX[n]: p for n, p in zip(names, positions)}


class PuppetDevice:
    """The 2020 firmware on a pseudo-terminal: bytes and operator input in, frames out.

    Args:
        state_rate_hz: rate of the state sets.
        hall_disconnected: hall-encoder joints (of 1, 3, 5) missing at power-on.
        usb_packet_size: bytes per USB packet the firmware receives (0: reads whole).

    Raises:
        ValueError: an argument is unusable.
    """

    def __init__(self, state_rate_hz=10.0, hall_disconnected=(), usb_packet_size=0):
        self.firmware = PuppetFirmware(float(state_rate_hz), hall_disconnected=hall_disconnected)
        self.hall_disconnected = list(hall_disconnected)
        self._receiver = FirmwareReceiver(self.firmware)
        self._packets = UsbPacketModel(usb_packet_size)
        self._span = ReadSpan()
        self._out = OutputQueue(PENDING_LIMIT_BYTES)
        self._noise = b''
        self._dropping = False
        self._published_config = self._published_opmode = None
        self._next_config_s = -math.inf
        self._ignored = 0

    def summary(self):
        """Return a line that describes the simulated device."""
        return 'state sets at %.1f Hz, hall encoders disconnected: %s, USB packets: %s' % (
            self.firmware.state_period_s ** -1, self.hall_disconnected or 'none',
            self._packets.packet_size or 'off')

    # Operator (ValueError: the input is ignored) -----------------------------------------------
    def set_hand(self, names, positions):
        """Move the hand toward joint names' mechanical angles (rad); NaN lets go of a joint."""
        self.firmware.set_hand(hand_targets(names, positions))

    def set_button(self, button):
        """Hold user button 1-4 down, or none (0)."""
        self.firmware.set_button(button)

    def set_grippers(self, readings):
        """Set the four gripper readings (0-1; reading 3 is the end piece's button)."""
        self.firmware.set_grippers(list(readings))

    def add_noise(self, data):
        """Put raw bytes on the line once, right before the next joint-state frame."""
        waiting = len(self._noise) + self._out.noise_waiting()
        if waiting + len(data) > NOISE_LIMIT_BYTES:
            raise ValueError('%d bytes of line noise: at most %d bytes of noise may wait to be '
                             'written, and %d wait (the host reads them as fast as it reads)'
                             % (len(data), NOISE_LIMIT_BYTES, waiting))
        self._noise += bytes(data)

    # The pseudo-terminal ----------------------------------------------------------------------
    def poll_timeout_s(self, now_s):
        """Return how long the pty may be waited on from now_s (s): until the firmware's next
        work, at most MAX_WAIT_S, and POLL_PERIOD_S with the packet model on."""
        due = self.firmware.next_due_s()
        wait = 0.0 if due is None else min(MAX_WAIT_S, max(0.0, due - now_s))
        if self._packets.packet_size:
            wait = min(wait, POLL_PERIOD_S)  # to tell one host write from several
        return wait

    def output_waiting(self):
        """Return True when frames or noise wait to be written."""
        return self._out.waiting() > 0

    def receive(self, chunk, idle_since_s):
        """Deliver one read of the pty to the firmware, in the USB packets it would see.

        Args:
            chunk: a pty_port.Chunk, or None when no byte was waiting at some moment at or
                after idle_since_s.
        """
        if chunk is None:
            self._span.empty(idle_since_s)
            return
        if chunk.data:
            for packet in self._packets.packets(chunk.data, self._span.span(chunk.end_s)):
                self._receiver.receive(packet)
        if chunk.drained:
            self._span.empty(chunk.start_s)

    def advance(self, now_s, write_some):
        """Run the firmware to now_s, queue what it sends and write what the line takes.

        Args:
            write_some(data): writes what it can of data, returns the count written (0: none).
        Returns:
            a Step.
        """
        firmware = self.firmware
        out = firmware.advance(now_s)
        states = [i for i, m in enumerate(out) if isinstance(m, codec.JointState)]
        noise = b''
        if self._noise and states:
            noise, self._noise = self._noise, b''
        cut = states[0] if states else len(out)
        notes = self._send(b''.join(device_frame(m) for m in out[:cut]), noise,
                           b''.join(device_frame(m) for m in out[cut:]), write_some)
        config = tuple(firmware.config[j][n] for j in settings.JOINTS for n in settings.NAMES)
        if config == self._published_config or now_s < self._next_config_s:
            config = None
        else:
            self._published_config, self._next_config_s = config, now_s + CONFIG_PERIOD_S
        opmode = interface.DEVICE_OPMODES[firmware.opmode]
        if opmode == self._published_opmode:
            opmode = None
        else:
            self._published_opmode = opmode
        ignored = firmware.ignored_frames
        if ignored == self._ignored:
            ignored = None
        else:
            self._ignored = ignored
        hand_torque = tuple(firmware.arm.hand_torque_nm.tolist()) if states else None
        return Step(config, opmode, firmware.take_control_ticks(), ignored, notes, hand_torque)

    def _send(self, frames, noise, more_frames, write_some):
        """Queue frames, noise (kept whole) and more frames; write what the line takes.

        Returns:
            lines to log when the host stops or starts reading again.
        """
        notes = []
        dropped = sum(self._out.add(data, droppable) for data, droppable in (
            (frames, True), (noise, False), (more_frames, True)))
        if dropped and not self._dropping:
            notes.append('the host is not reading; dropping frames')
            self._dropping = True
        if self._out.write(write_some) and self._dropping:
            notes.append('the host reads again (%d bytes dropped so far)'
                         % self._out.dropped_bytes)
            self._dropping = False
        return notes
