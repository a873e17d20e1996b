"""Teleoperation state machine of one puppet arm: pure, time as an argument.

The arm controller feeds it puppet data, the opmode others set and Baxter's state, calls step(t)
on each puppet sample and at its command rate, and carries out the Step it returns. The states
are robopuppet_msgs/TeleopState's (transitions; README.md, "Operating the puppet"). Button 1 and
the puppet's opmode (limp, hold, feel) are robopuppet.arm.opmode's.

Safety: Baxter follows nothing until all seven puppet encoders report Working and every joint
has sent a valid angle; every command is clamped to Baxter's joint limits and moves at a bounded
speed (a slow approach when following starts far from the puppet, then at most the joint's
velocity limit, see joint_motion.SpeedBudget; no speed parameter can exceed the URDF's limit);
non-finite angles are ignored, and a Baxter pose outside its joint limits is not believed; when
an arm stops following (the puppet's joint states or heartbeat stop or arrive too old to use, a
joint loses calibration, a press, the arm controller itself fails, config_X stores a change of
what the puppet's angles mean: arm.angle_settings) the arm is commanded to stay where Baxter
measures it at once, so it does not coast on to a stale target, and following resumes only
after fresh data and a new press; a Baxter arm that the other puppet drives is not
taken, and if both puppets claim one at once, both let it go. In feel the puppet goes limp on a
fault, without Baxter or without a fresh Baxter pose (see robopuppet.arm.opmode).
"""
import collections
import math

from robopuppet.arm import timing
from robopuppet.arm.baxter_watch import BaxterWatch
from robopuppet.arm.joint_motion import SpeedBudget, clamp, mirror
from robopuppet.arm.opmode import PuppetOpmode
from robopuppet.arm.puppet_watch import REFUSED, PuppetWatch
from robopuppet.arm.transitions import STOP_FOLLOWING, TRANSITIONS, events
from robopuppet.arm.zone_holds import ZoneHolds
from robopuppet.interface import (BAXTER_SIDE, BAXTER_SIDES, BUTTON_LEFT, BUTTON_OPMODE,
                                  BUTTON_RIGHT, CALIBRATING, FAULT, FOLLOWING,
                                  HEARTBEAT_TIMEOUT_S, NO_ROBOT, READY, check_side)

FOLLOW_BUTTON = dict(zip((BUTTON_LEFT, BUTTON_RIGHT), BAXTER_SIDES))  # button -> Baxter's arm
GRIP_PRESSED_BELOW, GRIP_RELEASED_ABOVE = 0.3, 0.7  # end-piece reading, with hysteresis
CLAIM_EXPIRY_S = 1.5       # the other puppet's claim on an arm lasts this long unless renewed

Grip = collections.namedtuple('Grip', 'side close')
Grip.__doc__ = "Close (close=True) or open Baxter's gripper on `side`."
Step = collections.namedtuple('Step', 'commands actions')
Step.__doc__ = """What to do now: commands {side: 7 joint positions rad} for the following
arms, and for an arm that has just stopped following its measured pose (stay there); empty when
nothing may move. actions: a list of opmode.SetOpmode, opmode.SetSetpoints and Grip, in the
order to carry them out."""


class Teleop:
    """Decide what Baxter and the puppet do, from what the puppet and Baxter report.

    Args:
        puppet_side: 'L' or 'R'; Baxter's arm on this side copies the puppet, the other mirrors.
        limits: {'left': 7 limits, 'right': 7 limits}, each with lower, upper (rad) and
            velocity (rad/s), in puppet joint order (see baxter_description.arm_limits).
        state_timeout_s, heartbeat_timeout_s: the puppet is silent after this long without
            joint states (default: timing.DEFAULT, at 10 Hz) or heartbeats (it beats at 1 Hz).
        approach_speed_rad_s: joint speed while a following arm closes in on the puppet's pose
            (capped per joint by the joint's velocity limit).
        track_tolerance_rad: the approach ends when every joint is this close to the target.
        command_period_s: the nominal time between commands; the speed budget holds this much
            motion, so one command may carry speed x command_period_s at once.
        zone_guards: {side: world.zones.ZoneGuard} of the arms that keep-out zones bind: each
            command of a following arm is cut to keep Baxter's motion out of every zone, and
            the speed budget goes on from the cut command (see zone_holds).
    """

    def __init__(self, puppet_side, limits, state_timeout_s=timing.DEFAULT.timeout_s,
                 heartbeat_timeout_s=HEARTBEAT_TIMEOUT_S, approach_speed_rad_s=0.5,
                 track_tolerance_rad=0.02, command_period_s=0.01, zone_guards=None):
        self.own_side = BAXTER_SIDE[check_side(puppet_side)]
        self.limits = limits
        self.puppet = PuppetWatch(state_timeout_s, heartbeat_timeout_s)
        self.robot = BaxterWatch(limits)
        self.zones = ZoneHolds(zone_guards, self.robot)
        self.approach_speed_rad_s = approach_speed_rad_s
        self.track_tolerance_rad = track_tolerance_rad
        self.command_period_s = command_period_s
        self.state = NO_ROBOT
        self.detail = 'waiting for Baxter'
        self.following = {side: False for side in BAXTER_SIDES}
        self.tracking = {side: False for side in BAXTER_SIDES}  # False while approaching
        self.gripper_closed = False
        self._fault_t = self._fault_why = None
        self._robot_ok = False
        self._motion = {}          # side -> SpeedBudget holding the last command
        self._claim_t = {side: None for side in BAXTER_SIDES}  # the other puppet's last claim
        self._button = 0
        self._pressed = []         # button presses not yet acted on
        self._grip_reading = None
        self._last_step_t = None
        self._failure = None       # why the arm controller failed, until the next step
        self._new_meaning = ''     # which angle settings changed, until the next step
        self.puppet_mode = PuppetOpmode(self.own_side, self.robot)

    @property
    def opmode(self):
        """The puppet's opmode as arm_X knows it: limp, hold or feel."""
        return self.puppet_mode.mode

    # ---- inputs --------------------------------------------------------------------------

    def on_joint_states(self, t, statuses, angles_rad):
        """Take 7 encoder statuses and 7 angles rad (PuppetWatch.on_joint_states)."""
        self.puppet.on_joint_states(t, statuses, angles_rad)

    def on_refused(self, t, why, stale=False, late=False):
        """Take joint states that may not be used (PuppetWatch.on_refused): stale ones silence
        the puppet at once, late ones name the silence when no usable ones come."""
        self.puppet.on_refused(t, why, stale, late)

    def on_heartbeat(self, t):
        """Take the puppet's heartbeat."""
        self.puppet.on_heartbeat(t)

    def heartbeat_age(self, t):
        """Return seconds since the puppet's last heartbeat, or -1.0 before the first."""
        return self.puppet.heartbeat_age(t)

    def on_robot_pose(self, t, pose, velocities=None):
        """Take Baxter's arm poses measured at t (BaxterWatch.on_robot_pose)."""
        self.robot.on_robot_pose(t, pose, velocities)

    def on_button(self, button):
        """Take the puppet's user-button reading (1-4, 0 none); a press acts once."""
        if button != self._button and button != 0:
            self._pressed.append(button)
        self._button = button

    def on_opmode(self, mode):
        """Take the opmode others set on <ns>/opmode (limp, hold or feel; a repeat changes
        nothing); return '' or a warning to log when it is no opmode (ignored)."""
        return self.puppet_mode.on_opmode(mode)

    def on_end_piece(self, reading):
        """Take the end-piece button reading (gripper 3: about 1 released, 0 pressed)."""
        if math.isfinite(reading):
            self._grip_reading = reading

    def on_other_puppet(self, t, follow_left, follow_right):
        """Take which Baxter arms the other puppet drives; this one will not take them too."""
        for side, claimed in zip(BAXTER_SIDES, (follow_left, follow_right)):
            self._claim_t[side] = t if claimed else None

    def on_robot(self, enabled):
        """Take whether Baxter is present and enabled."""
        self._robot_ok = enabled

    def on_angle_settings(self, what):
        """Take config_X's change of what the puppet's angles mean (e.g. "joint 0's home_angle"):
        following stops at the next step, as on any stop; a new press approaches again slowly."""
        self._new_meaning = ', '.join(filter(None, (self._new_meaning, what)))

    def on_controller_failed(self, why):
        """The arm controller itself failed (its command loop stalls or raises): stop following
        as on a silent puppet; following resumes only after a new press."""
        self._failure = why

    # ---- decisions -----------------------------------------------------------------------

    def _claimed(self, side, t):
        claim_t = self._claim_t[side]
        return claim_t is not None and t - claim_t < CLAIM_EXPIRY_S

    def _fire(self, event, detail):
        new = TRANSITIONS.get((self.state, event))
        if new is None:
            if self.state == CALIBRATING and event == 'uncalibrated':
                self.detail = detail  # which joints are still missing
            elif self.state == FAULT and event == 'refused' and self.detail == self._fault_why \
                    and not self._fault_why.startswith(REFUSED):   # it says so already
                self.detail = '%s; %s since: %s' % (self._fault_why, REFUSED, detail)
            return
        if new in STOP_FOLLOWING:
            self.following = {side: False for side in BAXTER_SIDES}
        if new == FAULT:
            self._fault_t, self._fault_why = self._last_step_t, detail
        self.state, self.detail = new, detail

    def _act_on_presses(self, t, actions):
        for button in self._pressed:
            if self.state not in (READY, FOLLOWING):
                continue  # a press in any other state does nothing, not even later
            if button == BUTTON_OPMODE:
                why = self.puppet_mode.press(t, self.following, self.puppet.state_t, actions)
                self.detail = why or self.detail
            elif button in FOLLOW_BUTTON:
                self._toggle_follow(FOLLOW_BUTTON[button], t)
        self._pressed = []

    def _toggle_follow(self, side, t):
        if self.following[side]:
            self.following[side] = False
        elif self._claimed(side, t):
            self.detail = 'the other puppet drives Baxter\'s %s arm already' % side
            return
        elif side in self.robot.pose:
            self.following[side], self.tracking[side] = True, False
            self._motion[side] = SpeedBudget(clamp(self.robot.pose[side], self.limits[side]),
                                             self.command_period_s, t)
        self._after_follow_change('')

    def _stop_for_new_meaning(self):
        what, self._new_meaning = self._new_meaning, ''
        buttons = [str(b) for b, side in sorted(FOLLOW_BUTTON.items()) if self.following[side]]
        if what and buttons:
            self.following = {side: False for side in BAXTER_SIDES}
            self._fire('follow_off', '')
            self.detail = '%s changed: following stopped; press %s to follow again' % (
                what, ' and '.join(buttons))

    def _drop_contested_arms(self, t):
        """Let go of any arm the other puppet claims too: both stopping is safe, both is not."""
        contested = [s for s in BAXTER_SIDES if self.following[s] and self._claimed(s, t)]
        for side in contested:
            self.following[side] = False
        if contested:
            self._after_follow_change('the other puppet took Baxter\'s %s arm too: both let go; '
                                      % ' and '.join(contested))

    def _after_follow_change(self, why):
        followers = [s for s in BAXTER_SIDES if self.following[s]]
        self._fire('follow_on' if followers else 'follow_off', '')
        self.detail = why + ('Baxter follows with its %s arm%s' % (
            ' and '.join(followers), 's' if len(followers) > 1 else '')
            if followers else 'no Baxter arm follows; press 2 or 3 to follow')

    def _grip_actions(self, actions):
        reading = self._grip_reading
        if reading is None:
            return
        if not self.gripper_closed and reading < GRIP_PRESSED_BELOW:
            self.gripper_closed = True
        elif self.gripper_closed and reading > GRIP_RELEASED_ABOVE:
            self.gripper_closed = False
        else:
            return
        actions.extend(Grip(side, self.gripper_closed) for side in BAXTER_SIDES
                       if self.following[side])

    def _commands_now(self, t):
        commands = {}
        for side in BAXTER_SIDES:
            if not self.following[side]:
                continue
            angles = self.puppet.angles if side == self.own_side else mirror(self.puppet.angles)
            target = clamp(angles, self.limits[side])
            speeds = [lim.velocity if self.tracking[side]
                      else min(self.approach_speed_rad_s, lim.velocity)
                      for lim in self.limits[side]]
            before = self._motion[side].command
            command = self.zones.cut(side, t, before, self._motion[side].move(target, speeds, t))
            self._motion[side].command = command
            if max(abs(c - g) for c, g in zip(command, target)) <= self.track_tolerance_rad:
                self.tracking[side] = True
            commands[side] = command
        return commands

    def _stay_commands(self, t, was_following):
        """Return {side: where Baxter's arm is now} for each arm that has just stopped following.

        Baxter in position mode goes on to the last command it got; commanding where it is
        stops it at once instead of after its command timeout (where it is now: BaxterWatch.now).
        Not while Baxter is absent or disabled: its pose may be stale then.
        """
        if not self._robot_ok:
            return {}
        commands = {}
        for side in BAXTER_SIDES:
            if was_following[side] and not self.following[side] and side in self.robot.pose:
                commands[side] = self.zones.stay(side, t, self.robot.now(side, t))
        return commands

    def step(self, t):
        """Advance to time t (s) and return the Step to carry out now."""
        self._last_step_t = t
        was_following = dict(self.following)
        failure, self._failure = self._failure, None
        for event, detail in events(t, self.state, self._fault_t, self._robot_ok, self.puppet,
                                    failure):
            self._fire(event, detail)
        actions = []
        self._drop_contested_arms(t)
        self._act_on_presses(t, actions)
        self._stop_for_new_meaning()   # after the presses: no press of this step outlives it
        went_limp = self.puppet_mode.step(t, self.state, self.following, self.puppet.state_t,
                                          actions)
        if went_limp:
            self.detail = '%s; %s' % (self.detail, went_limp)
        self._grip_actions(actions)
        held_before = self.zones.holding()
        commands = self._commands_now(t) if self.state == FOLLOWING else {}
        self.zones.forget(self.following)
        held = self.zones.detail()
        if held:
            self.detail = held
        elif held_before and self.state == FOLLOWING:
            self._after_follow_change('')   # the zone said so: say who follows again
        commands.update(self._stay_commands(t, was_following))
        return Step(commands, actions)
