"""Baxter's ROS API as the stand-in serves it, as plain data: commands in, log lines and states out.

Pure: no rospy, no messages, no clock. BaxterApi sits between baxter_sim_node and BaxterModel
and makes every decision that is not moving bytes: which refusals are logged (at most every
WARN_INTERVAL_S per topic and reason), which enable changes are logged and republished, when
/robot/state is due, and what each state message holds. Times: `now_s` is ROS time (s), which
the model and the stamps share; `wall_s` is monotonic time (s), which only the log throttle uses.
Not thread-safe: the node calls it under one lock.
"""
import collections

from robopuppet import interface
from robopuppet.baxter_description import BASE_FRAME
from robopuppet.baxter_sim import baxter_statics as statics
from robopuppet.baxter_sim import baxter_collision as collision
from robopuppet.baxter_sim.baxter_feed_forward import check_feed_forward
from robopuppet.baxter_sim.baxter_ik import ArmIK
from robopuppet.baxter_sim.baxter_publish_rate import JointStateRate
from robopuppet.baxter_sim.baxter_refusals import CommandError, RefusalThrottle, brief
from robopuppet.interface import BAXTER_SIDES

SOFTWARE_VERSION = '1.2.0'  # the Rethink SDK release the stand-in claims to run

# The electric gripper's hardware id; the SDK copies it from the state into every command.
GRIPPER_ID = 65538
GRIPPER_FIRMWARE_DATE = '2014/11/05 14:43:21'   # the SDK 1.2 warns for dates before 2014/05/20
# Message constants (baxter_core_msgs): EndEffectorProperties.ELECTRIC_GRIPPER, AssemblyState's
# ESTOP_BUTTON_UNPRESSED, ESTOP_SOURCE_NONE and ESTOP_SOURCE_USER.
ELECTRIC_GRIPPER = 2
ESTOP_BUTTON_UNPRESSED, ESTOP_SOURCE_NONE, ESTOP_SOURCE_USER = 0, 0, 1
STATE_EVERY_N_CYCLES = 5        # /robot/state at rate_hz / 5 (and on every change)
WARN_INTERVAL_S = 2.0           # a refusal is logged at most this often per topic and reason

Reply = collections.namedtuple('Reply', 'warning change')
Reply.__doc__ = """What a command leads to: `warning` a refusal line to log (None: taken, or
refused too recently to log again); `change` an enable-state change to log, after which
/robot/state must be published (None: no change)."""
# No endpoints: twist and wrench 0; no notes: nothing to log.
Cycle = collections.namedtuple('Cycle', 'joints poses grippers state_due io endpoints notes',
                               defaults=(None, ()))
Cycle.__doc__ = """One publishing cycle: `joints` (names, positions rad or m, velocities rad/s or
m/s, efforts N m; None on a cycle without /robot/joint_states), `poses` {side: ((x, y, z)
m, (qx, qy, qz, qw)) of the gripper in base},
`grippers` {side: EndEffectorState fields but the timestamp}, `state_due` (publish /robot/state
too), `io` {topic: fields} of every baxter_topics.io_publications() topic (AnalogIOState's
timestamp is the node's), `endpoints` {side: baxter_statics.Endpoint}: twist and wrench,
`notes` lines to log (baxter_collision's suppressions and zero-g, as they change)."""


def bool_param(name, value):
    """Return a parameter's value when it is True or False.

    Raises:
        ValueError: naming the parameter, for anything else (also 1, 0 and 'true').
    """
    if not isinstance(value, bool):
        raise ValueError('parameter %s must be true or false, got %r' % (name, value))
    return value


def gripper_properties(side):
    """Return the EndEffectorProperties fields of a side's electric gripper."""
    return dict(
        id=GRIPPER_ID, ui_type=ELECTRIC_GRIPPER,
        manufacturer='Rethink Research Robot', product='Electric Parallel Gripper',
        serial_number='RP-SIM-%s' % side.upper(), hardware_rev='1', firmware_rev='1.2.0',
        firmware_date=GRIPPER_FIRMWARE_DATE, has_calibration=True, controls_grip=True,
        senses_grip=True, reverses_grip=False, controls_force=True, senses_force=True,
        controls_position=True, senses_position=True, properties='')


def gripper_state(gripper, enabled):
    """Return the EndEffectorState fields (but the timestamp) of a baxter_gripper.Gripper.

    `ready` is enabled, not moving and no error: what the SDK's calibrate waits for. Position
    in % of the finger travel (0 closed).
    """
    command, sender, sequence = gripper.last_command
    return dict(
        id=GRIPPER_ID, enabled=enabled, calibrated=gripper.calibrated,
        ready=enabled and not gripper.moving and not gripper.error, moving=gripper.moving,
        gripping=False, missed=gripper.missed, error=gripper.error, reverse=False,
        position=gripper.position, force=0.0, state='', command=command,
        command_sender=sender, command_sequence=sequence)


class BaxterApi:
    """Obey Baxter's commands through a BaxterModel; say what to log and publish.

    Each command method takes the topic it came on and `wall_s` last, and returns a Reply; a
    refused command changes nothing.

    Args:
        model: a baxter_model.BaxterModel.
        command_timeout_s: both arms' joint command timeout (s, > 0) until a message sets it.
        warn_interval_s: the refusal log's interval per topic and reason (s).
        loop_rate_hz: the node's publishing loop's rate (Hz), the joint states' most.
    """

    def __init__(self, model, command_timeout_s, warn_interval_s=WARN_INTERVAL_S,
                 loop_rate_hz=100.0):
        self.model = model
        for side in BAXTER_SIDES:
            model.set_command_timeout(side, command_timeout_s)
        self.warn_interval_s = warn_interval_s
        self._throttle = RefusalThrottle(warn_interval_s)
        self.ik = {side: ArmIK(model.description, side) for side in BAXTER_SIDES}
        self.statics = {side: statics.ArmStatics(model.description, side)
                        for side in BAXTER_SIDES}
        self.joint_rate = JointStateRate(loop_rate_hz)
        self.safety = collision.RobotSafety()
        self._cycles = 0

    # -- commands --
    def joint_command(self, topic, side, mode, names, values, now_s, wall_s):
        """A JointCommand (mode, joint names, targets rad) for one arm, received at now_s;
        refused ('zero-g') while the arm's cuff holds it in zero-g."""
        return self._apply(topic, wall_s, self.safety.joint_command, self.model, side, mode,
                           names, values, now_s)

    def suppress_collision_avoidance(self, topic, side, now_s, wall_s):
        """A suppress_collision_avoidance (Empty) at now_s (baxter_collision)."""
        return self._apply(topic, wall_s, self.safety.suppress, side, 'collision_avoidance', now_s)

    def suppress_cuff_interaction(self, topic, side, now_s, wall_s):
        """A suppress_cuff_interaction (Empty) at now_s: a squeeze gives no zero-g."""
        return self._apply(topic, wall_s, self.safety.suppress, side, 'cuff_interaction', now_s)

    def speed_ratio(self, topic, side, ratio, wall_s):
        """A set_speed_ratio (0..1) for one arm."""
        return self._apply(topic, wall_s, self.model.set_speed_ratio, side, ratio)

    def command_timeout(self, topic, side, timeout_s, wall_s):
        """A joint_command_timeout (s) for one arm."""
        return self._apply(topic, wall_s, self.model.set_command_timeout, side, timeout_s)

    def gripper_command(self, topic, side, hardware_id, command, args, sender, sequence,
                        wall_s):
        """An EndEffectorCommand; one for another hardware id is refused unacknowledged."""
        if hardware_id != GRIPPER_ID:
            return Reply(self._refused(topic, CommandError(
                'gripper command %s ignored: id %d is not this gripper\'s %d'
                % (brief(command), hardware_id, GRIPPER_ID), 'wrong id'), wall_s), None)
        return self._apply(topic, wall_s, self.model.gripper_command, side, command, args,
                           sender, sequence)

    def publish_rate(self, topic, rate_hz, wall_s):
        """A joint_state_publish_rate (Hz): see baxter_publish_rate.JointStateRate.request."""
        try:
            return Reply(None, self.joint_rate.request(rate_hz))
        except CommandError as error:
            return Reply(self._refused(topic, error, wall_s), None)

    def inverse_dynamics(self, topic, side, positions, velocities, accelerations, wall_s):
        """An inverse_dynamics_command (the trajectory action server's feed-forward): refused,
        the stand-in is kinematic (its position control tracks without feed-forward)."""
        return Reply(self._refused(topic, check_feed_forward(
            side, positions, velocities, accelerations), wall_s), None)

    def custom_gripper(self, topic, side, hardware_id, wall_s):
        """An rsdk/set_properties or rsdk/set_state: refused, the gripper is electric."""
        return Reply(self._refused(topic, CommandError(
            '%s gripper: id %d ignored: an electric gripper\'s properties and state are the '
            'robot\'s; only a custom gripper takes them from the SDK' % (side, hardware_id),
            'electric gripper'), wall_s), None)

    def digital_output(self, topic, name, value, wall_s):
        """A DigitalOutputCommand: switch an output (a navigator light)."""
        return self._apply(topic, wall_s, self.model.io.command, name, value)

    def analog_output(self, topic, name, value, wall_s):
        """An AnalogOutputCommand: set an output (the torso fan's speed)."""
        return self._apply(topic, wall_s, self.model.analog.command, name, value)

    def digital_input(self, topic, name, value, wall_s):
        """The stand-in's simulated hand: press (True) or release an input (cuff, button)."""
        return self._apply(topic, wall_s, self.model.io.press, name, value)

    def head_pan(self, topic, target_rad, speed_ratio, enable_pan_request, wall_s):
        """A HeadPanCommand (refused while disabled)."""
        return self._apply(topic, wall_s, self.model.head_pan, target_rad, speed_ratio,
                           enable_pan_request)

    def head_nod(self, topic, nod, wall_s):
        """A command_head_nod (True: nod once)."""
        return self._apply(topic, wall_s, self.model.head.command_nod, nod)

    def solve_ik(self, side, poses, seeds, seed_mode, current):
        """Solve a SolvePositionIK request; touches no state, so it may run outside the lock.

        Args:
            poses: [(frame id, (x, y, z) m, (qx, qy, qz, qw))], the tool point in base.
            seeds: [{joint name: rad}], the user seed of each pose (missing: none).
            seed_mode: SolvePositionIK's seed_mode; current: {joint name: rad} now.
        Returns:
            ([baxter_ik.Solution] one per pose, [log text of each pose that was refused]).
        """
        answers, problems = [], []
        for i, (frame, xyz, quaternion) in enumerate(poses):
            try:
                if frame not in ('', BASE_FRAME):
                    raise ValueError('frame %s is not %s' % (brief(frame), BASE_FRAME))
                answers.append(self.ik[side].solve_seeded(
                    xyz, quaternion, seeds[i] if i < len(seeds) else {}, current, seed_mode))
            except ValueError as error:
                problems.append('%s arm IK: pose %d refused: %s' % (side, i, error))
                answers.append(self.ik[side].invalid())
        return answers, problems

    def ik_refused(self, topic, text, wall_s):
        """Return the (throttled) log line of a pose the IK service could not take, or None."""
        return self._refused(topic, CommandError(text, 'bad pose'), wall_s)

    def set_enabled(self, topic, enable, wall_s):
        """A set_super_enable: enable (refused while stopped) or disable."""
        return self._apply(topic, wall_s, self.model.set_enabled, enable)

    def stop(self, topic, wall_s):
        """A set_super_stop: disable and latch stopped."""
        return self._apply(topic, wall_s, self.model.stop)

    def reset(self, topic, wall_s):
        """A set_super_reset: clear stopped; the robot stays disabled."""
        return self._apply(topic, wall_s, self.model.reset)

    def _apply(self, topic, wall_s, action, *args):
        before = self.model.enabled, self.model.stopped
        try:
            action(*args)
        except CommandError as error:
            return Reply(self._refused(topic, error, wall_s), None)
        return Reply(None, _change(before, (self.model.enabled, self.model.stopped)))

    def _refused(self, topic, error, wall_s):
        """Return the log line of a refusal, or None when its kind was logged too recently."""
        skipped = self._throttle.report((topic, error.reason), wall_s)
        if skipped is None:
            return None
        return 'refused on %s: %s (%s: logged at most every %g s%s)' % (
            topic, error, error.reason, self.warn_interval_s,
            '; %d more since the last line' % skipped if skipped else '')

    # -- outputs --
    def robot_state(self):
        """Return the AssemblyState fields of /robot/state now (a stop is the user's e-stop)."""
        enabled, stopped = self.model.enabled, self.model.stopped
        return dict(ready=enabled and not stopped, enabled=enabled, stopped=stopped, error=False,
                    estop_button=ESTOP_BUTTON_UNPRESSED,
                    estop_source=ESTOP_SOURCE_USER if stopped else ESTOP_SOURCE_NONE)

    def cycle(self, now_s):
        """Advance the model to now_s (ROS time, s) and return what this cycle publishes."""
        model = self.model
        self.safety.hold_zero_g(model, now_s)
        model.step(now_s)
        notes = self.safety.changes(model, now_s)
        self._cycles += 1
        endpoints = {side: statics.arm_endpoint(self.statics[side], model.arms[side])
                     for side in BAXTER_SIDES}
        joints = statics.with_gravity(model.joint_state(), model.arms, endpoints,
                                      model.enabled) if self.joint_rate.due(now_s) else None
        return Cycle(joints,
                     {side: model.endpoint_pose(side) for side in BAXTER_SIDES},
                     {side: gripper_state(model.grippers[side], model.enabled)
                      for side in BAXTER_SIDES},
                     self._cycles % STATE_EVERY_N_CYCLES == 0, self._io_states(), endpoints,
                     notes)

    def _io_states(self):
        io = self.model.io
        states = {interface.digital_io_state_topic(n): f for n, f in io.digital_states().items()}
        states.update((interface.navigator_state_topic(n), f)
                      for n, f in io.navigator_states().items())
        states.update((interface.analog_io_state_topic(n), f)
                      for n, f in self.model.analog.states().items())
        states[interface.HEAD_STATE] = self.model.head.state()
        states.update(self.safety.states())
        return states


def _change(before, after):
    """Return the log text of a change of (enabled, stopped), or None when nothing changed."""
    if after == before:
        return None
    enabled, stopped = after
    if stopped != before[1]:
        return 'robot stopped' if stopped else 'robot reset (it stays disabled)'
    return 'robot enabled' if enabled else 'robot disabled'
