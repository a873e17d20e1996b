"""What the GUI knows about one puppet arm: latest values and bounded plot buffers.

Pure and thread-safe: ROS callbacks (any thread) call the `on_*` methods with the receive time;
the GUI thread calls `snapshot()` and `drain()` once per frame. Nothing here imports rospy or Qt
or reads a clock.
"""
import collections
import math
import reprlib
import threading

from robopuppet import baxter_description, interface, settings
from robopuppet.arm.readings import arm_poses

SERIES = ('angle', 'voltage', 'setpoint')

# The arm controller's state, as shown; fields follow robopuppet_msgs/TeleopState.
# zone_left/zone_right: the keep-out zone holding Baxter's following left/right arm back, or ''.
Teleop = collections.namedtuple('Teleop', 'state follow_left follow_right opmode heartbeat_age '
                                          'detail zone_left zone_right received_s')
# The serial link's health from one diagnostic_msgs/DiagnosticStatus.
Link = collections.namedtuple('Link', 'level name message values received_s')
# The operator-robot link as arm_X measures it (robopuppet_msgs/LinkState, figures in s; loss a
# fraction 0-1), with the GUI's own receive time.
RobotLink = collections.namedtuple('RobotLink', 'rtt_s sample_age_s max_sample_age_s clock_known '
                                                'loss level fault detail received_s')
# Baxter's measured arms from /robot/joint_states: {side: 7 angles rad in puppet joint order}.
Baxter = collections.namedtuple('Baxter', 'poses received_s')
Joint = collections.namedtuple('Joint', 'status angle_rad voltage_v setpoint_rad')
Snapshot = collections.namedtuple('Snapshot', 'heartbeat_s joints grippers button last_button '
                                              'opmode teleop link robot_link baxter')
BAXTER_JOINTS = {side: baxter_description.arm_joint_names(side)
                 for side in interface.BAXTER_SIDES}


class ArmState:
    """Latest state of one arm plus, per joint, bounded queues of (time s, value) for plotting.

    Each queue keeps at most `capacity` points; when the GUI does not drain in time the oldest
    points are dropped, so memory stays bounded whatever the publishers do.
    """

    def __init__(self, capacity=2048):
        self._lock = threading.Lock()
        self._heartbeat_s = None
        self._status = [None] * settings.NUM_JOINTS
        self._angle = [math.nan] * settings.NUM_JOINTS
        self._voltage = [math.nan] * settings.NUM_JOINTS
        self._setpoint = [math.nan] * settings.NUM_JOINTS
        self._setpoint_sent = [False] * settings.NUM_JOINTS  # since the last limp
        self._grippers = [math.nan] * interface.NUM_GRIPPERS
        self._button = None
        self._last_button = 0
        self._opmode = None
        self._teleop = None
        self._link = None
        self._robot_link = None
        self._baxter = None
        self._pending = {(kind, joint): collections.deque(maxlen=capacity)
                         for kind in SERIES for joint in settings.JOINTS}

    def on_heartbeat(self, now_s):
        """Record a heartbeat received at now_s."""
        with self._lock:
            self._heartbeat_s = now_s

    def on_status(self, joint, status):
        """Record a joint's encoder status text ('Working', 'Disconnected', 'Uncalibrated')."""
        _check_joint(joint)
        with self._lock:
            self._status[joint] = status

    def on_angle(self, joint, angle_rad, now_s):
        """Record a joint angle (rad) received at now_s."""
        _check_joint(joint)
        with self._lock:
            self._angle[joint] = angle_rad
            self._pending['angle', joint].append((now_s, angle_rad))

    def on_voltage(self, joint, voltage_v, now_s):
        """Record a joint's motor voltage (V) received at now_s."""
        _check_joint(joint)
        with self._lock:
            self._voltage[joint] = voltage_v
            self._pending['voltage', joint].append((now_s, voltage_v))

    def on_setpoint(self, joint, angle_rad, now_s):
        """Record a setpoint (rad) sent to a joint by anyone (used in hold mode)."""
        _check_joint(joint)
        with self._lock:
            self._set_setpoint(joint, angle_rad, now_s)
            self._setpoint_sent[joint] = True

    def on_opmode(self, opmode, now_s):
        """Record the opmode (limp, hold or feel); other text is ignored with ValueError.

        Entering hold or feel shows each joint's last angle as its setpoint unless a setpoint
        was sent to it since the last limp (the serial node fills in the current angles just
        so); limp ends the setpoint curves (NaN), so plots show setpoints only while holding.
        """
        if opmode not in interface.OPMODES:
            raise ValueError('opmode must be one of %s, got %s' % (interface.OPMODES,
                                                                   reprlib.repr(opmode)))
        with self._lock:
            if opmode == self._opmode:
                return
            self._opmode = opmode
            for joint in settings.JOINTS:
                if opmode == interface.LIMP:
                    self._set_setpoint(joint, math.nan, now_s)
                    self._setpoint_sent[joint] = False
                elif not self._setpoint_sent[joint]:
                    self._set_setpoint(joint, self._angle[joint], now_s)

    def on_gripper(self, gripper, reading):
        """Record a gripper reading (0-1)."""
        if gripper not in range(interface.NUM_GRIPPERS):
            raise ValueError('gripper must be 0-%d, got %r'
                             % (interface.NUM_GRIPPERS - 1, gripper))
        with self._lock:
            self._grippers[gripper] = reading

    def on_button(self, button):
        """Record the pressed user button (1-4, 0 none)."""
        with self._lock:
            self._button = button
            if button:
                self._last_button = button

    def on_teleop(self, teleop):
        """Record the arm controller's state (a Teleop) and the opmode it reports."""
        with self._lock:
            self._teleop = teleop
        if teleop.opmode in interface.OPMODES:
            self.on_opmode(teleop.opmode, teleop.received_s)

    def on_link(self, link):
        """Record the serial link's latest diagnostic status (a Link)."""
        with self._lock:
            self._link = link

    def on_robot_link(self, robot_link):
        """Record arm_X's latest view of the operator-robot link (a RobotLink)."""
        with self._lock:
            self._robot_link = robot_link

    def on_robot_joints(self, names, positions, now_s):
        """Record Baxter's arm angles from a /robot/joint_states message received at now_s.

        An arm whose seven joints are not all in the message keeps its previous pose.
        """
        poses, _ = arm_poses(names, positions, (), BAXTER_JOINTS)
        if not poses:
            return
        with self._lock:
            kept = dict(self._baxter.poses) if self._baxter is not None else {}
            kept.update((side, tuple(pose)) for side, pose in poses.items())
            self._baxter = Baxter(kept, now_s)

    def snapshot(self):
        """Return the latest values as an immutable Snapshot."""
        with self._lock:
            joints = tuple(Joint(*values) for values in zip(
                self._status, self._angle, self._voltage, self._setpoint))
            return Snapshot(self._heartbeat_s, joints, tuple(self._grippers), self._button,
                            self._last_button, self._opmode, self._teleop, self._link,
                            self._robot_link, self._baxter)

    def drain(self):
        """Return {(series, joint): [(time s, value), ...]} received since the last drain."""
        with self._lock:
            points = {key: list(queue) for key, queue in self._pending.items() if queue}
            for key in points:
                self._pending[key].clear()
        return points

    def _set_setpoint(self, joint, angle_rad, now_s):
        self._setpoint[joint] = angle_rad
        self._pending['setpoint', joint].append((now_s, angle_rad))


def _check_joint(joint):
    if joint not in settings.JOINTS:
        raise ValueError('joint must be 0-%d, got %r' % (settings.NUM_JOINTS - 1, joint))


def heartbeat_age(snapshot, now_s):
    """Return seconds since the last heartbeat, or None before the first one."""
    if snapshot.heartbeat_s is None:
        return None
    return max(0.0, now_s - snapshot.heartbeat_s)
