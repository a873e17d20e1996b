"""serial_X: the bridge between the puppet's microcontroller (serial frames) and ROS topics."""
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String, UInt8

from robopuppet import codec, settings
from robopuppet.device_settings import DeviceSettings
from robopuppet.serial_link import SerialLink
from robopuppet.teleop import HEARTBEAT_TIMEOUT_S

OPEN_RETRY_S = 0.5  # pause between attempts to open a missing or lost port
WAKE_S = 1.0  # pause between re-opens of a silent device
LOOP_S = 0.05  # period of the node's loop (settings, silence, diagnostics)


class SerialNode:
    """Publish every frame from the puppet as it arrives; send settings, setpoints and opmode.

    At start and after every (re)connect it loads all 84 settings from get_config into the
    device, then sends opmode limp. Until then (e.g. while the config node is down) the device
    runs on firmware defaults, so no joint_states and no joint_J/angle, voltage or enc_stat are
    published. The device mirrors what the config node stored: a joint_J/<setting> message only
    makes the node re-read that joint from get_config and send what differs (see
    robopuppet.device_settings). A missing, vanished
    or silent port is logged once and retried; no byte sequence stops the node.

    Publishes (in <ns> = /puppet/arm_<side>):
        heartbeat (std_msgs/Empty): one per heartbeat frame.
        joint_states (sensor_msgs/JointState): joint_0..joint_6, position = angle rad,
            effort = motor voltage V; one per complete set of seven joint state frames, once
            the settings are loaded after the current (re)connect.
        joint_J/angle, joint_J/voltage (std_msgs/Float32), joint_J/enc_stat (std_msgs/String):
            at most ~joint_topic_rate Hz each, enc_stat also at once when it changes; only once
            the settings are loaded, like joint_states.
        gripper_G (std_msgs/Float32), user_btn (std_msgs/UInt8): at most ~joint_topic_rate Hz
            each; user_btn also at once whenever it changes.
        /diagnostics (diagnostic_msgs/DiagnosticArray): link state at 1 Hz.
    Subscribes:
        opmode (std_msgs/String): 'limp' or 'hold'.
        joint_J/setpoint (std_msgs/Float32): rad, used by the device in hold mode.
        joint_J/<setting> (std_msgs/Float32): the twelve settings of DESIGN section 5. The
            value is not used: the node re-reads joint J from get_config 0.2 s (and 2 s) after
            the last such message and sends the device every value that differs.
    Uses: <ns>/get_config (robopuppet_msgs/GetConfig).
    Parameters:
        ~arm_side (str, required): 'L' or 'R'.
        ~port_name (str, default /dev/ttyACM0): serial device.
        ~baud_rate (int, default 115200).
        ~joint_topic_rate (float, default 100.0 Hz): cap of the per-joint Float32 topics;
            joint_states carries every set.
        ~silence_timeout (float, default 3.0 s): no frame for this long re-opens the port,
            then again every second until frames arrive.
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        self._ns = settings.namespace(side)
        self._port_name = rospy.get_param('~port_name', '/dev/ttyACM0')
        topic_rate_hz = float(rospy.get_param('~joint_topic_rate', 100.0))
        self._silence_timeout_s = float(rospy.get_param('~silence_timeout', 3.0))
        if topic_rate_hz <= 0.0 or self._silence_timeout_s <= 0.0:
            raise ValueError('~joint_topic_rate and ~silence_timeout must be positive')
        self._topic_period_s = 1.0 / topic_rate_hz
        self._name = rospy.get_name()
        self._decoder = codec.Decoder(codec.types_sent_by(codec.TO_HOST))
        self._last_frame_s = self._last_heartbeat_s = None
        self._silent = False
        self._positions = [0.0] * settings.NUM_JOINTS
        self._efforts = [0.0] * settings.NUM_JOINTS
        self._status = [None] * settings.NUM_JOINTS
        self._seen = None  # joints seen of the set in progress; None: wait for the next set
        self._button = None
        self._grippers = [None] * codec.NUM_GRIPPERS
        self._next_topics_s = 0.0
        self._incomplete_sets = 0
        self._link = SerialLink(self._port_name, int(rospy.get_param('~baud_rate', 115200)),
                                self._on_connect, self._on_data, rospy.loginfo, rospy.logwarn,
                                retry_s=OPEN_RETRY_S)
        self._settings = DeviceSettings(self._ns, self._link.write, self._name, self._port_name)
        self._make_publishers()
        self._make_subscribers()

    def _make_publishers(self):
        ns, queue = self._ns, 50
        self._pub_heartbeat = rospy.Publisher(ns + '/heartbeat', Empty, queue_size=queue)
        self._pub_states = rospy.Publisher(ns + '/joint_states', JointState, queue_size=queue)
        self._pub_angle, self._pub_voltage, self._pub_stat = [
            [rospy.Publisher('%s/joint_%d/%s' % (ns, j, topic), kind, queue_size=queue)
             for j in settings.JOINTS]
            for topic, kind in (('angle', Float32), ('voltage', Float32), ('enc_stat', String))]
        self._pub_gripper = [rospy.Publisher('%s/gripper_%d' % (ns, g), Float32, queue_size=queue)
                             for g in range(codec.NUM_GRIPPERS)]
        self._pub_button = rospy.Publisher(ns + '/user_btn', UInt8, queue_size=queue)
        self._pub_diag = rospy.Publisher('/diagnostics', DiagnosticArray, queue_size=10)

    def _make_subscribers(self):
        ns = self._ns
        self._subs = [rospy.Subscriber(ns + '/opmode', String, self._on_opmode, queue_size=10)]
        for joint in settings.JOINTS:
            self._subs.append(rospy.Subscriber('%s/joint_%d/setpoint' % (ns, joint), Float32,
                                               self._on_setpoint, joint, queue_size=10))
            self._subs.extend(
                rospy.Subscriber('%s/joint_%d/%s' % (ns, joint, name), Float32,
                                 lambda _msg, j: self._settings.mark(j), joint, queue_size=100)
                for name in settings.NAMES)

    def run(self):
        """Run the link; load and re-sync settings, watch for silence, publish diagnostics."""
        self._link.start()
        rospy.on_shutdown(self._link.stop)
        frames_before, next_diag_s = 0, time.monotonic()
        while not rospy.is_shutdown():
            self._settings.step(self._link.connected)
            self._check_silence()
            now = time.monotonic()
            if now >= next_diag_s:
                frames = self._decoder.frames
                self._publish_diagnostics(frames - frames_before)
                frames_before, next_diag_s = frames, now + 1.0
            time.sleep(LOOP_S)

    # Device -> ROS (reader thread) ----------------------------------------------------------
    def _on_connect(self):
        self._last_frame_s = time.monotonic()
        # A silent device gets its settings when it talks again.
        self._unload(load=not self._silent)

    def _unload(self, load):
        """Withhold the joint topics until the settings are loaded again."""
        self._settings.unload(load)
        self._seen = None  # then start with the first whole set after loading
        self._status = [None] * settings.NUM_JOINTS  # and publish every enc_stat at once

    def _on_data(self, data):
        for message in self._decoder.feed(data):
            self._last_frame_s = time.monotonic()
            if self._silent:
                rospy.loginfo('%s: frames from %s again; reloading the settings in case the '
                              'device restarted', self._name, self._port_name)
                self._silent = False
                self._unload(load=True)
            kind = type(message)
            if kind is codec.JointState:
                self._on_joint_state(message)
            elif kind is codec.Gripper:
                self._grippers[message.gripper] = message.reading
            elif kind is codec.Buttons:
                self._on_buttons(message.button)
            elif kind is codec.Heartbeat:
                self._last_heartbeat_s = self._last_frame_s
                self._pub_heartbeat.publish(Empty())

    def _on_joint_state(self, message):
        joint = message.joint
        last = joint == settings.NUM_JOINTS - 1
        if not self._settings.loaded:
            return  # firmware defaults (home_angle 0, sign_angle +1): publish nothing
        if self._seen is None:  # the first set since the load starts with joint 0
            if joint != 0:
                if last:
                    self._seen = set()
                return
            self._seen = set()
        self._positions[joint] = message.angle_rad
        self._efforts[joint] = message.voltage_v
        status = settings.ENC_STATUS[message.status]
        if status != self._status[joint]:
            self._status[joint] = status
            self._pub_stat[joint].publish(String(status))
        self._seen.add(joint)
        if not last:
            return
        if len(self._seen) != settings.NUM_JOINTS:
            self._incomplete_sets += 1  # a lost frame: never publish a stale joint as new
            self._seen.clear()
            return
        self._seen.clear()
        msg = JointState(name=settings.JOINT_NAMES, position=list(self._positions),
                         effort=list(self._efforts))
        msg.header.stamp = rospy.Time.now()
        self._pub_states.publish(msg)
        now = time.monotonic()
        if now >= self._next_topics_s:
            # Keep the average at most the cap, absorbing up to one period of arrival jitter.
            self._next_topics_s = max(self._next_topics_s + self._topic_period_s,
                                      now - self._topic_period_s)
            self._publish_joint_topics()

    def _publish_joint_topics(self):
        for joint in settings.JOINTS:
            self._pub_angle[joint].publish(Float32(self._positions[joint]))
            self._pub_voltage[joint].publish(Float32(self._efforts[joint]))
            self._pub_stat[joint].publish(String(self._status[joint]))
        for gripper, reading in enumerate(self._grippers):
            if reading is not None:
                self._pub_gripper[gripper].publish(Float32(reading))
        if self._button is not None:
            self._pub_button.publish(UInt8(self._button))

    def _on_buttons(self, button):
        if button != self._button:
            self._button = button
            self._pub_button.publish(UInt8(button))

    # ROS -> device ---------------------------------------------------------------------------
    def _send(self, messages, what):
        try:
            data = b''.join(codec.encode(m) for m in messages)
        except codec.CodecError as error:
            rospy.logwarn('%s: not sending %s: %s', self._name, what, error)
            return False
        if not self._link.write(data):
            rospy.logwarn_throttle(5.0, '%s: %s not sent: serial port %s is not connected'
                                   % (self._name, what, self._port_name))
            return False
        return True

    def _on_opmode(self, msg):
        if msg.data not in codec.OPMODES:
            rospy.logwarn('%s: opmode must be one of %s, got %r; ignored',
                          self._name, '/'.join(codec.OPMODES), msg.data)
            return
        self._send([codec.Opmode(codec.OPMODES.index(msg.data))], 'opmode ' + msg.data)

    def _on_setpoint(self, msg, joint):
        self._send([codec.JointSetpoint(joint, msg.data)], 'joint %d setpoint' % joint)

    def _check_silence(self):
        """Re-open the port after ~silence_timeout without frames, then every second."""
        last = self._last_frame_s
        if not self._link.connected or last is None:
            return
        quiet_s = time.monotonic() - last
        if quiet_s > (WAKE_S if self._silent else self._silence_timeout_s):
            if not self._silent:
                rospy.logwarn('%s: no frame from %s for %.1f s; re-opening the port every '
                              '%.0f s until it talks', self._name, self._port_name, quiet_s,
                              WAKE_S)
                self._silent = True
            self._last_frame_s = time.monotonic()
            self._link.reopen()

    def _publish_diagnostics(self, frames_per_s):
        now = time.monotonic()
        heartbeat = self._last_heartbeat_s
        since = 'never' if heartbeat is None else '%.1f' % (now - heartbeat)
        if not self._link.connected:
            level, text = DiagnosticStatus.ERROR, 'link down: %s not open' % self._port_name
        elif self._silent:
            level, text = DiagnosticStatus.ERROR, 'device silent'
        elif not self._settings.loaded:
            level, text = (DiagnosticStatus.WARN, 'waiting for settings from get_config; '
                           'joint states withheld')
        elif heartbeat is None or now - heartbeat > HEARTBEAT_TIMEOUT_S:
            level, text = DiagnosticStatus.WARN, 'link up, no heartbeat'
        else:
            level, text = DiagnosticStatus.OK, 'link up'
        dec, link = self._decoder, self._link
        values = (('port', self._port_name), ('link', 'up' if link.connected else 'down'),
                  ('settings loaded', str(self._settings.loaded)),
                  ('frames per s', str(frames_per_s)),
                  ('s since heartbeat', since), ('dropped bytes', str(dec.dropped_bytes)),
                  ('bad checksums', str(dec.bad_checksums)), ('unknown ids', str(dec.unknown_ids)),
                  ('invalid frames', str(dec.invalid_frames)),
                  ('incomplete joint sets', str(self._incomplete_sets)),
                  ('connects', str(link.connects)), ('write errors', str(link.write_errors)))
        status = DiagnosticStatus(level=level, name='%s: puppet serial link' % self._name,
                                  message=text, hardware_id=self._port_name,
                                  values=[KeyValue(k, v) for k, v in values])
        array = DiagnosticArray(status=[status])
        array.header.stamp = rospy.Time.now()
        self._pub_diag.publish(array)


def main():
    """Run the serial node until shutdown."""
    rospy.init_node('serial_interface')
    try:
        node = SerialNode()
    except (KeyError, ValueError) as error:
        rospy.logfatal('serial node cannot start: %s', error)
        raise SystemExit(1)
    node.run()
