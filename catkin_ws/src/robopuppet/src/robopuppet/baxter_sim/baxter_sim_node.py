"""ROS node baxter_sim: a kinematic Baxter stand-in that speaks Baxter's own ROS API.

The motion is robopuppet.baxter_sim.baxter_model; this module only wires it to topics. Every callback and
the publishing loop run through a robopuppet.periodic Guard: an exception is logged with the
count of failures so far and the node keeps going.
"""
import math
import sys
import threading
import time

import rospkg
import rospy
from baxter_core_msgs.msg import (AssemblyState, EndEffectorCommand, EndEffectorProperties,
                                  EndEffectorState, EndpointState, JointCommand)
from sensor_msgs.msg import JointState
from std_msgs.msg import Bool, Empty, Float64

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_model import BaxterModel
from robopuppet.baxter_sim.baxter_refusals import CommandError, RefusalThrottle, brief
from robopuppet.periodic import Guard, Loop

SOFTWARE_VERSION = '1.2.0'
# The electric gripper's hardware id; the SDK copies it from the state into every command.
GRIPPER_ID = 65538
GRIPPER_FIRMWARE_DATE = '2014/11/05 14:43:21'   # the SDK 1.2 warns for dates before 2014/05/20
STATE_EVERY_N_CYCLES = 5                        # /robot/state at rate_hz / 5
SWITCH_INTERVAL_S = 0.0005
WARN_INTERVAL_S = 2.0       # a refusal is logged at most this often per topic and reason


def positive_param(name, value):
    """Return a parameter's value as a finite float > 0.

    Raises:
        ValueError: naming the parameter, when the value is anything else.
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not (math.isfinite(number) and number > 0.0) or isinstance(value, bool):
        raise ValueError('parameter %s must be a number > 0, got %r' % (name, value))
    return number


def gripper_properties(side):
    """Return the EndEffectorProperties of a side's electric gripper."""
    return EndEffectorProperties(
        id=GRIPPER_ID, ui_type=EndEffectorProperties.ELECTRIC_GRIPPER,
        manufacturer='Rethink Research Robot', product='Electric Parallel Gripper',
        serial_number='RP-SIM-%s' % side.upper(), hardware_rev='1', firmware_rev='1.2.0',
        firmware_date=GRIPPER_FIRMWARE_DATE, has_calibration=True, controls_grip=True,
        senses_grip=True, reverses_grip=False, controls_force=True, senses_force=True,
        controls_position=True, senses_position=True, properties='')


def _positive_param(name, default):
    return positive_param(rospy.resolve_name(name), rospy.get_param(name, default))


class BaxterSimNode:
    """Publish Baxter's state and obey its commands, through BaxterModel.

    ROS API:
      Subscribes: /robot/set_super_enable (std_msgs/Bool), /robot/set_super_reset and
        /robot/set_super_stop (std_msgs/Empty), /robot/limb/<side>/joint_command
        (baxter_core_msgs/JointCommand), /robot/limb/<side>/set_speed_ratio (std_msgs/Float64,
        0..1), /robot/limb/<side>/joint_command_timeout (std_msgs/Float64, s),
        /robot/end_effector/<side>_gripper/command (baxter_core_msgs/EndEffectorCommand).
      Publishes: /robot/joint_states (sensor_msgs/JointState, every cycle), /robot/state
        (baxter_core_msgs/AssemblyState, latched, rate_hz/5 and on change),
        /robot/limb/<side>/endpoint_state (baxter_core_msgs/EndpointState, frame base, every
        cycle), /robot/end_effector/<side>_gripper/state (EndEffectorState, every cycle) and
        .../properties (EndEffectorProperties, latched).
      Sets: /rethink/software_version = '1.2.0'.
      Logs: a refused command, at most every 2 s per topic and reason of refusal; an exception
        in a callback or in the publishing loop (which both go on), with the count of failures
        since start (the stand-in has no /diagnostics).
      Parameters: /robot_description (URDF text; the package's urdf/baxter.urdf when unset),
        ~rate_hz (float, 100), ~joint_command_timeout (float s, 0.2, initial value for both
        arms), ~gripper_calibrated (bool, false: like the real grippers after power-up).
    """

    def __init__(self):
        """Read and check the parameters, then advertise and subscribe.

        Raises:
            ValueError: a parameter is unusable (the message names it).
        """
        text = rospy.get_param('/robot_description', None)
        try:
            description = bd.Description(text) if text else bd.load(
                bd.urdf_path(rospkg.RosPack().get_path('robopuppet')))
        except bd.DescriptionError as error:
            raise ValueError('parameter /robot_description: %s' % error) from error
        self._rate_hz = _positive_param('~rate_hz', 100.0)
        timeout_s = _positive_param('~joint_command_timeout', 0.2)
        calibrated = rospy.get_param('~gripper_calibrated', False)
        if not isinstance(calibrated, bool):
            raise ValueError('parameter %s must be true or false, got %r'
                             % (rospy.resolve_name('~gripper_calibrated'), calibrated))
        self._lock = threading.Lock()         # the model, between the loop and the callbacks
        self._state_lock = threading.Lock()   # orders /robot/state messages like the changes
        self._throttle = RefusalThrottle(WARN_INTERVAL_S)
        self._guard = Guard(rospy.get_name(), self._log_failure)
        self._model = BaxterModel(description, rospy.get_time(), gripper_calibrated=calibrated)
        for side in bd.SIDES:
            self._model.set_command_timeout(side, timeout_s)
        rospy.set_param('/rethink/software_version', SOFTWARE_VERSION)
        self._state_pub = rospy.Publisher('/robot/state', AssemblyState, queue_size=1, latch=True)
        self._joint_pub = rospy.Publisher('/robot/joint_states', JointState, queue_size=10)
        self._endpoint_pub, self._gripper_pub = {}, {}
        self._cycle = 0
        for side in bd.SIDES:
            limb = '/robot/limb/%s/' % side
            gripper = '/robot/end_effector/%s_gripper/' % side
            self._endpoint_pub[side] = rospy.Publisher(limb + 'endpoint_state', EndpointState,
                                                       queue_size=10)
            self._gripper_pub[side] = rospy.Publisher(gripper + 'state', EndEffectorState,
                                                      queue_size=10)
            rospy.Publisher(gripper + 'properties', EndEffectorProperties, queue_size=1,
                            latch=True).publish(gripper_properties(side))
            self._subscribe(limb + 'joint_command', JointCommand, self._on_joint_command, side)
            self._subscribe(limb + 'set_speed_ratio', Float64, self._on_setting,
                            self._model.set_speed_ratio, side)
            self._subscribe(limb + 'joint_command_timeout', Float64, self._on_setting,
                            self._model.set_command_timeout, side)
            self._subscribe(gripper + 'command', EndEffectorCommand, self._on_gripper_command,
                            side)
        self._subscribe('/robot/set_super_enable', Bool, self._on_enable)
        self._subscribe('/robot/set_super_reset', Empty, self._on_enable_action,
                        self._model.reset)
        self._subscribe('/robot/set_super_stop', Empty, self._on_enable_action, self._model.stop)
        self._publish_state()

    def _subscribe(self, topic, msg_type, handler, *args):
        """Subscribe handler(msg, topic, *args), run through the Guard."""
        def guarded(msg):
            self._guard.call(topic, handler, msg, topic, *args)
        rospy.Subscriber(topic, msg_type, guarded, queue_size=10)

    def _log_failure(self, text):
        """Log a callback's or the loop's exception (the Guard throttles and counts them)."""
        rospy.logerr('%s [%d failures in all since start]', text, self._guard.errors)

    def _apply(self, topic, action, *args):
        """Run a model call under the lock; log (never raise) a refused command.

        A refusal is logged at most every WARN_INTERVAL_S for each topic and reason, so a
        script that repeats a bad command at 100 Hz gets one line every 2 s, and other kinds
        of refusal, or the same kind on another topic, are each still reported.

        Returns:
            True when the model took the command.
        """
        with self._lock:
            try:
                action(*args)
                return True
            except CommandError as error:
                self._refused(topic, error.reason, str(error))
                return False

    def _refused(self, topic, reason, text):
        skipped = self._throttle.report((topic, reason), time.monotonic())
        if skipped is not None:
            rospy.logwarn('refused on %s: %s (%s: logged at most every %g s%s)', topic, text,
                          reason, WARN_INTERVAL_S,
                          '; %d more since the last line' % skipped if skipped else '')

    def _on_joint_command(self, msg, topic, side):
        self._apply(topic, self._model.joint_command, side, msg.mode, msg.names, msg.command,
                    rospy.get_time())

    def _on_setting(self, msg, topic, setter, side):
        self._apply(topic, setter, side, msg.data)

    def _on_gripper_command(self, msg, topic, side):
        if msg.id != GRIPPER_ID:
            with self._lock:
                self._refused(topic, 'wrong id', 'gripper command %s ignored: id %d is not this '
                              'gripper\'s %d' % (brief(msg.command), msg.id, GRIPPER_ID))
            return
        self._apply(topic, self._model.gripper_command, side, msg.command, msg.args, msg.sender,
                    msg.sequence)

    def _enable_state(self):
        with self._lock:
            return self._model.enabled, self._model.stopped

    def _on_enable(self, msg, topic):
        before = self._enable_state()
        self._apply(topic, self._model.set_enabled, msg.data)
        self._state_changed(before)

    def _on_enable_action(self, _msg, topic, action):
        before = self._enable_state()
        self._apply(topic, action)
        self._state_changed(before)

    def _state_changed(self, before):
        """Log and publish /robot/state when enable or stop changed (not for repeats)."""
        enabled, stopped = after = self._enable_state()
        if after == before:
            return
        if stopped != before[1]:
            rospy.loginfo('robot %s', 'stopped' if stopped else 'reset (it stays disabled)')
        else:
            rospy.loginfo('robot %s', 'enabled' if enabled else 'disabled')
        self._publish_state()

    def _publish_state(self):
        # Read and publish under one lock: the loop and the enable callbacks both publish, and
        # the latched message must be the newest state, never an older one published late.
        with self._state_lock:
            with self._lock:
                enabled, stopped = self._model.enabled, self._model.stopped
            self._state_pub.publish(AssemblyState(
                ready=enabled and not stopped, enabled=enabled, stopped=stopped, error=False,
                estop_button=AssemblyState.ESTOP_BUTTON_UNPRESSED,
                estop_source=(AssemblyState.ESTOP_SOURCE_USER if stopped
                              else AssemblyState.ESTOP_SOURCE_NONE)))

    def _publish_cycle(self, stamp):
        with self._lock:
            self._model.step(stamp.to_sec())
            names, positions, velocities, efforts = self._model.joint_state()
            poses = {side: self._model.endpoint_pose(side) for side in bd.SIDES}
            enabled = self._model.enabled
            grippers = [(side, self._gripper_state(side, stamp, enabled)) for side in bd.SIDES]
        joints = JointState(name=names, position=positions, velocity=velocities, effort=efforts)
        joints.header.stamp = stamp
        self._joint_pub.publish(joints)
        for side, ((x, y, z), (qx, qy, qz, qw)) in poses.items():
            endpoint = EndpointState()
            endpoint.header.stamp = stamp
            endpoint.header.frame_id = bd.BASE_FRAME
            p, o = endpoint.pose.position, endpoint.pose.orientation
            p.x, p.y, p.z, o.x, o.y, o.z, o.w = x, y, z, qx, qy, qz, qw
            self._endpoint_pub[side].publish(endpoint)
        for side, state in grippers:
            self._gripper_pub[side].publish(state)

    def _gripper_state(self, side, stamp, enabled):
        gripper = self._model.grippers[side]
        command, sender, sequence = gripper.last_command
        return EndEffectorState(
            timestamp=stamp, id=GRIPPER_ID, enabled=enabled, calibrated=gripper.calibrated,
            ready=enabled and not gripper.moving and not gripper.error, moving=gripper.moving,
            gripping=False, missed=gripper.missed, error=gripper.error, reverse=False,
            position=gripper.position, force=0.0, state='', command=command,
            command_sender=sender, command_sequence=sequence)

    def _loop_once(self):
        if rospy.is_shutdown():
            return
        self._publish_cycle(rospy.get_rostime())
        self._cycle += 1
        if self._cycle % STATE_EVERY_N_CYCLES == 0:
            self._publish_state()

    def spin(self):
        """Step and publish at rate_hz (on a Loop thread) until shutdown."""
        loop = Loop(self._guard, 'publishing loop', 1.0 / self._rate_hz, self._loop_once)
        rospy.on_shutdown(loop.stop)
        loop.start()
        rospy.spin()
        loop.stop()


def main():
    """Run the baxter_sim node."""
    # The publishing loop must wake on time: let it take the GIL from subscriber threads within
    # 0.5 ms instead of Python's default 5 ms.
    sys.setswitchinterval(SWITCH_INTERVAL_S)
    rospy.init_node('baxter_sim')
    try:
        node = BaxterSimNode()
    except (ValueError, rospkg.ResourceNotFound) as error:
        rospy.logfatal('baxter_sim cannot start: %s', error)
        raise SystemExit(1)
    node.spin()
