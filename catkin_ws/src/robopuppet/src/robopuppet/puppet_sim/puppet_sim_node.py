"""puppet_sim_X: the simulated puppet controller on a pseudo-terminal, played by ROS topics."""
import contextlib
import os
import select
import threading
import time
import tty

import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, MultiArrayDimension, String, UInt8, UInt8MultiArray

from robopuppet import interface, settings
from robopuppet.periodic import Guard
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_model import PuppetFirmware
from robopuppet.puppet_sim.puppet_wire import (POLL_PERIOD_S, FirmwareReceiver, OutputQueue, ReadSpan,
                                    UsbPacketModel, device_frame)

JOINT_INDEX = {name: j for j, name in enumerate(settings.JOINT_NAMES)}
# Device frames that the pty did not take yet are kept up to this much, about eight state sets;
# beyond it, like the real device, the simulator drops what nobody reads rather than deliver old
# states late.
PENDING_LIMIT_BYTES = 1024
NOISE_LIMIT_BYTES = 1 << 20  # line noise waiting to be written; more is refused
READ_SIZE = 4096


class PuppetSimNode:
    """Behave byte for byte like the puppet's microcontroller (the 2020 firmware) on a pty.

    The serial node opens ~port_link like a USB serial port. The firmware and arm model are
    puppet_model (and puppet_arm), the receive logic and USB packets puppet_wire; this adapter
    moves bytes and operator input.

    Subscribes (in <sim> = /puppet_sim/arm_<side>):
        hand (sensor_msgs/JointState): joint_0..joint_6 mechanical angles rad where the
            operator's hand moves the puppet; a NaN position lets go of that joint. Until the
            first message the hand holds the rest pose (see docs/serial.md).
        button (std_msgs/UInt8): the user button held down, 1-4, or 0 for none.
        grippers (std_msgs/Float32MultiArray): four readings 0-1; reading 3 is the end-piece
            button, ~1 released and ~0 pressed.
        line_noise (std_msgs/UInt8MultiArray): raw bytes put on the line once, right before the
            next joint state frame, all of them, as fast as the host reads (a test hook for
            garbage on the wire; at most NOISE_LIMIT_BYTES may wait, more is refused).
    Publishes (for tests and the GUI):
        <sim>/device_config (std_msgs/Float32MultiArray, latched): the last value the device
            received for each of the 7 x 12 settings (power-on values before), row per joint
            in settings.NAMES order; at most 10 Hz, when they change.
        <sim>/device_opmode (std_msgs/String, latched): 'limp' or 'hold', when it changes.
        <sim>/control (sensor_msgs/JointState): every 50 Hz control tick in hold; names
            joint_0..joint_6, position = setpoints rad, velocity = reported angles rad,
            effort = PID voltages V.
    Parameters:
        ~arm_side (str, required): 'L' or 'R'.
        ~port_link (str, default /tmp/robopuppet_arm_<side>): symlink to the pseudo-terminal.
        ~state_rate (float, default 10.0 Hz): rate of the state sets.
        ~hall_disconnected (list of int, default []): hall-encoder joints (1, 3, 5) missing at
            power-on: they report Disconnected and angle 0.
        ~usb_packet_size (int, default 0 = off): deliver host bytes to the firmware in USB
            packets of at most this many bytes (64: the Teensy's full-speed USB), see
            puppet_wire.UsbPacketModel for the host writes it can tell apart.
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        interface.puppet_ns(side)  # validates the side
        self._sim_ns = '/puppet_sim/arm_%s' % side
        self._link = rospy.get_param('~port_link', '/tmp/robopuppet_arm_%s' % side)
        missing = rospy.get_param('~hall_disconnected', [])
        if not isinstance(missing, list) or not all(isinstance(j, int) for j in missing):
            raise ValueError('~hall_disconnected must be a list of joint numbers, got %r'
                             % (missing,))
        packet_size = rospy.get_param('~usb_packet_size', 0)
        if not isinstance(packet_size, int):
            raise ValueError('~usb_packet_size must be an integer, got %r' % (packet_size,))
        self._firmware = PuppetFirmware(float(rospy.get_param('~state_rate', 10.0)),
                                        hall_disconnected=missing)
        self._receiver = FirmwareReceiver(self._firmware)
        self._packets = UsbPacketModel(packet_size)
        self._span = ReadSpan()
        self._guard = Guard(rospy.get_name(), rospy.logerr)
        self._lock = threading.Lock()
        self._master = self._slave = None
        self._out = OutputQueue(PENDING_LIMIT_BYTES)
        self._dropping = False
        self._noise = b''
        self._ignored_logged = 0
        self._published_config = self._published_opmode = None
        self._next_config_s = 0.0
        self._pub_config = rospy.Publisher(self._sim_ns + '/device_config', Float32MultiArray,
                                           queue_size=1, latch=True)
        self._pub_opmode = rospy.Publisher(self._sim_ns + '/device_opmode', String,
                                           queue_size=1, latch=True)
        self._pub_control = rospy.Publisher(self._sim_ns + '/control', JointState,
                                            queue_size=100)
        self._subs = [
            rospy.Subscriber(self._sim_ns + '/hand', JointState, self._on_hand, queue_size=10),
            rospy.Subscriber(self._sim_ns + '/button', UInt8, self._on_button, queue_size=10),
            rospy.Subscriber(self._sim_ns + '/grippers', Float32MultiArray, self._on_grippers,
                             queue_size=10),
            rospy.Subscriber(self._sim_ns + '/line_noise', UInt8MultiArray, self._on_noise,
                             queue_size=10)]
        rospy.loginfo('%s: state sets at %.1f Hz, hall encoders disconnected: %s, USB packets: '
                      '%s', self._sim_ns, self._firmware.state_period_s ** -1, missing or 'none',
                      packet_size or 'off')

    # Operator --------------------------------------------------------------------------------
    def _on_hand(self, msg):
        if len(msg.position) != len(msg.name) or any(n not in JOINT_INDEX for n in msg.name):
            rospy.logwarn('%s/hand: need names from joint_0..joint_6 and one position each; '
                          'got names %s with %d positions; ignored', self._sim_ns,
                          list(msg.name), len(msg.position))
            return
        with self._lock:
            self._firmware.set_hand({JOINT_INDEX[n]: p for n, p in zip(msg.name, msg.position)})

    def _on_button(self, msg):
        with self._lock:
            try:
                self._firmware.set_button(msg.data)
            except ValueError as error:
                rospy.logwarn('%s/button: %s; ignored', self._sim_ns, error)

    def _on_grippers(self, msg):
        with self._lock:
            try:
                self._firmware.set_grippers(list(msg.data))
            except ValueError as error:
                rospy.logwarn('%s/grippers: %s; ignored', self._sim_ns, error)

    def _on_noise(self, msg):
        data = bytes(msg.data)
        with self._lock:
            waiting = len(self._noise) + self._out.noise_waiting()
            if waiting + len(data) > NOISE_LIMIT_BYTES:
                rospy.logwarn('%s/line_noise: %d bytes refused: at most %d bytes of noise may '
                              'wait to be written, and %d wait (the host reads them as fast as '
                              'it reads)', self._sim_ns, len(data), NOISE_LIMIT_BYTES, waiting)
                return
            self._noise += data

    # Pseudo-terminal -------------------------------------------------------------------------
    def _open_pty(self):
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)  # the host sees a raw port even before it configures it
        os.set_blocking(self._master, False)
        temporary = '%s.%d.tmp' % (self._link, os.getpid())
        with contextlib.suppress(FileNotFoundError):
            os.unlink(temporary)  # left by a crashed process that had the same pid
        os.symlink(os.ttyname(self._slave), temporary)
        os.replace(temporary, self._link)
        rospy.loginfo('simulated puppet on %s -> %s', self._link, os.ttyname(self._slave))

    def _close_pty(self):
        try:
            if os.readlink(self._link) == os.ttyname(self._slave):
                os.unlink(self._link)
        except OSError:
            pass  # the link was removed or replaced by someone else: leave it
        os.close(self._master)
        os.close(self._slave)

    def _write_some(self, data):
        try:
            return os.write(self._master, data)
        except BlockingIOError:
            return 0

    def run(self):
        """Serve the pseudo-terminal until shutdown; the link is removed on exit."""
        self._open_pty()
        try:
            while not rospy.is_shutdown():
                if self._guard.call('simulator loop', self._step) is None:
                    time.sleep(0.05)  # a failure repeats at most 20 times a second
        finally:
            self._close_pty()

    def _step(self):
        """One pass: read what the host sent, run the firmware, write what it sends."""
        with self._lock:
            due = self._firmware.next_due_s()
        before = time.monotonic()
        wait = 0.0 if due is None else min(0.1, max(0.0, due - before))
        if self._packets.packet_size:
            wait = min(wait, POLL_PERIOD_S)  # to tell one host write from several
        # The simulator keeps its own slave fd open, so reading the master never gives EIO.
        writable = [self._master] if self._out.waiting() else []
        readable, _, _ = select.select([self._master], writable, [], wait)
        packets = []
        if readable:
            read_at = time.monotonic()
            try:
                data = os.read(self._master, READ_SIZE)
            except (BlockingIOError, InterruptedError):
                data = b''
            if data:
                packets = self._packets.packets(data, self._span.span(time.monotonic()))
            if len(data) < READ_SIZE:
                self._span.empty(read_at)
        else:
            self._span.empty(before)
        with self._lock:
            for packet in packets:
                self._receiver.receive(packet)
            out = self._firmware.advance(time.monotonic())
            ticks = self._firmware.take_control_ticks()
            config = tuple(self._firmware.config[j][n]
                           for j in settings.JOINTS for n in settings.NAMES)
            opmode = interface.OPMODES[self._firmware.opmode]
            ignored = self._firmware.ignored_frames
            states = [i for i, m in enumerate(out) if isinstance(m, codec.JointState)]
            noise = b''
            if self._noise and states:
                noise, self._noise = self._noise, b''
            cut = states[0] if states else len(out)
            self._send(b''.join(device_frame(m) for m in out[:cut]), noise,
                       b''.join(device_frame(m) for m in out[cut:]))
        self._publish(config, opmode, ticks, ignored)
        return True

    def _send(self, frames, noise, more_frames):
        """Queue frames, noise (kept whole) and more frames; write what the pty takes."""
        dropped = sum(self._out.add(data, droppable) for data, droppable in (
            (frames, True), (noise, False), (more_frames, True)))
        if dropped and not self._dropping:
            rospy.loginfo('%s: the host is not reading; dropping frames', self._link)
            self._dropping = True
        if self._out.write(self._write_some) and self._dropping:
            rospy.loginfo('%s: the host reads again (%d bytes dropped so far)', self._link,
                          self._out.dropped_bytes)
            self._dropping = False

    def _publish(self, config, opmode, ticks, ignored):
        now = time.monotonic()
        if config != self._published_config and now >= self._next_config_s:
            self._publish_config(config)
            self._published_config, self._next_config_s = config, now + 0.1
        if opmode != self._published_opmode:
            self._pub_opmode.publish(String(opmode))
            self._published_opmode = opmode
        for tick in ticks:
            msg = JointState(name=list(settings.JOINT_NAMES), position=list(tick.setpoint_rad),
                             velocity=list(tick.angle_rad), effort=list(tick.voltage_v))
            msg.header.stamp = rospy.Time.now()
            self._pub_control.publish(msg)
        if ignored != self._ignored_logged:
            rospy.logwarn_throttle(5.0, '%s: %d frames for a joint out of range 0-6 ignored (the '
                                   'real firmware would write past its arrays)', self._link,
                                   ignored)
            self._ignored_logged = ignored

    def _publish_config(self, values):
        msg = Float32MultiArray(data=list(values))
        msg.layout.dim = [
            MultiArrayDimension(label='joint', size=settings.NUM_JOINTS, stride=len(values)),
            MultiArrayDimension(label='setting', size=len(settings.NAMES),
                                stride=len(settings.NAMES))]
        self._pub_config.publish(msg)


def main():
    """Run the simulated puppet controller until shutdown."""
    rospy.init_node('puppet_sim')
    try:
        node = PuppetSimNode()
    except (KeyError, ValueError) as error:
        rospy.logfatal('puppet_sim cannot start: %s', error)
        raise SystemExit(1)
    try:
        node.run()
    except OSError as error:
        rospy.logfatal('puppet_sim: pseudo-terminal failed: %s', error)
        raise SystemExit(1)
