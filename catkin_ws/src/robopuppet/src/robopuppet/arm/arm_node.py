"""arm_X: drives Baxter from one puppet arm, through Baxter's own ROS API (robopuppet.arm.teleop)."""
import json
import math
import threading
import time

import rospkg
import rospy
from baxter_core_msgs.msg import (AssemblyState, EndEffectorCommand, EndEffectorProperties,
                                  EndEffectorState, JointCommand)
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty, Float32, String, UInt8

from robopuppet import baxter_description, interface, settings
from robopuppet.arm import baxter_watch, teleop
from robopuppet.periodic import Guard, Loop
from robopuppet_msgs.msg import TeleopState

ROBOT_TIMEOUT_S = 1.0        # Baxter is absent when /robot/state or joint states are older
ENABLE_PERIOD_S = 1.0        # how often to ask an absent or disabled Baxter to enable
STATE_PERIOD_S = 0.5         # teleop_state and /diagnostics at least this often
GRIPPER_CALIBRATE_RETRY_S = 3.0
MIN_COMMAND_RATE_HZ = 10.0   # Baxter drops a position command after 0.2 s; keep well inside it
WATCHDOG_PERIOD_S = 0.05     # the watchdog thread checks the command loop this often
# The command loop has failed when it has not completed a step for this many command periods.
STALL_PERIODS = 10
DIAG_LEVEL = {teleop.NO_ROBOT: DiagnosticStatus.WARN, teleop.CALIBRATING: DiagnosticStatus.OK,
              teleop.READY: DiagnosticStatus.OK, teleop.FOLLOWING: DiagnosticStatus.OK,
              teleop.FAULT: DiagnosticStatus.ERROR}


def positive_param(name, default, minimum=0.0):
    """Return a private parameter as a finite float above `minimum` (at least it, if not 0).

    Raises:
        ValueError: the parameter is not such a number.
    """
    value = rospy.get_param(name, default)
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0.0 and number >= minimum):
        raise ValueError('%s must be a number of at least %g, got %r' % (name, minimum, value)
                         if minimum else '%s must be a positive number, got %r' % (name, value))
    return number


def joint_angles(msg):
    """Return the puppet's 7 angles (rad) from a JointState, matched by name, or raise.

    Raises:
        ValueError: a name of joint_0..joint_6 is missing, or names and positions differ in
            number (the message says which).
    """
    if len(msg.name) != len(msg.position):
        raise ValueError('%d names but %d positions' % (len(msg.name), len(msg.position)))
    position = dict(zip(msg.name, msg.position))
    missing = [n for n in settings.JOINT_NAMES if n not in position]
    if missing:
        raise ValueError('no %s (names %s)' % (', '.join(missing), list(msg.name)[:10]))
    return [float(position[n]) for n in settings.JOINT_NAMES]


class ArmNode:
    """Follow the puppet with Baxter's arms and grippers; drive the puppet in hold mode.

    A command is computed as soon as puppet joint states arrive (low latency) and at least at
    ~command_rate, the steady stream Baxter needs; no command goes out unless teleop allows it.
    The command loop and a watchdog run on threads of their own (robopuppet.periodic): an
    exception is logged, counted in /diagnostics and survived, and a command loop that stops
    completing steps is a fault (following stops, Baxter is told to stay) found by the watchdog.

    ROS API:
      Subscribes: <ns>/joint_states (sensor_msgs/JointState), <ns>/joint_J/enc_stat
        (std_msgs/String), <ns>/heartbeat (std_msgs/Empty), <ns>/user_btn (std_msgs/UInt8),
        <ns>/gripper_3 (std_msgs/Float32, the end-piece button), the other puppet's
        teleop_state (an arm it drives is not taken by this one), /robot/state
        (baxter_core_msgs/AssemblyState), /robot/joint_states (sensor_msgs/JointState),
        /robot/end_effector/<side>_gripper/state and .../properties (baxter_core_msgs).
      Publishes: /robot/limb/<side>/joint_command (baxter_core_msgs/JointCommand, position mode),
        /robot/end_effector/<side>_gripper/command (baxter_core_msgs/EndEffectorCommand),
        /robot/set_super_enable (std_msgs/Bool), <ns>/opmode (std_msgs/String),
        <ns>/joint_J/setpoint (std_msgs/Float32), <ns>/teleop_state
        (robopuppet_msgs/TeleopState, latched), /diagnostics (diagnostic_msgs/DiagnosticArray).
      Parameters: ~arm_side ('L' or 'R', required; <ns> is /puppet/arm_<side>),
        ~command_rate (Hz, 100, at least 10), ~state_timeout (s, 0.4: the puppet is silent
        after this long without joint states), ~heartbeat_timeout (s, 2.5), ~approach_speed
        (rad/s, 0.5: joint speed while Baxter closes in on the puppet's pose when following
        starts; each joint's URDF velocity limit caps it).
      The puppet's joint_states are matched by name (joint_0..joint_6); a message without all
      seven names is refused with a warning.
    """

    def __init__(self):
        side = rospy.get_param('~arm_side')
        self._ns = interface.puppet_ns(side)
        self._name = 'arm_' + side
        self._period_s = 1.0 / positive_param('~command_rate', 100.0, MIN_COMMAND_RATE_HZ)
        description = baxter_description.load(baxter_description.urdf_path(
            rospkg.RosPack().get_path('robopuppet')))
        limits = {s: baxter_description.arm_limits(s, description) for s in teleop.SIDES}
        self._joint_names = {s: baxter_description.arm_joint_names(s) for s in teleop.SIDES}
        self._teleop = teleop.Teleop(
            side, limits,
            state_timeout_s=positive_param('~state_timeout', teleop.STATE_TIMEOUT_S),
            heartbeat_timeout_s=positive_param('~heartbeat_timeout', interface.HEARTBEAT_TIMEOUT_S),
            approach_speed_rad_s=positive_param('~approach_speed', 0.5),
            command_period_s=self._period_s)
        self._lock = threading.Lock()
        self._guard = Guard(self._name, rospy.logerr)
        self._statuses = ['Disconnected'] * settings.NUM_JOINTS
        self._refused_states = 0  # puppet joint_states without the seven joint names
        self._robot_enabled = False
        self._robot_state_t = self._robot_joints_t = None
        self._gripper_id = {s: 0 for s in teleop.SIDES}
        self._calibrate_sent_t = {s: -1e9 for s in teleop.SIDES}
        self._gripper_calibrated = {s: False for s in teleop.SIDES}  # seen calibrated once
        self._gripper_sequence = 0
        self._last_command_t = self._last_enable_t = self._last_state_t = -1e9
        self._last_step_t = time.monotonic()  # when _run last completed
        self._published_state = None

        self._pub_command = {s: rospy.Publisher('/robot/limb/%s/joint_command' % s, JointCommand,
                                                queue_size=10, tcp_nodelay=True)
                             for s in teleop.SIDES}
        self._pub_gripper = {s: rospy.Publisher('/robot/end_effector/%s_gripper/command' % s,
                                                EndEffectorCommand, queue_size=10)
                             for s in teleop.SIDES}
        self._pub_enable = rospy.Publisher('/robot/set_super_enable', Bool, queue_size=1)
        self._pub_opmode = rospy.Publisher(self._ns + '/opmode', String, queue_size=10)
        self._pub_setpoint = [rospy.Publisher('%s/joint_%d/setpoint' % (self._ns, j), Float32,
                                              queue_size=10) for j in settings.JOINTS]
        self._pub_state = rospy.Publisher(self._ns + '/teleop_state', TeleopState, queue_size=1,
                                          latch=True)
        self._pub_diag = rospy.Publisher('/diagnostics', DiagnosticArray, queue_size=10)

        for j in settings.JOINTS:
            rospy.Subscriber('%s/joint_%d/enc_stat' % (self._ns, j), String, self._on_status,
                             callback_args=j, queue_size=10)
        rospy.Subscriber(self._ns + '/joint_states', JointState, self._on_joint_states,
                         queue_size=10, tcp_nodelay=True)
        rospy.Subscriber(self._ns + '/heartbeat', Empty, self._on_heartbeat, queue_size=10)
        rospy.Subscriber(self._ns + '/user_btn', UInt8, self._on_button, queue_size=10)
        rospy.Subscriber('%s/gripper_%d' % (self._ns, interface.END_PIECE_GRIPPER), Float32,
                         self._on_end_piece, queue_size=10)
        other = interface.puppet_ns('L' if side == 'R' else 'R')
        rospy.Subscriber(other + '/teleop_state', TeleopState, self._on_other_puppet,
                         queue_size=10)
        rospy.Subscriber('/robot/state', AssemblyState, self._on_robot_state, queue_size=10)
        rospy.Subscriber('/robot/joint_states', JointState, self._on_robot_joints, queue_size=10)
        for s in teleop.SIDES:
            gripper = '/robot/end_effector/%s_gripper/' % s
            rospy.Subscriber(gripper + 'properties', EndEffectorProperties,
                             self._on_gripper_properties, callback_args=s, queue_size=1)
            rospy.Subscriber(gripper + 'state', EndEffectorState, self._on_gripper_state,
                             callback_args=s, queue_size=1)
        self._loops = [Loop(self._guard, 'command loop', self._period_s / 2, self._on_timer),
                       Loop(self._guard, 'watchdog', WATCHDOG_PERIOD_S, self._watch)]
        for loop in self._loops:
            loop.start()
        rospy.on_shutdown(lambda: [loop.stop() for loop in self._loops])

    # ---- puppet and robot input ----------------------------------------------------------

    def _on_status(self, msg, joint):
        with self._lock:
            self._statuses[joint] = msg.data

    def _on_joint_states(self, msg):
        try:
            angles = joint_angles(msg)
        except ValueError as error:
            self._refused_states += 1
            rospy.logwarn_throttle(5, '%s: puppet joint_states refused (%d so far): %s',
                                   self._name, self._refused_states, error)
            return
        bad = [settings.JOINT_NAMES[j] for j, a in enumerate(angles) if not math.isfinite(a)]
        if bad:
            rospy.logwarn_throttle(5, '%s: puppet joint_states with non-finite %s: each such '
                                   'joint keeps its last valid angle', self._name, ', '.join(bad))
        with self._lock:
            now = time.monotonic()
            self._teleop.on_joint_states(now, list(self._statuses), angles)
            self._guard.call('step on joint states', self._step, now)  # act on fresh data now

    def _on_heartbeat(self, msg):
        with self._lock:
            self._teleop.on_heartbeat(time.monotonic())

    def _on_button(self, msg):
        with self._lock:
            self._teleop.on_button(time.monotonic(), msg.data)

    def _on_end_piece(self, msg):
        with self._lock:
            self._teleop.on_end_piece(time.monotonic(), msg.data)

    def _on_other_puppet(self, msg):
        with self._lock:
            self._teleop.on_other_puppet(time.monotonic(), msg.follow_left, msg.follow_right)

    def _on_robot_state(self, msg):
        with self._lock:
            self._robot_enabled = msg.enabled and not msg.stopped and not msg.error
            self._robot_state_t = time.monotonic()

    def _on_robot_joints(self, msg):
        now = time.monotonic()
        position = dict(zip(msg.name, msg.position))
        velocity = dict(zip(msg.name, msg.velocity)) if len(msg.velocity) == len(msg.name) else {}
        pose = {s: [position[n] for n in names] for s, names in self._joint_names.items()
                if all(n in position for n in names)}
        speeds = {s: [velocity.get(n, 0.0) for n in names] for s, names in
                  self._joint_names.items()}
        # The measurement's age from its stamp when that is believable (same clock, not from
        # the future nor older than the extrapolation may reach), else from now.
        age_s = (rospy.Time.now() - msg.header.stamp).to_sec() if msg.header.stamp else 0.0
        if not 0.0 <= age_s <= baxter_watch.MAX_EXTRAPOLATION_S:
            age_s = 0.0
        with self._lock:
            self._robot_joints_t = now
            self._teleop.on_robot_pose(now - age_s, pose, speeds)

    def _on_gripper_properties(self, msg, side):
        with self._lock:
            self._gripper_id[side] = msg.id

    def _on_gripper_state(self, msg, side):
        with self._lock:
            # An electric gripper ignores 'go' until calibrated (as after power-up): calibrate
            # it, as the Rethink SDK does, and ask again while it has not done so. Calibrating
            # opens the gripper, so never one that reported calibrated since this node started
            # (a garbage or glitched state must not drop what it holds), nor one that follows
            # the puppet closed.
            now = time.monotonic()
            if msg.calibrated == EndEffectorState.STATE_TRUE:
                self._gripper_calibrated[side] = True
            holding = self._teleop.following[side] and self._teleop.gripper_closed
            if (not self._gripper_calibrated[side] and not holding and msg.id
                    and now - self._calibrate_sent_t[side] > GRIPPER_CALIBRATE_RETRY_S):
                self._calibrate_sent_t[side] = now
                self._gripper_id[side] = msg.id
                self._send_gripper(side, EndEffectorCommand.CMD_CALIBRATE, {})
                rospy.loginfo('%s: calibrating Baxter\'s %s gripper', self._name, side)

    # ---- output --------------------------------------------------------------------------

    def _on_timer(self):
        with self._lock:
            now = time.monotonic()
            if now - self._last_command_t >= self._period_s * 0.9:
                self._step(now)

    def _watch(self):
        """Fault the teleop when the command loop has not completed a step for a while."""
        if not self._lock.acquire(timeout=STALL_PERIODS * self._period_s):
            raise RuntimeError('the command loop holds its lock for over %.2f s'
                               % (STALL_PERIODS * self._period_s))
        try:
            now = time.monotonic()
            stalled_s = now - self._last_step_t
            if stalled_s > STALL_PERIODS * self._period_s:
                why = 'no step completed for %.2f s; last error: %s' % (
                    stalled_s, self._guard.last_error or 'none')
                rospy.logerr_throttle(5, '%s: command loop failed: %s', self._name, why)
                self._teleop.on_controller_failed(now, why)
                self._step(now)
        finally:
            self._lock.release()

    def _robot_present(self, now):
        return all(t is not None and now - t < ROBOT_TIMEOUT_S
                   for t in (self._robot_state_t, self._robot_joints_t))

    def _step(self, now):
        """Run one step; a step that raises is a fault of the controller (it no longer knows
        what it commanded), reported at the next step. Call with the lock held."""
        try:
            self._run(now)
        except Exception as error:
            self._teleop.on_controller_failed(now, '%s: %s' % (type(error).__name__, error))
            raise

    def _run(self, now):
        """Step the teleop state machine and carry out its decisions. Call with the lock held."""
        present = self._robot_present(now)
        self._teleop.on_robot(now, present and self._robot_enabled)
        if not (present and self._robot_enabled) and now - self._last_enable_t > ENABLE_PERIOD_S:
            self._last_enable_t = now
            self._pub_enable.publish(Bool(True))
        result = self._teleop.step(now)
        for side, angles in result.commands.items():
            self._pub_command[side].publish(JointCommand(
                mode=JointCommand.POSITION_MODE, command=angles, names=self._joint_names[side]))
        self._last_command_t = now
        for action in result.actions:
            self._carry_out(action)
        self._report(now)
        self._last_step_t = now

    def _carry_out(self, action):
        if isinstance(action, teleop.SetOpmode):
            self._pub_opmode.publish(String(action.mode))
        elif isinstance(action, teleop.SetSetpoints):
            for publisher, angle in zip(self._pub_setpoint, action.angles):
                publisher.publish(Float32(angle))
        elif isinstance(action, teleop.Grip):
            position = (EndEffectorState.POSITION_CLOSED if action.close
                        else EndEffectorState.POSITION_OPEN)
            self._send_gripper(action.side, EndEffectorCommand.CMD_GO, {'position': position})

    def _send_gripper(self, side, command, args):
        self._gripper_sequence += 1
        self._pub_gripper[side].publish(EndEffectorCommand(
            id=self._gripper_id[side], command=command, args=json.dumps(args),
            sender=rospy.get_name(), sequence=self._gripper_sequence))

    def _report(self, now):
        tp = self._teleop
        snapshot = (tp.state, tp.following['left'], tp.following['right'], tp.opmode, tp.detail)
        if snapshot != self._published_state:
            rospy.loginfo('%s: %s (%s)', self._name, tp.state, tp.detail)
        elif now - self._last_state_t < STATE_PERIOD_S:
            return
        self._published_state, self._last_state_t = snapshot, now
        msg = TeleopState(state=tp.state, follow_left=tp.following['left'],
                          follow_right=tp.following['right'], opmode=tp.opmode,
                          heartbeat_age=tp.heartbeat_age(now), detail=tp.detail)
        msg.header.stamp = rospy.Time.now()
        self._pub_state.publish(msg)
        values = [KeyValue(k, str(v)) for k, v in (
            ('state', tp.state), ('follow_left', tp.following['left']),
            ('follow_right', tp.following['right']), ('opmode', tp.opmode),
            ('heartbeat_age_s', '%.2f' % tp.heartbeat_age(now)),
            ('ignored_angles', tp.puppet.ignored_angles), ('ignored_robot_poses', tp.robot.ignored_poses),
            ('refused_joint_states', self._refused_states),
            ('callback_errors', self._guard.errors), ('last_error', self._guard.last_error))]
        diag = DiagnosticArray(status=[DiagnosticStatus(
            level=DIAG_LEVEL[tp.state], name='%s: teleoperation' % self._name,
            message='%s: %s' % (tp.state, tp.detail), hardware_id=self._ns, values=values)])
        diag.header.stamp = msg.header.stamp
        self._pub_diag.publish(diag)


def main():
    """Run the arm controller until shutdown."""
    rospy.init_node('arm')
    try:
        ArmNode()
    except (KeyError, ValueError) as error:
        rospy.logfatal('arm node cannot start: %s', error)
        raise SystemExit(1)
    rospy.spin()
