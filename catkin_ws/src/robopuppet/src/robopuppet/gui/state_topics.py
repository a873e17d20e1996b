"""The GUI's subscriptions: one puppet arm's state topics (and Baxter's, the recorder's) into an
ArmState.

No Qt here: callbacks run on rospy's threads and only touch the locked ArmState (or this
object's own lock); the GUI thread reads them once per frame.
"""
import threading

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String, UInt8

from robopuppet import interface, settings
from robopuppet.episodes import recording
from robopuppet.gui import state
from robopuppet_msgs.msg import ArmSettings, LinkState, RecordingState, TeleopState

# Incoming messages each subscriber keeps when its callback falls behind (older ones are
# dropped); /diagnostics carries every node's statuses, so it keeps more.
QUEUE_SIZE = 10
DIAGNOSTICS_QUEUE_SIZE = 100
# /robot/joint_states comes from the robot host at ~100 Hz across the operator-robot link; the
# GUI shows only the newest, so a late sample is dropped rather than queued.
ROBOT_QUEUE_SIZE = 1


def is_link_status(status, ns):
    """Return True when a diagnostic_msgs/DiagnosticStatus is the serial link of the arm at ns.

    Each per-arm status has hardware_id == interface.puppet_ns(side); the serial link's name
    ends with interface.DIAG_LINK, whatever the serial node is called.
    """
    return status.hardware_id == ns and status.name.endswith(interface.DIAG_LINK)


class StateTopics:
    """Fill an ArmState from one puppet arm's topics; keep its stored settings and the recording.

    Subscribes (under <ns> = /puppet/arm_<side>): heartbeat, opmode, teleop_state, user_btn,
        gripper_G, joint_J/{enc_stat,angle,voltage,setpoint}, stored_settings (kept for
        stored_settings()); /diagnostics, keeping the serial link's status of this arm
        (is_link_status); /puppet/recording (robopuppet_msgs/RecordingState, kept for
        recording_status()); <ns>/link_state (robopuppet_msgs/LinkState from arm_X, kept as a
        state.RobotLink with its receive time); /robot/joint_states (sensor_msgs/JointState,
        queue 1: only the newest sample is kept) for the tracking error the main tab shows.
    """

    def __init__(self, side, arm_state, clock):
        self.ns = interface.puppet_ns(side)
        self.state = arm_state
        self._clock = clock
        self._lock = threading.Lock()  # _stored and _recording
        self._stored = self._recording = None

        def sub(name, kind, callback, queue_size=QUEUE_SIZE, **kwargs):
            return rospy.Subscriber(name, kind, callback, queue_size=queue_size, **kwargs)

        def own(name):
            return '%s/%s' % (self.ns, name)

        self._subscribers = [
            sub(own(interface.HEARTBEAT), Empty, lambda _: arm_state.on_heartbeat(clock())),
            sub(own(interface.OPMODE), String, self._on_opmode),
            sub(own(interface.TELEOP_STATE), TeleopState, self._on_teleop),
            sub(own(interface.USER_BUTTON), UInt8, lambda msg: arm_state.on_button(msg.data)),
            sub(interface.DIAGNOSTICS, DiagnosticArray, self._on_diagnostics,
                queue_size=DIAGNOSTICS_QUEUE_SIZE),
            sub(own(interface.STORED_SETTINGS), ArmSettings, self._on_stored, queue_size=1),
            sub(interface.RECORDING_TOPIC, RecordingState, self._on_recording, queue_size=1),
            sub(own(interface.LINK_STATE), LinkState, self._on_link_state, queue_size=1),
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

    def stored_settings(self):
        """Return config_X's latest stored_settings as {joint: {name: value}}, or None."""
        with self._lock:
            return self._stored

    def recording_status(self):
        """Return the recorder's latest recording.Status, or None before the first."""
        with self._lock:
            return self._recording

    def _on_recording(self, msg):
        status = recording.Status(msg.recording, msg.episode, msg.duration_s, msg.size_bytes,
                                  msg.messages, msg.problem)
        with self._lock:
            self._recording = status

    def _on_stored(self, msg):
        stored = {j.joint: {name: getattr(j, name) for name in settings.NAMES}
                  for j in msg.joints}
        with self._lock:
            self._stored = stored

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
