"""serial_X: the bridge between the puppet's microcontroller (serial frames) and ROS topics."""
import threading
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String, UInt8

from robopuppet import interface, settings
from robopuppet.interface import HEARTBEAT_TIMEOUT_S
from robopuppet.periodic import Guard, Loop
from robopuppet.protocol import codec, device_commands, device_settings, state_set
from robopuppet.protocol.device_settings import DeviceSettings
from robopuppet.protocol.serial_link import SerialLink

OPEN_RETRY_S = 0.5  # pause between attempts to open a missing or lost port
WAKE_S = 1.0  # pause between re-opens of a silent device
LOOP_S = 0.05  # period of the node's loops (settings; silence and diagnostics)
SETTINGS_STALL_S = 3.0 * device_settings.CALL_TIMEOUT_S  # the settings loop hangs: say so
RATE_WARN_S = 30.0  # a state rate that disagrees with ~comm_rate is logged this often


class SerialNode:
    """Publish every frame from the puppet as it arrives; send settings, setpoints and opmode.

    At start and after every (re)connect it loads all 84 settings from get_config into the
    device, then sends opmode limp. Until then (e.g. while the config node is down) the device
    runs on firmware defaults, so no joint_states and no joint_J/angle, voltage or enc_stat are
    published. get_config runs off the node's loops with a timeout (robopuppet.protocol.device_settings):
    a hung config node delays only the settings and shows in /diagnostics as unreachable. The
    device mirrors what the config node stored: a joint_J/<setting> message only makes the node
    re-read that joint from get_config and send what differs (see robopuppet.protocol.device_settings).
    A missing, vanished or silent port is logged once and retried; no byte sequence stops the
    node.

    Publishes (in <ns> = /puppet/arm_<side>):
        heartbeat (std_msgs/Empty): one per heartbeat frame on a healthy line, and only
            whole, plausible state sets are published (robopuppet.protocol.state_set).
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
        opmode (std_msgs/String): 'limp' or 'hold'. The firmware holds the setpoints it has
            (0 rad after power-on or limp), so a hold without seven setpoints since the last
            limp/connect first sends the current angles as the missing setpoints, in the same
            write; with no current angles yet (settings not loaded, no joint state) the hold
            is refused with a warning.
        joint_J/setpoint (std_msgs/Float32): rad, used by the device in hold mode; sent as
            it comes, also after a hold.
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
        ~comm_rate (float, default 0: no check): the state-set rate the firmware sends, a
            compile-time constant (10 Hz in 2020) that this parameter does not change; when
            the measured rate differs from it by more than 20 % the node warns (log, at most
            every 30 s, and /diagnostics).
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        self._ns = interface.puppet_ns(side)
        self._port_name = rospy.get_param('~port_name', '/dev/ttyACM0')
        topic_rate_hz = float(rospy.get_param('~joint_topic_rate', 100.0))
        self._silence_timeout_s = float(rospy.get_param('~silence_timeout', 3.0))
        if topic_rate_hz <= 0.0 or self._silence_timeout_s <= 0.0:
            raise ValueError('~joint_topic_rate and ~silence_timeout must be positive')
        self._comm_rate_hz = float(rospy.get_param('~comm_rate', 0.0))
        if not self._comm_rate_hz >= 0.0:
            raise ValueError('~comm_rate must be positive (or 0: no check)')
        self._topic_period_s = 1.0 / topic_rate_hz
        self._name = rospy.get_name()
        self._decoder = codec.Decoder(codec.types_sent_by(codec.TO_HOST))
        self._last_frame_s = self._last_heartbeat_s = None
        self._silent = False
        self._positions = [0.0] * settings.NUM_JOINTS
        self._efforts = [0.0] * settings.NUM_JOINTS
        self._status = [None] * settings.NUM_JOINTS
        self._seen = None  # publish joints of sets begun from this time; None: not loaded
        self._button = None
        self._grippers = [None] * interface.NUM_GRIPPERS
        self._next_topics_s = 0.0
        self._receiver = state_set.Receiver(self._voltage_limits, self._decoder)
        self._link = SerialLink(self._port_name, int(rospy.get_param('~baud_rate', 115200)),
                                self._on_connect, self._on_data, rospy.loginfo, rospy.logwarn,
                                retry_s=OPEN_RETRY_S)
        self._settings = DeviceSettings(self._ns, self._link.write, self._name, self._port_name)
        self._guard = Guard(self._name, rospy.logerr)
        self._loops = []
        self._host_lock = threading.Lock()  # _hold and _rate, with the writes they are about
        self._hold = device_commands.HoldGate()
        self._rate = device_commands.RateMeter()
        self._rate_epoch = None
        self._errors_reported = 0
        self._next_diag_s, self._frames_before = 0.0, 0
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
                             for g in range(interface.NUM_GRIPPERS)]
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
        """Run the link and two guarded loops until shutdown: one loads and re-syncs the
        settings (it may wait for get_config), the other watches for silence and publishes
        /diagnostics, so a hung config node cannot stop the diagnostics."""
        self._link.start()
        self._loops = [
            Loop(self._guard, 'settings loop', LOOP_S,
                 lambda: self._settings.step(self._link.connected)).start(),
            Loop(self._guard, 'watch loop', LOOP_S, self._watch).start()]
        rospy.on_shutdown(self._stop)
        rospy.spin()

    def _stop(self):
        for loop in self._loops:
            loop.stop()
        self._link.stop()

    def _watch(self):
        self._check_silence()
        now = time.monotonic()
        if now >= self._next_diag_s:
            frames = self._decoder.frames
            self._publish_diagnostics(frames - self._frames_before)
            self._frames_before, self._next_diag_s = frames, now + 1.0

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
        now = time.monotonic()
        receiver, decoder = self._receiver, self._decoder
        refused = receiver.implausible_frames + decoder.invalid_frames
        events = receiver.feed(data, now)
        if receiver.implausible_frames + decoder.invalid_frames != refused:
            rospy.logwarn_throttle(10.0, '%s: dropped an implausible frame from %s (%d so far): '
                                   '%s' % (self._name, self._port_name, refused + 1,
                                           receiver.last_problem))
        if not events:
            return
        self._last_frame_s = now  # only whole sets and healthy heartbeats: noise is not life
        if self._silent:
            rospy.loginfo('%s: frames from %s again; reloading the settings in case the '
                          'device restarted', self._name, self._port_name)
            self._silent = False
            self._unload(load=True)
        if not self._settings.loaded:
            self._seen = None
        elif self._seen is None:
            self._seen = now  # loaded since the last chunk: publish sets that begin now
        for event in events:
            if type(event) is codec.Heartbeat:
                self._last_heartbeat_s = now
                self._pub_heartbeat.publish(Empty())
            else:
                self._on_state_set(event, now)

    def _voltage_limits(self, joint):
        """Return the (min, max) motor voltage in V that the device holds for a joint."""
        held = self._settings.held(joint)
        return held['voltage_min'], held['voltage_max']

    def _on_state_set(self, state, now):
        """Publish a whole, plausible state set (a state_set.StateSet) received at now."""
        # Joints only once the settings are loaded, from the first set begun after the load:
        # before it the device runs on firmware defaults (home_angle 0, sign_angle +1).
        joints = self._seen is not None and state.start_s >= self._seen
        if joints:
            for message in state.joints:
                joint = message.joint
                self._positions[joint] = message.angle_rad
                self._efforts[joint] = message.voltage_v
                status = interface.ENC_STATUS[message.status]
                if status != self._status[joint]:
                    self._status[joint] = status
                    self._pub_stat[joint].publish(String(status))
            msg = JointState(name=settings.JOINT_NAMES, position=list(self._positions),
                             effort=list(self._efforts))
            msg.header.stamp = rospy.Time.now()
            self._pub_states.publish(msg)
            # The hold gets its current angles and the rate check its count.
            self._guard.call('hold and rate bookkeeping', self._on_states_published, msg)
        self._grippers = list(state.grippers)
        self._on_buttons(state.button)
        if now >= self._next_topics_s:
            # Keep the average at most the cap, absorbing up to one period of arrival jitter.
            self._next_topics_s = max(self._next_topics_s + self._topic_period_s,
                                      now - self._topic_period_s)
            self._publish_joint_topics(joints)

    def _publish_joint_topics(self, joints):
        if joints:
            for joint in settings.JOINTS:
                self._pub_angle[joint].publish(Float32(self._positions[joint]))
                self._pub_voltage[joint].publish(Float32(self._efforts[joint]))
                self._pub_stat[joint].publish(String(self._status[joint]))
        for gripper, reading in enumerate(self._grippers):
            self._pub_gripper[gripper].publish(Float32(reading))
        if self._button is not None:
            self._pub_button.publish(UInt8(self._button))

    def _on_buttons(self, button):
        if button != self._button:
            self._button = button
            self._pub_button.publish(UInt8(button))

    # ROS -> device ---------------------------------------------------------------------------
    def _send(self, messages, what):
        """Send messages in whole-frame writes of <= 64 bytes; return True if all went out.

        Call with _host_lock held: the hold gate records what went out under the same lock.
        """
        epoch = self._settings.epoch  # before the write: see device_commands.HoldGate
        try:
            writes = device_commands.pack([codec.encode(m) for m in messages])
        except codec.CodecError as error:
            rospy.logwarn('%s: not sending %s: %s', self._name, what, error)
            return False
        if not all(self._link.write(data) for data in writes):
            rospy.logwarn_throttle(5.0, '%s: %s not sent: serial port %s is not connected'
                                   % (self._name, what, self._port_name))
            return False
        self._hold.record(messages, epoch)
        return True

    def _on_opmode(self, msg):
        if msg.data not in interface.OPMODES:
            rospy.logwarn('%s: opmode must be one of %s, got %r; ignored',
                          self._name, '/'.join(interface.OPMODES), msg.data)
            return
        with self._host_lock:
            if msg.data != 'hold':
                self._send([codec.Opmode(interface.OPMODES.index(msg.data))], 'opmode ' + msg.data)
                return
            plan = self._hold.plan_hold(self._settings.epoch)
            if plan.refusal:
                rospy.logwarn('%s: hold refused: %s; send joint_J/setpoint for every joint '
                              'first, or wait for the joint states', self._name, plan.refusal)
                return
            filled = [m.joint for m in plan.messages if isinstance(m, codec.JointSetpoint)]
            if filled:
                rospy.loginfo('%s: hold: joints %s had no setpoint since the last limp or '
                              'connect; their current angles go first', self._name, filled)
            self._send(plan.messages, 'opmode hold')

    def _on_setpoint(self, msg, joint):
        with self._host_lock:
            self._send([codec.JointSetpoint(joint, msg.data)], 'joint %d setpoint' % joint)

    def _on_states_published(self, msg):
        now, epoch = time.monotonic(), self._settings.epoch
        with self._host_lock:
            self._hold.on_angles(msg.position, epoch)
            if epoch != self._rate_epoch:  # a new load: measure from here
                self._rate.restart(now)
                self._rate_epoch = epoch
            self._rate.add(now)

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

    def _level_and_text(self, now, heartbeat, rate_hz):
        """Return the /diagnostics level and message: the worst problem first."""
        config = self._settings
        unreachable = config.config_status == device_settings.UNREACHABLE
        why = ('config node unreachable (%s)' % config.config_problem if unreachable
               else 'config node %s' % config.config_status)
        settings_run = self._loops[0].last_run_s if self._loops else None
        errors = self._guard.errors + self._link.callback_errors
        new_errors, self._errors_reported = errors - self._errors_reported, errors
        rate = device_commands.rate_problem(rate_hz, self._comm_rate_hz)
        if rate:
            rospy.logwarn_throttle(RATE_WARN_S, '%s: %s' % (self._name, rate))
        if not self._link.connected:
            return DiagnosticStatus.ERROR, 'link down: %s not open' % self._port_name
        if self._silent:
            return DiagnosticStatus.ERROR, 'device silent'
        if settings_run is not None and now - settings_run > SETTINGS_STALL_S:
            return DiagnosticStatus.ERROR, ('settings loop stalled for %.0f s; %s'
                                            % (now - settings_run, why))
        if not config.loaded:
            return (DiagnosticStatus.ERROR if unreachable else DiagnosticStatus.WARN,
                    'waiting for settings from get_config (%s); joint states withheld' % why)
        if heartbeat is None or now - heartbeat > HEARTBEAT_TIMEOUT_S:
            return DiagnosticStatus.WARN, 'link up, no heartbeat'
        if unreachable:
            return DiagnosticStatus.WARN, ('link up; %s: setting changes do not reach the '
                                           'puppet' % why)
        if rate:
            return DiagnosticStatus.WARN, 'link up; ' + rate
        if new_errors:
            return DiagnosticStatus.WARN, ('link up; %d callback errors survived in the last '
                                           'second: %s' % (new_errors, self._guard.last_error))
        return DiagnosticStatus.OK, 'link up'

    def _publish_diagnostics(self, frames_per_s):
        now = time.monotonic()
        heartbeat = self._last_heartbeat_s
        since = 'never' if heartbeat is None else '%.1f' % (now - heartbeat)
        with self._host_lock:
            rate_hz = self._rate.rate_hz(now)
        level, text = self._level_and_text(now, heartbeat, rate_hz)
        config = self._settings
        config_text = config.config_status + (
            ' (%d calls stuck)' % config.stuck_calls if config.stuck_calls else '')
        dec, link = self._decoder, self._link
        values = (('port', self._port_name), ('link', 'up' if link.connected else 'down'),
                  ('settings loaded', str(self._settings.loaded)),
                  ('frames per s', str(frames_per_s)),
                  ('s since heartbeat', since), ('dropped bytes', str(dec.dropped_bytes)),
                  ('bad checksums', str(dec.bad_checksums)), ('unknown ids', str(dec.unknown_ids)),
                  ('invalid frames', str(dec.invalid_frames)),
                  ('incomplete joint sets', str(self._receiver.dropped_sets)),
                  ('stray frames', str(self._receiver.stray_frames)),
                  ('implausible frames', str(self._receiver.implausible_frames)),
                  ('refused heartbeats', str(self._receiver.refused_heartbeats)),
                  ('connects', str(link.connects)), ('write errors', str(link.write_errors)),
                  ('config node', config_text),
                  ('state sets per s', 'measuring' if rate_hz is None else '%.1f' % rate_hz),
                  ('comm_rate', '%.1f' % self._comm_rate_hz if self._comm_rate_hz else 'unset'),
                  ('callback errors', str(self._guard.errors + link.callback_errors)))
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
