"""The ROS side of playback into the puppet (`replay EPISODE --into puppet`): feeds
robopuppet.episodes.puppet_playback what the puppet reports and sends its setpoints.

Used by robopuppet.episodes.replay_node (the terminal command replay), which reads the episode
and builds the core.
"""
import time

import rosgraph
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Empty, Float32, String, UInt8

from robopuppet import interface as ifc
from robopuppet import settings
from robopuppet.arm.readings import joint_angles
from robopuppet.episodes import replay
from robopuppet.episodes.player import Player
from robopuppet_msgs.msg import ArmSettings

RATE_HZ = 50.0        # setpoints per second and joint: the firmware's control rate
WAIT_S = 5.0          # for the puppet's joint states and encoder statuses before refusing
SETTINGS_WAIT_S = 1.0  # then this much longer for the latched stored settings


class PuppetPlayer(Player):
    """Play one episode into the puppet arms of the core's paths; run() returns the exit code.

    Subscribes per played side X (<ns> = /puppet/arm_X): <ns>/joint_states (position: the
    angles rad, effort: the motor voltages V, which the tracking watch reads),
    <ns>/joint_J/enc_stat, <ns>/user_btn, <ns>/opmode (another node's limp ends the playback),
    <ns>/stored_settings (robopuppet_msgs/ArmSettings, latched: the angle, speed and voltage
    limits); interface.REPLAY_STOP (std_msgs/Empty).
    Publishes per side: <ns>/joint_J/setpoint (std_msgs/Float32, rad, RATE_HZ) and <ns>/opmode
    (std_msgs/String: hold at the start, after seven setpoints; limp when the side does not
    follow, robopuppet.episodes.tracking_watch).
    """

    def __init__(self, core, say):
        super().__init__(core, say)
        sub, sides = rospy.Subscriber, sorted(core.paths)
        self._setpoints = {s: [rospy.Publisher(ifc.joint_topic(s, j, 'setpoint'), Float32,
                                               queue_size=10, tcp_nodelay=True)
                               for j in settings.JOINTS] for s in sides}
        self._opmode = {s: rospy.Publisher(ifc.puppet_ns(s) + '/' + ifc.OPMODE, String,
                                           queue_size=10) for s in sides}
        for s in sides:
            ns = ifc.puppet_ns(s) + '/'
            sub(ns + ifc.JOINT_STATES, JointState, self._on_states, s, 10, tcp_nodelay=True)
            for j in settings.JOINTS:
                sub(ifc.joint_topic(s, j, 'enc_stat'), String,
                    lambda m, a: self._call(self.core.on_status, *a, m.data), (s, j), 10)
            sub(ns + ifc.USER_BUTTON, UInt8,
                lambda m, s: self._call(self.core.on_button, s, m.data), s, 10)
            sub(ns + ifc.OPMODE, String, self._on_opmode, s, 10)
            sub(ns + ifc.STORED_SETTINGS, ArmSettings, lambda m, s: self._call(
                self.core.on_settings, s, {j.joint: {n: getattr(j, n) for n in settings.NAMES}
                                           for j in m.joints}), s, 1)
        sub(ifc.REPLAY_STOP, Empty, lambda m: self._call(self.core.stop, 'stop requested'),
            queue_size=10)

    def _on_states(self, msg, side):
        try:
            angles = joint_angles(msg.name, msg.position)
        except ValueError:
            return  # not the puppet's seven joints: no reading of where it is
        try:
            voltages = joint_angles(msg.name, msg.effort)  # matched by name as the angles
        except ValueError:
            voltages = None  # no motor voltages: the tracking watch cannot see saturation
        self._call(self.core.on_puppet, side, angles, voltages)

    def _on_opmode(self, msg, side):
        sender = msg._connection_header.get('callerid', '?')
        if sender != rospy.get_name():  # our own hold comes back too
            self._call(self.core.on_opmode, side, msg.data, sender)

    def _send(self, step):
        for side, angles in step.setpoints.items():
            for publisher, angle in zip(self._setpoints[side], angles):
                publisher.publish(Float32(angle))
        for side, mode in step.opmodes.items():
            self._opmode[side].publish(String(mode))

    def _wait(self, ready, timeout_s):
        deadline = time.monotonic() + timeout_s
        while not ready() and time.monotonic() < deadline and not rospy.is_shutdown():
            time.sleep(0.05)

    def _connected(self):
        """Return True when every publisher reaches every subscriber the master knows of."""
        try:
            subscribers = dict(rosgraph.Master(rospy.get_name()).getSystemState()[1])
        except (OSError, rosgraph.MasterException):
            return False  # the master is not reachable: try again
        publishers = [p for pubs in self._setpoints.values() for p in pubs]
        return all(p.get_num_connections() >= len(subscribers.get(p.resolved_name, ()))
                   for p in publishers + list(self._opmode.values()))

    def run(self):
        """Check, hold, approach, play; return the exit code (0 finished, 1 stopped, 2 refused)."""
        core = self.core
        self._wait(lambda: not self._call(core.refusal), WAIT_S)
        self._wait(lambda: not core.missing_settings(), SETTINGS_WAIT_S)
        self._wait(self._connected, WAIT_S)
        if rospy.is_shutdown():
            self._say('stopped: shut down before the start')
            return 1
        try:
            with self._lock:
                self._send(core.start(time.monotonic()))
        except replay.ReplayError as error:
            self._say('refused: %s' % error)
            return 2
        self._say('moving slowly to the start pose of puppet arm %s (limits from %s)' % (
            ', '.join(sorted(core.paths)), ', '.join(sorted(set(core.limit_source.values())))))
        self._play('playback', RATE_HZ, 0.2)
        outcome = '; '.join(core.outcome(side) for side in sorted(core.paths))
        if core.phase == replay.FINISHED:
            self._say('finished: %s' % outcome)
            return 0
        self._say('stopped: %s; %s' % (core.why or 'shut down', outcome))
        return 1
