"""Everything arm_X decides, in one pure object beneath the node: the node's only entry point.

One input method per topic the node subscribes; step() returns typed actions for the node to
publish (time in s is an argument; no rospy, no messages, not thread-safe: arm_X makes every call
under its one lock).

It holds the teleop state machine (robopuppet.arm.teleop), Baxter's upkeep (presence, enabling,
gripper calibration: robopuppet.arm.baxter_upkeep), the operator-robot link (pings, echoes, the
age of each puppet sample: robopuppet.arm.link_watch), what the puppet's angles mean (the
stored angle settings and each sample's tag: robopuppet.arm.angle_settings), the puppet's
encoder statuses, the pace of the command stream, the command loop's health and the teleop
report (teleop_state and /diagnostics).

Two clocks: `t` (monotonic s) paces teleop; `now_s` (the robot host's ROS clock, s) is the one
pings carry and puppet samples are aged on.
"""
import collections
import reprlib

from robopuppet import baxter_description, settings
from robopuppet.arm.angle_settings import AngleSettingsWatch, describe
from robopuppet.arm.baxter_upkeep import BaxterUpkeep
from robopuppet.arm.link_clock import Refused
from robopuppet.arm.link_watch import LATE, STALE_KINDS, LinkWatch
from robopuppet.arm.readings import arm_poses, joint_angles, non_finite_joints
from robopuppet.arm.teleop import Grip, Teleop
from robopuppet.interface import (BAXTER_SIDES, CALIBRATING, DIAG_TELEOP, DISCONNECTED,
                                  ENC_STATUS, FAULT, FOLLOWING, NO_ROBOT, READY, puppet_ns)

STATE_PERIOD_S = 0.5  # the report (teleop_state, /diagnostics) goes out at least this often
# The command loop has failed when it has not completed a step for this many command periods.
STALL_PERIODS = 10
# /diagnostics level per teleop state, as diagnostic_msgs/DiagnosticStatus names them.
DIAG_LEVEL = {NO_ROBOT: 'WARN', CALIBRATING: 'OK', READY: 'OK', FOLLOWING: 'OK', FAULT: 'ERROR'}
LEVELS = ('OK', 'WARN', 'ERROR')

Enable = collections.namedtuple('Enable', '')
Enable.__doc__ = 'Ask Baxter to enable (/robot/set_super_enable).'
ArmCommand = collections.namedtuple('ArmCommand', 'side names angles')
ArmCommand.__doc__ = "Command Baxter's arm on `side` to 7 joint positions (rad) of its joint names."
Report = collections.namedtuple('Report', 'changed state follow_left follow_right opmode '
                                          'heartbeat_age_s detail zone_left zone_right '
                                          'diag_name hardware_id level message values '
                                          'assist_left assist_right', defaults=(False, False))
Report.__doc__ = """The teleop report: changed (it differs from the last one: log it), the
TeleopState fields, the DiagnosticStatus's name, hardware_id, level ('OK', 'WARN' or 'ERROR'),
message and values [(key, text)], and last TeleopState's assist_left and assist_right."""


class ArmController:
    """Decide what arm_X sends Baxter and the puppet.

    Args:
        side: the puppet's side, 'L' or 'R'.
        limits: {'left': 7 limits, 'right': 7 limits} (see baxter_description.arm_limits).
        timing: the StateTimeout at the puppet's comm_rate (robopuppet.arm.timing).
        heartbeat_timeout_s: the puppet is silent after this long without a heartbeat.
        approach_speed_rad_s: joint speed while a following arm closes in on the puppet.
        command_period_s: the command stream's period (s).
        guard: the node's robopuppet.periodic.Guard (its errors go into the report).
        t: the time (s) at the start.
        age_bound: the timing.AgeBound on puppet samples' age.
        zone_guards: {side: world.zones.ZoneGuard} that cut commands at keep-out zones (see
            teleop.Teleop).
        leash_s: how far a command may lead Baxter, in s of mode-1 travel (arm.leash; 0: none).
    """

    def __init__(self, side, limits, timing, heartbeat_timeout_s, approach_speed_rad_s,
                 command_period_s, guard, t, age_bound, zone_guards=None, leash_s=0.0):
        self.teleop = Teleop(side, limits, state_timeout_s=timing.timeout_s,
                             heartbeat_timeout_s=heartbeat_timeout_s,
                             approach_speed_rad_s=approach_speed_rad_s,
                             command_period_s=command_period_s, zone_guards=zone_guards,
                             leash_s=leash_s)
        self.baxter = BaxterUpkeep()
        self.link = LinkWatch(side, age_bound, timing.timeout_s)
        self.angle_settings = AngleSettingsWatch()
        self.timing = timing
        self.command_period_s = command_period_s
        self.guard = guard
        self.diag_name = 'arm_%s: %s' % (side, DIAG_TELEOP)
        self.hardware_id = puppet_ns(side)
        self.joint_names = {s: baxter_description.arm_joint_names(s) for s in BAXTER_SIDES}
        self.refused_states = 0  # puppet joint_states without the seven joint names
        self.last_step_t = t     # when a step was last carried out completely
        self._statuses = [DISCONNECTED] * settings.NUM_JOINTS
        self._command_t = None
        self._reported = self._report_t = None

    # ---- inputs --------------------------------------------------------------------------

    def on_status(self, joint, status):
        """Take a joint's encoder status (interface.ENC_STATUS). Any other text keeps the joint
        from counting as Working and is kept cut short (reprlib), as the report and the log
        show it: a 10^5-character garbage status would otherwise go into every teleop_state."""
        self._statuses[joint] = status if status in ENC_STATUS else reprlib.repr(status)

    def on_joint_states(self, t, names, positions, stamp_s, now_s, tag=''):
        """Take the puppet's joint states, stamped stamp_s (operator clock) and received at
        now_s (robot clock), tagged `tag` (header.frame_id: the angle settings they were made
        with, see angle_settings); return (taken, a warning to log or '').

        A message without joint_0..joint_6 is refused (not taken) and counted; so is one that
        link_watch does not let through (of unknown age: the stream is stale, which teleop takes
        as a silent puppet; too old: dropped, silent only when no usable one comes for the state
        timeout; out of order). A taken one's warning also says when the newest stamp used
        before was forgotten (link_watch: in the future on the refined clock estimate).
        """
        try:
            angles = joint_angles(names, positions)
        except ValueError as error:
            self.refused_states += 1
            return False, 'puppet joint_states refused (%d so far): %s' % (
                self.refused_states, error)
        reanchored = self.link.reanchored
        try:
            self.link.take(now_s, stamp_s)
        except Refused as refusal:
            self.teleop.on_refused(t, str(refusal), stale=refusal.kind in STALE_KINDS,
                                   late=refusal.kind == LATE)
            if refusal.kind == LATE:
                return False, 'puppet joint_states dropped (%d late so far): %s' % (
                    self.link.refused[LATE], refusal)
            return False, 'puppet joint_states refused (%d %s so far): %s' % (
                self.link.refused[refusal.kind], refusal.kind, refusal)
        other_meaning = self.angle_settings.refusal(tag)
        if other_meaning:
            self.teleop.on_refused(t, other_meaning)
            return False, 'puppet joint_states refused (%d for their angle settings so far): ' \
                '%s' % (self.angle_settings.refused, other_meaning)
        self.teleop.on_joint_states(t, list(self._statuses), angles)
        bad = non_finite_joints(angles)
        notes = ['puppet joint_states with non-finite %s: each such joint keeps its last valid '
                 'angle' % ', '.join(bad)] if bad else []
        if self.link.reanchored != reanchored:
            notes.append('the newest puppet sample used before lies in the future on the '
                         "operator clock's estimate now: forgotten (%d so far), later ones "
                         'compare with this one' % self.link.reanchored)
        return True, '; '.join(notes)

    def on_robot_joints(self, t, names, positions, velocities, age_s):
        """Take Baxter's joint states, received at t and measured age_s (s) earlier (by their
        stamp). An age below 0 (a stamp ahead of this host's clock) counts as 0; a larger one is
        kept: a late pose counts as old (feel refuses one over 1 s old, see opmode), while
        BaxterWatch.now extrapolates it by at most MAX_EXTRAPOLATION_S."""
        self.baxter.on_robot_joints(t)
        poses, speeds = arm_poses(names, positions, velocities, self.joint_names)
        self.teleop.on_robot_pose(t - (age_s if age_s > 0.0 else 0.0), poses, speeds)

    def on_heartbeat(self, t):
        """Take the puppet's heartbeat."""
        self.teleop.on_heartbeat(t)

    def on_button(self, button):
        """Take the puppet's user-button reading (1-4, 0 none); a press acts once."""
        self.teleop.on_button(button)

    def on_opmode(self, mode):
        """Take the opmode others set on <ns>/opmode; return '' or a warning to log (see
        teleop.Teleop.on_opmode)."""
        return self.teleop.on_opmode(mode)

    def on_end_piece(self, reading):
        """Take the end-piece button reading (gripper 3: about 1 released, 0 pressed)."""
        self.teleop.on_end_piece(reading)

    def on_other_puppet(self, t, follow_left, follow_right):
        """Take which Baxter arms the other puppet drives (its teleop_state)."""
        self.teleop.on_other_puppet(t, follow_left, follow_right)

    def on_assist_target(self, t, side, positions, gripper_closed, hold, detail):
        """Take the assist's target for Baxter's `side` arm, received at t; return '' or why it
        was refused (to log): for this puppet's own arm, an unknown arm, not 7 finite angles
        (arm.assist_follow; counted in the report's refused_assist_targets)."""
        return self.teleop.on_assist_target(t, side, positions, gripper_closed, hold, detail)

    def on_robot_state(self, t, enabled, stopped, error):
        """Take /robot/state's flags."""
        self.baxter.on_robot_state(t, enabled, stopped, error)

    def on_stored_settings(self, joints):
        """Take config_X's stored settings, [(joint, {name: value})]; return a line to log, ''
        when none. A change of an angle setting (the first message is none) stops following."""
        try:
            changes = self.angle_settings.on_stored(joints)
        except ValueError as error:
            return 'stored_settings ignored: %s' % error
        if not changes:
            return ''
        self.teleop.on_angle_settings(describe(changes))
        return '%s changed in stored_settings: following stops' % describe(changes)

    def on_echo(self, now_s, seq, sent_s, echoed_s):
        """Take a link echo that arrived at now_s; return '' or why it was ignored (to log)."""
        return self.link.clock.on_echo(now_s, seq, sent_s, echoed_s)

    def on_gripper_state(self, t, side, gripper_id, calibrated):
        """Take a gripper's state; return the actions it calls for ([] or a calibrate)."""
        holding = (self.teleop.following[side] and self.teleop.gripper_closed
                   or self.teleop.assist.gripper_closed(side))
        calibrate = self.baxter.on_gripper_state(t, side, gripper_id, calibrated, holding)
        return [calibrate] if calibrate else []

    # ---- steps ---------------------------------------------------------------------------

    def step_due(self, t):
        """Return whether the steady command stream needs a step at t (none went out for
        about a command period)."""
        return self._command_t is None or t - self._command_t >= 0.9 * self.command_period_s

    def step(self, t):
        """Advance to t; return the actions to carry out in order, then call done(t).

        The actions: Enable, an ArmCommand per commanded arm, teleop's opmode.SetOpmode and
        opmode.SetSetpoints, a baxter_upkeep.GripperCommand per teleop Grip, and last a Report when
        one is due.
        """
        ready = self.baxter.ready(t)
        self.teleop.on_robot(ready)
        actions = [Enable()] if self.baxter.enable_due(t) else []
        result = self.teleop.step(t)
        self._command_t = t
        actions += [ArmCommand(side, self.joint_names[side], angles)
                    for side, angles in sorted(result.commands.items())]
        actions += [self.baxter.grip(a.side, a.close) if isinstance(a, Grip) else a
                    for a in result.actions]
        report = self._report(t)
        return actions + [report] if report else actions

    def ping(self, now_s):
        """Return (seq, sent_s) of the link ping to send now, or None when none is due."""
        return self.link.clock.ping(now_s)

    def link_report(self, now_s):
        """Return the link_watch.LinkReport when one is due, else None."""
        return self.link.report(now_s, self.teleop.state != NO_ROBOT)

    def done(self, t):
        """Take that the step at t was carried out completely."""
        self.last_step_t = t

    def failed(self, error):
        """Take that a step raised `error`: the controller no longer knows what it commanded,
        a fault at the next step."""
        self.teleop.on_controller_failed('%s: %s' % (type(error).__name__, error))

    def stall(self, t):
        """Return why the command loop has failed at t ('' when it has not): no step carried out
        for STALL_PERIODS command periods. A failure faults the teleop at the next step."""
        stalled_s = t - self.last_step_t
        if stalled_s <= STALL_PERIODS * self.command_period_s:
            return ''
        why = 'no step completed for %.2f s; last error: %s' % (
            stalled_s, self.guard.last_error or 'none')
        self.teleop.on_controller_failed(why)
        return why

    # ---- report --------------------------------------------------------------------------

    def _report(self, t):
        tp = self.teleop
        follow_left, follow_right = (tp.following[side] for side in BAXTER_SIDES)
        assist_left, assist_right = (tp.assist.assisted[side] for side in BAXTER_SIDES)
        zone_left, zone_right = (tp.zones.zone(side) for side in BAXTER_SIDES)
        snapshot = (tp.state, follow_left, follow_right, tp.opmode, tp.detail, zone_left,
                    zone_right, assist_left, assist_right)
        changed = snapshot != self._reported
        if not changed and t - self._report_t < STATE_PERIOD_S:
            return None
        self._reported, self._report_t = snapshot, t
        level, message = DIAG_LEVEL[tp.state], '%s: %s' % (tp.state, tp.detail)
        for late in (x for x in (self.timing, self.link.bound) if not x.meets_stop):
            level = max(level, 'WARN', key=LEVELS.index)
            message += '; ' + late.describe()
        values = [
            ('state', tp.state), ('follow_left', follow_left), ('follow_right', follow_right),
            ('assist_left', assist_left), ('assist_right', assist_right),
            ('opmode', tp.opmode), ('zone_left', zone_left), ('zone_right', zone_right),
            ('heartbeat_age_s', '%.2f' % tp.heartbeat_age(t)),
            ('comm_rate_hz', '%g' % self.timing.comm_rate_hz),
            ('state_timeout_s', '%.2f' % self.timing.timeout_s),
            ('stop_within_s', '%.2f' % self.timing.stop_s),
            ('max_sample_age_s', '%.2f' % self.link.bound.bound_s),
            ('ignored_angles', tp.puppet.ignored_angles),
            ('ignored_robot_poses', tp.robot.ignored_poses),
            ('refused_joint_states', self.refused_states),
            ('refused_for_angle_settings', self.angle_settings.refused),
            ('refused_assist_targets', tp.assist.refused),
            ('callback_errors', self.guard.errors), ('last_error', self.guard.last_error)]
        return Report(changed, tp.state, follow_left, follow_right, tp.opmode,
                      tp.heartbeat_age(t), tp.detail, zone_left, zone_right, self.diag_name,
                      self.hardware_id, level, message,
                      [(key, str(value)) for key, value in values], assist_left, assist_right)
