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

from robopuppet import codec, settings
from robopuppet.puppet_model import PuppetFirmware

JOINT_INDEX = {name: j for j, name in enumerate(settings.JOINT_NAMES)}
# Bytes that the pty did not take yet (a partial write) are kept up to this much, about eight
# state sets; beyond it, like the real device, the simulator drops what nobody reads rather than
# deliver old states late.
PENDING_LIMIT_BYTES = 1024


class PuppetSimNode:
    """Behave byte for byte like the puppet's microcontroller on a pseudo-terminal.

    The serial node opens ~port_link like a USB serial port. The firmware and arm model are
    robopuppet.puppet_model; this adapter moves bytes and operator input.

    Subscribes (in <sim> = /puppet_sim/arm_<side>):
        hand (sensor_msgs/JointState): joint_0..joint_6 mechanical angles rad where the
            operator's hand moves the puppet; a NaN position lets go of that joint. Until the
            first message the hand holds the rest pose (see docs/serial.md).
        button (std_msgs/UInt8): the user button held down, 1-4, or 0 for none.
        grippers (std_msgs/Float32MultiArray): four readings 0-1; reading 3 is the end-piece
            button, ~1 released and ~0 pressed.
        line_noise (std_msgs/UInt8MultiArray): raw bytes put on the line once, right before the
            next joint state frame (a test hook for garbage on the wire).
    Publishes (latched, for tests and the GUI):
        <sim>/device_config (std_msgs/Float32MultiArray): the 7 x 12 settings the device holds,
            row per joint in settings.NAMES order; at most 10 Hz, when they change.
        <sim>/device_opmode (std_msgs/String): 'limp' or 'hold', when it changes.
    Parameters:
        ~arm_side (str, required): 'L' or 'R'.
        ~port_link (str, default /tmp/robopuppet_arm_<side>): symlink to the pseudo-terminal.
        ~state_rate (float, default 10.0 Hz): rate of the state sets.
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        settings.namespace(side)  # validates the side
        self._sim_ns = '/puppet_sim/arm_%s' % side
        self._link = rospy.get_param('~port_link', '/tmp/robopuppet_arm_%s' % side)
        self._firmware = PuppetFirmware(float(rospy.get_param('~state_rate', 10.0)))
        self._decoder = codec.Decoder(codec.types_sent_by(codec.TO_DEVICE))
        self._lock = threading.Lock()
        self._master = self._slave = None
        self._pending = b''  # written to the line as the pty takes it
        self._dropped_bytes = 0
        self._dropping = False
        self._noise = b''
        self._pub_config = rospy.Publisher(self._sim_ns + '/device_config', Float32MultiArray,
                                           queue_size=1, latch=True)
        self._pub_opmode = rospy.Publisher(self._sim_ns + '/device_opmode', String,
                                           queue_size=1, latch=True)
        self._subs = [
            rospy.Subscriber(self._sim_ns + '/hand', JointState, self._on_hand, queue_size=10),
            rospy.Subscriber(self._sim_ns + '/button', UInt8, self._on_button, queue_size=10),
            rospy.Subscriber(self._sim_ns + '/grippers', Float32MultiArray, self._on_grippers,
                             queue_size=10),
            rospy.Subscriber(self._sim_ns + '/line_noise', UInt8MultiArray, self._on_noise,
                             queue_size=10)]

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
        with self._lock:
            self._noise += bytes(msg.data)

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

    def _write(self, data):
        """Put data on the line after what is pending; write as much as the pty takes.

        Like the real device, drop what nobody reads: when more than PENDING_LIMIT_BYTES wait,
        they are dropped, counted and logged (once until the host reads again).
        """
        self._pending += data
        if len(self._pending) > PENDING_LIMIT_BYTES:
            self._dropped_bytes += len(self._pending)
            self._pending = b''
            if not self._dropping:
                rospy.loginfo('%s: the host is not reading; dropping frames', self._link)
                self._dropping = True
            return
        try:
            written = os.write(self._master, self._pending) if self._pending else 0
        except BlockingIOError:
            written = 0
        self._pending = self._pending[written:]
        if written and self._dropping:
            rospy.loginfo('%s: the host reads again (%d bytes dropped so far)', self._link,
                          self._dropped_bytes)
            self._dropping = False

    def run(self):
        """Serve the pseudo-terminal until shutdown; the link is removed on exit."""
        self._open_pty()
        try:
            self._loop()
        finally:
            self._close_pty()

    def _loop(self):
        published_config = published_opmode = None
        next_publish_s = 0.0
        while not rospy.is_shutdown():
            with self._lock:
                due = self._firmware.next_due_s()
            wait = 0.0 if due is None else min(0.1, max(0.0, due - time.monotonic()))
            # The simulator keeps its own slave fd open, so reading the master never gives EIO.
            writable = [self._master] if self._pending else []
            ready, _, _ = select.select([self._master], writable, [], wait)
            messages = []
            if ready:
                try:
                    messages = self._decoder.feed(os.read(self._master, 4096))
                except (BlockingIOError, InterruptedError):
                    pass
            with self._lock:
                for message in messages:
                    self._firmware.handle(message)
                out = self._firmware.advance(time.monotonic())
                config = tuple(self._firmware.config[j][n]
                               for j in settings.JOINTS for n in settings.NAMES)
                opmode = codec.OPMODES[self._firmware.opmode]
                frames = [codec.encode(m) for m in out]
                if self._noise and any(isinstance(m, codec.JointState) for m in out):
                    first = next(i for i, m in enumerate(out) if isinstance(m, codec.JointState))
                    frames.insert(first, self._noise)
                    self._noise = b''
            if frames or self._pending:
                self._write(b''.join(frames))
            now = time.monotonic()
            if config != published_config and now >= next_publish_s:
                self._publish_config(config)
                published_config, next_publish_s = config, now + 0.1
            if opmode != published_opmode:
                self._pub_opmode.publish(String(opmode))
                published_opmode = opmode

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
