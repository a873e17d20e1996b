"""puppet_sim_X: the simulated puppet controller on a pseudo-terminal, played by ROS topics."""
import threading
import time

import rosgraph
import rospkg
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32MultiArray, UInt8, UInt8MultiArray

from robopuppet import interface
from robopuppet.periodic import Guard
from robopuppet.puppet_sim.puppet_device import PuppetDevice, check_params
from robopuppet.puppet_sim.puppet_publishers import StepPublishers
from robopuppet.puppet_sim.pty_port import PtyPort


class PuppetSimNode:
    """Behave byte for byte like the puppet's microcontroller (the 2020 firmware) on a pty.

    The serial node opens ~port_link like a USB serial port. The device is puppet_device (over
    puppet_model, puppet_arm and puppet_wire), the pty pty_port, the publishers
    puppet_publishers; this adapter moves bytes and operator input between them and ROS.

    Subscribes (in <sim> = /puppet_sim/arm_<side>):
        hand (sensor_msgs/JointState): joint_0..joint_6 mechanical angles rad where the
            operator's hand moves the puppet; a NaN position lets go of that joint; a message
            with a position infinite or outside [-pi, pi] is refused (warning). Until the
            first message the hand holds the rest pose (see docs/serial.md). The hand grips a
            joint for 1 s after each target for it, then rests and gives way to its motor
            (puppet_arm: HAND_GRIP_S, HAND_YIELD_V); to hold on, send the target again.
        button (std_msgs/UInt8): the user button held down, 1-4, or 0 for none.
        grippers (std_msgs/Float32MultiArray): four readings 0-1; reading 3 is the end-piece
            button, ~1 released and ~0 pressed.
        line_noise (std_msgs/UInt8MultiArray): raw bytes put on the line once, right before the
            next joint state frame, all of them, as fast as the host reads (a test hook for
            garbage on the wire; at most 1 MiB may wait, more is refused).
    Publishes (for tests and the GUI):
        <sim>/device_config (std_msgs/Float32MultiArray, latched): the last value the device
            received for each of the 7 x 12 settings (power-on values before), row per joint
            in settings.NAMES order; at most 10 Hz, when they change.
        <sim>/device_opmode (std_msgs/String, latched): 'limp' or 'hold' (the firmware's two;
            serial_X puts feel on the wire as hold), when it changes.
        <sim>/control (sensor_msgs/JointState): every 50 Hz control tick in hold; names
            joint_0..joint_6, position = setpoints rad, velocity = reported angles rad,
            effort = PID voltages V.
        <sim>/hand_torque (sensor_msgs/JointState): with every state set (~state_rate; one
            for the sets a late step catches up);
            names joint_0..joint_6, effort = the torque N m the operator's hand exerts on each
            joint (0 where it lets go): in feel mode, what the nurse feels.
    Parameters:
        ~arm_side (str, required): 'L' or 'R'.
        ~port_link (str, default $ROS_HOME/robopuppet/pty_<master host>_<port>_arm_<side>, see
            interface.sim_link_prefix): symlink to the pseudo-terminal; refused (exit 1) while
            another live simulator owns it, removed at exit only while it is still ours.
        ~state_rate (float, default 10.0 Hz): rate of the state sets.
        ~hall_disconnected (list of int, default []): hall-encoder joints (1, 3, 5) missing at
            power-on: they report Disconnected and angle 0.
        ~usb_packet_size (int, default 0 = off): deliver host bytes to the firmware in USB
            packets of at most this many bytes (64: the Teensy's full-speed USB), see
            puppet_wire.UsbPacketModel for the host writes it can tell apart.
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        self._ns = interface.sim_ns(side)  # ValueError for a bad side
        default_link = '%s_arm_%s' % (interface.sim_link_prefix(
            rosgraph.get_master_uri(), rospkg.get_ros_home()), side)
        self._pty = PtyPort(rospy.get_param('~port_link', default_link))
        missing = rospy.get_param('~hall_disconnected', [])
        packet_size = rospy.get_param('~usb_packet_size', 0)
        check_params(missing, packet_size)
        self._device = PuppetDevice(rospy.get_param('~state_rate', 10.0), missing, packet_size)
        self._guard = Guard(rospy.get_name(), rospy.logerr)
        self._lock = threading.Lock()
        self._publishers = StepPublishers(self._ns)
        device = self._device
        self._subs = [
            self._subscribe(interface.SIM_HAND, JointState, device.set_hand,
                            lambda m: (m.name, m.position)),
            self._subscribe(interface.SIM_BUTTON, UInt8, device.set_button, lambda m: (m.data,)),
            self._subscribe(interface.SIM_GRIPPERS, Float32MultiArray, device.set_grippers,
                            lambda m: (m.data,)),
            self._subscribe(interface.SIM_LINE_NOISE, UInt8MultiArray, device.add_noise,
                            lambda m: (bytes(m.data),))]
        rospy.loginfo('%s: %s', self._ns, device.summary())

    def _subscribe(self, name, msg_type, action, fields):
        """Subscribe: each message runs action(*fields(msg)); a ValueError is logged."""
        topic = '%s/%s' % (self._ns, name)

        def on_msg(msg):
            with self._lock:
                try:
                    action(*fields(msg))
                except ValueError as error:
                    rospy.logwarn('%s: %s; ignored', topic, error)
        return rospy.Subscriber(topic, msg_type, on_msg, queue_size=10)

    def run(self):
        """Serve the pseudo-terminal until shutdown; our link is removed on exit."""
        try:
            rospy.loginfo('simulated puppet on %s -> %s', self._pty.link, self._pty.open())
            while not rospy.is_shutdown():
                if self._guard.call('simulator loop', self._step) is None:
                    time.sleep(0.05)  # a failure repeats at most 20 times a second
        finally:
            self._pty.close()

    def _step(self):
        """One pass: read what the host sent, run the firmware, write what it sends, publish."""
        before = time.monotonic()
        with self._lock:
            timeout_s = self._device.poll_timeout_s(before)
            writing = self._device.output_waiting()
        chunk = self._pty.poll(timeout_s, writing)
        with self._lock:
            self._device.receive(chunk, before)
            step = self._device.advance(time.monotonic(), self._pty.write_some)
        self._publishers.publish(step)
        if step.ignored is not None:
            rospy.logwarn_throttle(5.0, '%s: %d frames for a joint out of range 0-6 ignored (the '
                                   'real firmware would write past its arrays)', self._pty.link,
                                   step.ignored)
        for note in step.notes:
            rospy.loginfo('%s: %s', self._pty.link, note)
        return True


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
