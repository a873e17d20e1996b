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
fault, without Baxter or without a fresh Baxter pose (see robopuppet.arm.opmode). The arm that
robopuppet's assist drives through this controller (arm.assist_follow) moves by the same rules,
holds where it is while the assist says hold, stops on every stop and goes to the other puppet.
"""
import collections
import math

from robopuppet.arm import timing
from robopuppet.arm.arm_drive import ArmDrive
from robopuppet.arm.assist_follow import AssistFollow, who_drives
from robopuppet.arm.baxter_watch import BaxterWatch
from robopuppet.arm.joint_motion import mirror
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
and assisted arms and, for an arm that has just stopped, its measured pose (stay there); empty
when nothing may move. actions: a list of opmode.SetOpmode, opmode.SetSetpoints and Grip, in the
order to carry them out."""


class Teleop:
    """Decide what Baxter and the puppet do, from what the puppet and Baxter report.

    Args:
        puppet_side: 'L' or 'R'; Baxter's arm on this side copies the puppet, the other mirrors.
        limits: {'left': 7 limits, 'right': 7 limits}, each with lower, upper (rad) and
            velocity (rad/s), in puppet joint order (see baxter_description.arm_limits).
        state_timeout_s, heartbeat_timeout_s: the puppet is silent after this long without
            joint states (default: timing.DEFAULT, at 10 Hz) or heartbeats (it beats at 1 Hz).
        approach_speed_rad_s, track_tolerance_rad, command_period_s, leash_s: how a following
            arm closes in on the puppet's pose, how far one command may move and lead Baxter
            (arm_drive.ArmDrive; leash_s 0: no leash).
        zone_guards: {side: world.zones.ZoneGuard} of the arms that keep-out zones bind: each
            command of a following arm is cut to keep Baxter's motion out of every zone, and
            the speed budget goes on from the cut command (see zone_holds).
    """

    def __init__(self, puppet_side, limits, state_timeout_s=timing.DEFAULT.timeout_s,
                 heartbeat_timeout_s=HEARTBEAT_TIMEOUT_S, approach_speed_rad_s=0.5,
                 track_tolerance_rad=0.02, command_period_s=0.01, zone_guards=None,
                 leash_s=0.0):
        self.own_side = BAXTER_SIDE[check_side(puppet_side)]
        self.limits = limits
        self.puppet = PuppetWatch(state_timeout_s, heartbeat_timeout_s)
        self.robot = BaxterWatch(limits)
        self.zones = ZoneHolds(zone_guards, self.robot)
        self.drive = ArmDrive(limits, self.robot, self.zones, approach_speed_rad_s,
                              track_tolerance_rad, command_period_s, leash_s)
        self.state = NO_ROBOT
        self.detail = 'waiting for Baxter'
        self.following = {side: False for side in BAXTER_SIDES}
        self.tracking = self.drive.tracking  # {side: False while approaching}
        self.gripper_closed = False
        self._fault_t = self._fault_why = None
        self._robot_ok = False
        self._claim_t = {side: None for side in BAXTER_SIDES}  # the other puppet's last claim
        self._button = 0
        self._pressed = []         # button presses not yet acted on
        self._grip_reading = None
        self._last_step_t = None
        self._failure = None       # why the arm controller failed, until the next step
        self._new_meaning = ''     # which angle settings changed, until the next step
        self.puppet_mode = PuppetOpmode(self.own_side, self.robot)
        self.assist = AssistFollow(self.own_side)

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

    def on_assist_target(self, t, side, positions, gripper_closed, hold, detail):
        """Take an assist target (AssistFollow.on_target); return '' or why it was refused."""
        return self.assist.on_target(t, side, positions, gripper_closed, hold, detail)

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
            self.assist.release_all()
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
        if self.following[side] or self.assist.assisted[side]:
            self.following[side] = False
            self.assist.release(side)
        elif self._claimed(side, t):
            self.detail = 'the other puppet drives Baxter\'s %s arm already' % side
            return
        elif side in self.robot.pose:  # the assist's arm, when it has a target; else puppet's
            self.following[side] = not self.assist.engage(side, t)
            self.drive.start(side, t)
        self._after_follow_change('')

    def _stop_for_new_meaning(self):
        what, self._new_meaning = self._new_meaning, ''
        buttons = [str(b) for b, side in sorted(FOLLOW_BUTTON.items()) if self.driven()[side]]
        if what and buttons:
            self.following = {side: False for side in BAXTER_SIDES}
            self.assist.release_all()
            self._fire('follow_off', '')
            self.detail = '%s changed: following stopped; press %s to follow again' % (
                what, ' and '.join(buttons))

    def _drop_claimed_arms(self, t):
        """Let go of any arm the other puppet claims too: both stopping is safe, both is not;
        an arm the assist drives goes to the other puppet (a take-over: it does not let go)."""
        for side in [s for s in BAXTER_SIDES if self.assist.assisted[s] and self._claimed(s, t)]:
            self.assist.release(side)
            self._after_follow_change("puppet %s took Baxter's %s arm over from the assist; " % (
                'L' if self.own_side == 'right' else 'R', side))
        contested = [s for s in BAXTER_SIDES if self.following[s] and self._claimed(s, t)]
        for side in contested:
            self.following[side] = False
        if contested:
            self._after_follow_change('the other puppet took Baxter\'s %s arm too: both let go; '
                                      % ' and '.join(contested))

    def driven(self):
        """Return {side: whether Baxter's arm follows this puppet or the assist through it}."""
        return {s: self.following[s] or self.assist.assisted[s] for s in BAXTER_SIDES}

    def _after_follow_change(self, why):
        followers = [s for s in BAXTER_SIDES if self.following[s]]
        assisted = [s for s in BAXTER_SIDES if self.assist.assisted[s]]
        self._fire('follow_on' if followers or assisted else 'follow_off', '')
        self.detail = why + who_drives(followers, assisted)

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

    def _commands_now(self, t, actions):
        commands = {}
        for side in BAXTER_SIDES:
            if self.following[side]:
                angles = self.puppet.angles if side == self.own_side else mirror(
                    self.puppet.angles)
                commands[side] = self.drive.toward(side, t, angles)
            elif self.assist.assisted[side]:
                angles, changed, grip = self.assist.plan(side, t)
                actions.extend([Grip(side, grip)] if grip is not None else [])
                commands[side] = (self.drive.hold(side, t, changed) if angles is None
                                  else self.drive.toward(side, t, angles))
        return commands

    def step(self, t):
        """Advance to time t (s) and return the Step to carry out now."""
        self._last_step_t = t
        was_driven = self.driven()
        failure, self._failure = self._failure, None
        for event, detail in events(t, self.state, self._fault_t, self._robot_ok, self.puppet,
                                    failure):
            self._fire(event, detail)
        actions = []
        self._drop_claimed_arms(t)
        self._act_on_presses(t, actions)
        self._stop_for_new_meaning()   # after the presses: no press of this step outlives it
        went_limp = self.puppet_mode.step(t, self.state, self.following, self.puppet.state_t,
                                          actions)
        if went_limp:
            self.detail = '%s; %s' % (self.detail, went_limp)
        self._grip_actions(actions)
        held_before = self.zones.holding() or any(self.assist.holding.values())
        commands = self._commands_now(t, actions) if self.state == FOLLOWING else {}
        self.zones.forget(self.driven())
        held = '; '.join(filter(None, (self.zones.detail(), self.assist.hold_detail(t))))
        if held:
            self.detail = held
        elif held_before and self.state == FOLLOWING:
            self._after_follow_change('')   # the zone said so: say who follows again
        stopped = [s for s in BAXTER_SIDES if was_driven[s] and not self.driven()[s]]
        if self._robot_ok:   # not to a Baxter absent or disabled: its pose may be stale then
            commands.update({s: self.drive.stay(s, t) for s in stopped if s in self.robot.pose})
        return Step(commands, actions)
