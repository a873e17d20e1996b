"""serial_X: the bridge between the puppet's microcontroller (serial frames) and ROS topics."""
import gc
import threading
import time

import rospy
from std_msgs.msg import Float32, String

from robopuppet import interface, params, settings
from robopuppet.link_recovery import LinkRecovery
from robopuppet.periodic import Guard
from robopuppet.protocol.core_runner import CoreRunner
from robopuppet.protocol.link_health import LinkFacts
from robopuppet.protocol.serial_core import SerialCore
from robopuppet.protocol.serial_link import SerialLink
from robopuppet.protocol.serial_topics import SerialTopics
from robopuppet_msgs.msg import ArmSettings

OPEN_RETRY_S = 0.5  # pause between attempts to open a missing or lost port


class SerialNode:
    """Wire robopuppet.protocol.serial_core.SerialCore to the port, the topics and a worker.

    The port's reader thread and the subscriber threads feed the core (core_runner.CoreRunner:
    one lock, the writes paced outside it); one worker thread steps it when it has work or a
    deadline (a settings write, the silence watch, feel's watchdog, diagnostics; docs/serial.md).

    Publishes (in <ns> = /puppet/arm_<side>; see robopuppet.protocol.state_output): heartbeat
        (std_msgs/Empty), joint_states (sensor_msgs/JointState: position rad, effort V,
        header.frame_id the settings.angle_tag of the settings sent to the device last),
        joint_J/angle, joint_J/voltage (std_msgs/Float32: rad, V), joint_J/enc_stat
        (std_msgs/String), gripper_G (std_msgs/Float32, 0-1), user_btn (std_msgs/UInt8);
        /diagnostics (1 Hz): status '<node>: puppet serial link', hardware_id <ns>.
        opmode (std_msgs/String): limp, when feel mode ends without being told (its setpoint
        watchdog, a reconnect, a refused feel), so that every node knows the puppet is limp.
    Subscribes: active_settings (robopuppet_msgs/ArmSettings, latched, from config_X: the
        settings the device should hold, the feel profile's in feel mode), opmode
        (std_msgs/String: limp; hold; feel = the device's hold, once it holds the feel
        profile, + the setpoint watchdog), joint_J/setpoint (std_msgs/Float32, rad).
    Echoes: each link_ping (robopuppet_msgs/LinkPing, arm_X's) goes back at once on link_echo
        with `echoed` = rospy.Time.now(), both tcp_nodelay: arm_X measures the clock that stamps
        joint_states (serial_topics). After a cut, link_recovery connects anew to arm_X's
        publishers once link_ping is stuck.
    Parameters: ~arm_side (str, required: L or R); ~port_name (str, default /dev/ttyACM0);
        ~baud_rate (int, default 115200); ~joint_topic_rate (float, default 100.0 Hz: cap of
        the per-joint topics); ~silence_timeout (float, default 3.0 s: no frame for this long
        re-opens the port, then every second); ~comm_rate (float, default 10 Hz as arm_X's; 0: no
        check: the firmware's compile-time state-set rate; 20 % off is reported);
        ~feel_setpoint_timeout (float, default 0.5 s: in feel mode, no joint setpoint for this
        long, or no feel gains on the device this long after the opmode, sends limp, logs a
        warning and publishes limp on opmode).
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        ns = interface.puppet_ns(side) + '/'
        self._name, port = rospy.get_name(), rospy.get_param('~port_name', '/dev/ttyACM0')
        self._wake, self._stopping = threading.Event(), threading.Event()
        self._guard = Guard(self._name, rospy.logerr)
        info, warn = (lambda text: rospy.loginfo('%s: %s', self._name, text),
                      lambda text: rospy.logwarn('%s: %s', self._name, text))
        self._link = SerialLink(port, int(rospy.get_param('~baud_rate', 115200)),
                                self._on_connect, self._on_data, info, warn, retry_s=OPEN_RETRY_S)
        active = ns + interface.ACTIVE_SETTINGS
        self._runner = CoreRunner(self._link, lambda write: SerialCore(
            write, time.monotonic, info, warn, port, active,
            topic_rate_hz=float(rospy.get_param('~joint_topic_rate', 100.0)),
            silence_timeout_s=float(rospy.get_param('~silence_timeout', 3.0)),
            comm_rate_hz=float(rospy.get_param('~comm_rate', interface.DEFAULT_COMM_RATE_HZ)),
            feel_timeout_s=params.positive('~feel_setpoint_timeout',
                                           rospy.get_param('~feel_setpoint_timeout', 0.5))))
        self._core = self._runner.core
        self._worker = threading.Thread(target=self._work, name='serial worker', daemon=True)
        self._topics = SerialTopics(side, self._name)
        self._active_sub = rospy.Subscriber(active, ArmSettings, self._on_active, queue_size=1)
        # Woken: feel mode's watchdog deadline may come before the worker's planned step.
        self._subs = [rospy.Subscriber(ns + interface.OPMODE, String, lambda msg: self._call(
            self._core.on_opmode, msg.data, wake=True), queue_size=10)]
        self._subs += [rospy.Subscriber(interface.joint_topic(side, j, 'setpoint'), Float32,
                                        lambda msg, j: self._call(self._core.on_setpoint, j,
                                                                  msg.data), j, queue_size=10)
                       for j in settings.JOINTS]
        self._recovery = LinkRecovery(self._name, [ns + interface.LINK_PING])

    def run(self):
        """Run the link and the worker until shutdown."""
        rospy.on_shutdown(self._stop)
        self._link.start()
        self._worker.start()
        self._recovery.start()
        rospy.spin()

    def _stop(self):
        self._stopping.set()
        self._wake.set()
        self._worker.join(2.0)
        self._link.stop()

    def _call(self, method, *args, wake=False):
        """Call a core method (CoreRunner.call); wake the worker if asked or if it has work."""
        result, due = self._runner.call(method, *args)
        if wake or due:
            self._wake.set()
        return result

    def _on_connect(self):
        self._call(self._core.on_connect, wake=True)

    def _on_data(self, data):
        self._topics.publish(self._call(self._core.on_data, data))

    def _on_active(self, msg):
        joints = [(j.joint, {n: getattr(j, n) for n in settings.NAMES}) for j in msg.joints]
        self._call(self._core.on_stored, msg.revision, joints, msg.profile)

    def _work(self):
        next_s = time.monotonic()
        while not self._stopping.is_set():
            self._wake.wait(max(0.0, next_s - time.monotonic()))
            self._wake.clear()
            # A failed step is logged and counted (Guard); the next comes a second later.
            next_s = self._guard.call('serial worker', self._step) or time.monotonic() + 1.0

    def _step(self):
        link, guard = self._link, self._guard
        actions = self._runner.call(self._core.step, LinkFacts(
            link.connected, link.connects, link.write_errors, guard.errors + link.callback_errors,
            guard.last_error, self._active_sub.get_num_connections()))[0]
        if actions.opmode is not None:
            self._topics.publish_opmode(actions.opmode)
        if actions.reopen:
            link.reopen()
        if actions.diagnostics is not None:
            self._topics.publish_diagnostics(actions.diagnostics)
        return actions.next_s


def main():
    """Run the serial node until shutdown."""
    rospy.init_node('serial_interface')
    try:
        node = SerialNode()
    except (KeyError, ValueError) as error:
        rospy.logfatal('serial node cannot start: %s', error)
        raise SystemExit(1)
    # What start-up made lives as long as the node: out of the cyclic collector's way, a full
    # collection (now and then) stops every thread for ~0.2 ms instead of ~11 ms.
    gc.freeze()
    node.run()
