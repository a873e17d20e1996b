"""The GUI's ROS side: subscribers that fill an ArmState, publishers, the config node's services.

No Qt here: callbacks run on rospy's threads and only touch the locked ArmState; the GUI thread
reads it once per frame.
"""
import collections
import math
import reprlib
import threading

import rospkg
import rospy
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, Float32MultiArray, String, UInt8

from robopuppet import interface, settings
from robopuppet.calibration import procedure
from robopuppet.episodes import recording
from robopuppet.gui import state
from robopuppet_msgs.msg import ArmSettings, JointChange, LinkState, RecordingState, TeleopState
from robopuppet_msgs.srv import GetConfig, Record, SetArmConfig, SetConfig

# Incoming messages each subscriber keeps when its callback falls behind (older ones are
# dropped); /diagnostics carries every node's statuses, so it keeps more.
QUEUE_SIZE = 10
DIAGNOSTICS_QUEUE_SIZE = 100
# /robot/joint_states comes from the robot host at ~100 Hz across the operator-robot link; the
# GUI shows only the newest, so a late sample is dropped rather than queued.
ROBOT_QUEUE_SIZE = 1


SetAnswer = collections.namedtuple('SetAnswer', 'stored error values')
SetAnswer.__doc__ = """The config node's answer to set_config: stored (bool), error (why not, or
'') and values, the joint's {name: value} stored now (set_arm_config's: {joint: {name: value}}
of all seven joints)."""


class ConfigUnavailable(RuntimeError):
    """get_config, set_config or set_arm_config did not answer (config node not running, or the
    call failed)."""


RecordAnswer = collections.namedtuple('RecordAnswer', 'ok error episode')
RecordAnswer.__doc__ = """The recorder's answer to /puppet/record: ok (bool), error (why not, or
''), episode (the episode's bag file)."""


def is_link_status(status, ns):
    """Return True when a diagnostic_msgs/DiagnosticStatus is the serial link of the arm at ns.

    Each per-arm status has hardware_id == interface.puppet_ns(side); the serial link's name
    ends with interface.DIAG_LINK, whatever the serial node is called.
    """
    return status.hardware_id == ns and status.name.endswith(interface.DIAG_LINK)


class PuppetClient:
    """Connect an ArmState to one puppet arm's topics and services.

    Subscribes (under <ns> = /puppet/arm_<side>): heartbeat, opmode, teleop_state, user_btn,
        gripper_G, joint_J/{enc_stat,angle,voltage,setpoint}, stored_settings (kept for
        stored_settings()); and /diagnostics, keeping the serial link's status of this arm
        (is_link_status).
    Publishes: <ns>/opmode (std_msgs/String), <ns>/joint_J/setpoint (std_msgs/Float32),
        <ns>/calibration_target (sensor_msgs/JointState, procedure.TARGET_TOPIC).
    Calls: <ns>/get_config (robopuppet_msgs/GetConfig), <ns>/set_config
        (robopuppet_msgs/SetConfig), <ns>/set_arm_config (robopuppet_msgs/SetArmConfig).
    Recording: subscribes /puppet/recording (robopuppet_msgs/RecordingState, kept for
        recording_status()) and calls /puppet/record (robopuppet_msgs/Record).
    Replay: publishes interface.REPLAY_STOP (std_msgs/Empty) on stop_replay().
    Link to the robot room: subscribes <ns>/link_state (robopuppet_msgs/LinkState from arm_X,
        kept in the ArmState as a state.RobotLink with its receive time).
    Baxter: subscribes /robot/joint_states (sensor_msgs/JointState, queue 1: only the newest
        sample is kept) for the tracking error the main tab shows.
    """

    def __init__(self, side, arm_state, clock=rospy.get_time):
        self.side = side
        self.ns = interface.puppet_ns(side)
        self.state = arm_state
        self._clock = clock
        self._stored_lock = threading.Lock()
        self._stored = None

        def topic(name):
            return '%s/%s' % (self.ns, name)

        def sub(name, kind, callback, queue_size=QUEUE_SIZE, **kwargs):
            return rospy.Subscriber(name, kind, callback, queue_size=queue_size, **kwargs)

        self._subscribers = [
            sub(topic(interface.HEARTBEAT), Empty, lambda _: arm_state.on_heartbeat(clock())),
            sub(topic(interface.OPMODE), String, self._on_opmode),
            sub(topic(interface.TELEOP_STATE), TeleopState, self._on_teleop),
            sub(topic(interface.USER_BUTTON), UInt8, lambda msg: arm_state.on_button(msg.data)),
            sub(interface.DIAGNOSTICS, DiagnosticArray, self._on_diagnostics,
                queue_size=DIAGNOSTICS_QUEUE_SIZE),
            sub(topic(interface.STORED_SETTINGS), ArmSettings, self._on_stored, queue_size=1),
            sub(recording.RECORDING_TOPIC, RecordingState, self._on_recording, queue_size=1),
            sub(topic(interface.LINK_STATE), LinkState, self._on_link_state, queue_size=1),
            sub(interface.ROBOT_JOINT_STATES, JointState, self._on_robot_joints,
                queue_size=ROBOT_QUEUE_SIZE),
        ]
        for gripper in range(interface.NUM_GRIPPERS):
            self._subscribers.append(sub(interface.gripper_topic(side, gripper), Float32,
                                         self._on_gripper, callback_args=gripper))
        for joint in settings.JOINTS:
            self._subscribers += [
                sub(interface.joint_topic(side, joint, name), kind, callback, callback_args=joint)
                for name, kind, callback in (('enc_stat', String, self._on_status),
                                             ('angle', Float32, self._on_angle),
                                             ('voltage', Float32, self._on_voltage),
                                             ('setpoint', Float32, self._on_setpoint))]
        self._opmode_pub = rospy.Publisher(topic(interface.OPMODE), String, queue_size=1)
        self._setpoint_pubs = [rospy.Publisher(interface.joint_topic(side, joint, 'setpoint'),
                                               Float32, queue_size=1)
                               for joint in settings.JOINTS]
        self._target_pub = rospy.Publisher(topic(procedure.TARGET_TOPIC), JointState,
                                           queue_size=1)
        self._get_config = rospy.ServiceProxy(topic(interface.GET_CONFIG), GetConfig)
        self._set_config = rospy.ServiceProxy(topic(interface.SET_CONFIG), SetConfig)
        self._set_arm_config = rospy.ServiceProxy(topic(interface.SET_ARM_CONFIG), SetArmConfig)
        self._record = rospy.ServiceProxy(recording.RECORD_SERVICE, Record)
        self._replay_stop_pub = rospy.Publisher(interface.REPLAY_STOP, Empty, queue_size=1)
        self._recording = None

    def now(self):
        """Return the current ROS time in s (the time base of the ArmState)."""
        return self._clock()

    def set_opmode(self, opmode):
        """Publish the opmode: limp, hold or feel.

        Hold and feel first send each joint's current angle as its setpoint: the firmware holds
        the setpoints it has (0 rad after limp), so a bare hold would drive the puppet to 0 rad
        (in feel, arm_X then streams Baxter's pose as setpoints).
        """
        if opmode not in interface.OPMODES:
            raise ValueError('opmode must be one of %s, got %s' % (interface.OPMODES,
                                                                   reprlib.repr(opmode)))
        if opmode in (interface.HOLD, interface.FEEL):
            for joint, values in enumerate(self.state.snapshot().joints):
                if math.isfinite(values.angle_rad):
                    self.set_setpoint(joint, values.angle_rad)
        self._opmode_pub.publish(String(opmode))

    def set_setpoint(self, joint, angle_rad):
        """Publish a joint's setpoint (rad; used by the puppet in hold mode)."""
        self._setpoint_pubs[joint].publish(Float32(angle_rad))

    def publish_target(self, pose):
        """Publish a procedure.Pose as the calibration target (Baxter's names and rad)."""
        names, positions = procedure.target_state(self.side, pose)
        self._target_pub.publish(JointState(name=names, position=positions,
                                            header=rospy.Header(stamp=rospy.Time.now())))

    def get_config(self, joint, timeout_s=1.0):
        """Return the stored {name: value} of a joint. Blocks: call it off the GUI thread.

        Only finding the service is bounded (timeout_s); a config node that accepts the call and
        never answers blocks the caller, so the GUI gives up on its own deadline (JointTab).

        Raises:
            ConfigUnavailable: the service is not there within timeout_s or the call failed.
        """
        response = self._call(self._get_config, interface.GET_CONFIG, timeout_s, joint)
        return {name: getattr(response, name) for name in settings.NAMES}

    def set_config(self, joint, values, timeout_s=1.0):
        """Ask the config node to store {name: value} of a joint, all or none; return a SetAnswer.

        Blocks like get_config: call it off the GUI thread.

        Raises:
            ConfigUnavailable: the service is not there within timeout_s or the call failed.
        """
        names = list(values)
        response = self._call(self._set_config, interface.SET_CONFIG, timeout_s, joint, names,
                              [values[name] for name in names])
        return SetAnswer(response.stored, response.error,
                         {name: getattr(response.settings, name) for name in settings.NAMES})

    def set_arm_config(self, values, timeout_s=1.0):
        """Ask the config node to store {joint: {name: value}} in one request, all or none (a
        calibration); return a SetAnswer. Blocks like get_config: call it off the GUI thread.

        Raises:
            ConfigUnavailable: the service is not there within timeout_s or the call failed.
        """
        response = self._call(self._set_arm_config, interface.SET_ARM_CONFIG, timeout_s,
                              [JointChange(joint, list(v), list(v.values()))
                               for joint, v in values.items()])
        return SetAnswer(response.stored, response.error, {
            j.joint: {name: getattr(j, name) for name in settings.NAMES}
            for j in response.settings.joints})

    def stored_settings(self):
        """Return config_X's latest stored_settings as {joint: {name: value}}, or None."""
        with self._stored_lock:
            return self._stored

    def record(self, start, notes='', timeout_s=1.0):
        """Ask the recorder to start (start True) or stop an episode; return a RecordAnswer.

        Blocks like get_config: call it off the GUI thread.

        Raises:
            ConfigUnavailable: the recorder is not there within timeout_s or the call failed.
        """
        try:
            self._record.wait_for_service(timeout_s)
            response = self._record(start, notes)
        except (rospy.ROSException, rospy.ServiceException) as error:
            raise ConfigUnavailable('%s: %s' % (recording.RECORD_SERVICE, error)) from None
        return RecordAnswer(response.ok, response.error, response.episode)

    def stop_replay(self):
        """Ask a running replay to stop (std_msgs/Empty on interface.REPLAY_STOP)."""
        self._replay_stop_pub.publish(Empty())

    @staticmethod
    def episodes_dir():
        """Return the recorder's default episodes directory ($ROS_HOME/robopuppet/episodes)."""
        return recording.episodes_dir(rospkg.get_ros_home())

    def recording_status(self):
        """Return the recorder's latest recording.Status, or None before the first."""
        with self._stored_lock:
            return self._recording

    def _on_recording(self, msg):
        status = recording.Status(msg.recording, msg.episode, msg.duration_s, msg.size_bytes,
                                  msg.messages, msg.problem)
        with self._stored_lock:
            self._recording = status

    def _on_stored(self, msg):
        stored = {j.joint: {name: getattr(j, name) for name in settings.NAMES}
                  for j in msg.joints}
        with self._stored_lock:
            self._stored = stored

    def _call(self, proxy, service, timeout_s, *args):
        try:
            proxy.wait_for_service(timeout_s)
            return proxy(*args)
        except (rospy.ROSException, rospy.ServiceException) as error:
            raise ConfigUnavailable('%s/%s: %s' % (self.ns, service, error)) from None

    def _on_opmode(self, msg):
        try:
            self.state.on_opmode(msg.data, self._clock())
        except ValueError as error:
            rospy.logwarn_throttle(10, '%s/opmode ignored: %s', self.ns, error)

    def _on_link_state(self, msg):
        self.state.on_robot_link(state.RobotLink(
            msg.rtt, msg.sample_age, msg.max_sample_age, msg.clock_known, msg.loss, msg.level,
            msg.fault, msg.detail, self._clock()))

    def _on_teleop(self, msg):
        self.state.on_teleop(state.Teleop(msg.state, msg.follow_left, msg.follow_right,
                                          msg.opmode, msg.heartbeat_age, msg.detail,
                                          msg.zone_left, msg.zone_right, self._clock()))

    def _on_robot_joints(self, msg):
        self.state.on_robot_joints(msg.name, msg.position, self._clock())

    def _on_diagnostics(self, msg):
        for status in msg.status:
            if is_link_status(status, self.ns):
                self.state.on_link(state.Link(
                    status.level, status.name, status.message,
                    tuple((kv.key, kv.value) for kv in status.values), self._clock()))

    def _on_gripper(self, msg, gripper):
        self.state.on_gripper(gripper, msg.data)

    def _on_status(self, msg, joint):
        self.state.on_status(joint, msg.data)

    def _on_angle(self, msg, joint):
        self.state.on_angle(joint, msg.data, self._clock())

    def _on_voltage(self, msg, joint):
        self.state.on_voltage(joint, msg.data, self._clock())

    def _on_setpoint(self, msg, joint):
        self.state.on_setpoint(joint, msg.data, self._clock())


class SimPuppetClient:
    """Operate the simulated puppet: move its hand, hold its buttons.

    Publishes (latched, under /puppet_sim/arm_<side>): hand (sensor_msgs/JointState, joint_0..6
        in rad), button (std_msgs/UInt8, the button held down, 0 none), grippers
        (std_msgs/Float32MultiArray, four readings 0-1; reading 3 is the end-piece button,
        1 released, 0 pressed).
    """

    def __init__(self, side):
        self.ns = interface.sim_ns(side)
        self._hand_pub = rospy.Publisher('%s/%s' % (self.ns, interface.SIM_HAND), JointState,
                                         queue_size=1, latch=True)
        self._button_pub = rospy.Publisher('%s/%s' % (self.ns, interface.SIM_BUTTON), UInt8,
                                           queue_size=4, latch=True)
        self._grippers_pub = rospy.Publisher('%s/%s' % (self.ns, interface.SIM_GRIPPERS),
                                             Float32MultiArray, queue_size=4, latch=True)

    def connected(self):
        """Return True when a simulated puppet listens to the hand, button and grippers."""
        return all(p.get_num_connections() > 0
                   for p in (self._hand_pub, self._button_pub, self._grippers_pub))

    def set_hand(self, angles_rad):
        """Publish the seven hand angles (rad)."""
        msg = JointState(name=list(settings.JOINT_NAMES), position=[float(a) for a in angles_rad])
        msg.header.stamp = rospy.Time.now()
        self._hand_pub.publish(msg)

    def set_button(self, button):
        """Publish the button held down (1-4, 0 none)."""
        self._button_pub.publish(UInt8(button))

    def set_grippers(self, readings):
        """Publish the four gripper readings (0-1)."""
        self._grippers_pub.publish(Float32MultiArray(data=[float(r) for r in readings]))
