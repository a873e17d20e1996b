"""Teleoperation state machine of one puppet arm (DESIGN section 6): pure, time as an argument.

The arm node feeds it puppet data (joint states, heartbeats, buttons, the end-piece reading) and
Baxter's state, calls step(t) at its command rate, and carries out what step returns: joint
positions for each following Baxter arm and actions (opmode, puppet setpoints, grippers).

Safety: Baxter follows nothing until all seven puppet encoders report Working; every command is
clamped to Baxter's joint limits and moves at most at a bounded speed (a slow approach when
following starts far from the puppet, then at most the joint's velocity limit); non-finite angles
are ignored; when the puppet's joint states or heartbeat stop, commands stop at once (Baxter then
holds by its own command timeout) and following resumes only after fresh data and a new press.
"""
import collections
import math

NO_ROBOT, CALIBRATING, READY, FOLLOWING, FAULT = (
    'no_robot', 'calibrating', 'ready', 'following', 'fault')
LIMP, HOLD = 'limp', 'hold'
SIDES = ('left', 'right')
MIRRORED_JOINTS = (0, 2, 4, 6)  # negated on the arm opposite the puppet's side
BUTTON_HOLD, BUTTON_LEFT, BUTTON_RIGHT = 1, 2, 3
GRIP_PRESSED_BELOW, GRIP_RELEASED_ABOVE = 0.3, 0.7  # end-piece reading, with hysteresis

# (state, event) -> next state. Events not listed for a state leave it unchanged.
TRANSITIONS = {
    (NO_ROBOT, 'robot_ok'): CALIBRATING,
    (CALIBRATING, 'robot_lost'): NO_ROBOT,
    (CALIBRATING, 'calibrated'): READY,
    (CALIBRATING, 'silent'): FAULT,
    (READY, 'robot_lost'): NO_ROBOT,
    (READY, 'uncalibrated'): CALIBRATING,
    (READY, 'follow_on'): FOLLOWING,
    (READY, 'silent'): FAULT,
    (FOLLOWING, 'robot_lost'): NO_ROBOT,
    (FOLLOWING, 'uncalibrated'): CALIBRATING,
    (FOLLOWING, 'follow_off'): READY,
    (FOLLOWING, 'silent'): FAULT,
    (FAULT, 'robot_lost'): NO_ROBOT,
    (FAULT, 'fresh'): CALIBRATING,
}
# Following is switched off on entering these states.
STOP_FOLLOWING = (NO_ROBOT, CALIBRATING, READY, FAULT)

SetOpmode = collections.namedtuple('SetOpmode', 'mode')
SetOpmode.__doc__ = 'Send the puppet opmode `mode` (limp or hold).'
SetSetpoints = collections.namedtuple('SetSetpoints', 'angles')
SetSetpoints.__doc__ = 'Send the puppet seven joint setpoints (rad).'
Grip = collections.namedtuple('Grip', 'side close')
Grip.__doc__ = "Close (close=True) or open Baxter's gripper on `side`."
Step = collections.namedtuple('Step', 'commands actions')
Step.__doc__ = """What to do now: commands {side: 7 joint positions rad} for the following
arms (empty when nothing may move), actions a list of SetOpmode, SetSetpoints and Grip."""


def mirror(angles):
    """Return puppet angles as the opposite Baxter arm takes them (joints 0, 2, 4, 6 negated)."""
    return [-a if j in MIRRORED_JOINTS else a for j, a in enumerate(angles)]


def clamp(angles, limits):
    """Return angles clamped to limits, a sequence of objects with lower and upper (rad)."""
    return [min(max(a, lim.lower), lim.upper) for a, lim in zip(angles, limits)]


def move_toward(current, target, max_steps):
    """Return current moved toward target by at most max_steps[j] on each joint j."""
    return [c + min(max(t - c, -m), m) for c, t, m in zip(current, target, max_steps)]


class Teleop:
    """Decide what Baxter and the puppet do, from what the puppet and Baxter report.

    Args:
        puppet_side: 'L' or 'R'; Baxter's arm on this side copies the puppet, the other mirrors.
        limits: {'left': 7 limits, 'right': 7 limits}, each with lower, upper (rad) and
            velocity (rad/s), in puppet joint order (see baxter_description.arm_limits).
        state_timeout_s: the puppet is silent when no joint states came for this long.
        heartbeat_timeout_s: ... or no heartbeat for this long (the firmware beats at 1 Hz).
        approach_speed_rad_s: joint speed while a following arm closes in on the puppet's pose.
        track_tolerance_rad: the approach ends when every joint is this close to the target.
        command_period_s: the nominal time between commands. A command may move a joint by
            speed x max(time since the last command, command_period_s): fresh puppet data that
            arrives just after a steady-stream command is still carried whole, not in slices.
    """

    def __init__(self, puppet_side, limits, state_timeout_s=0.3, heartbeat_timeout_s=2.5,
                 approach_speed_rad_s=0.5, track_tolerance_rad=0.02, command_period_s=0.01):
        if puppet_side not in ('L', 'R'):
            raise ValueError("puppet side must be 'L' or 'R', got %r" % (puppet_side,))
        self.own_side = 'left' if puppet_side == 'L' else 'right'
        self.limits = limits
        self.state_timeout_s = state_timeout_s
        self.heartbeat_timeout_s = heartbeat_timeout_s
        self.approach_speed_rad_s = approach_speed_rad_s
        self.track_tolerance_rad = track_tolerance_rad
        self.command_period_s = command_period_s
        self.state = NO_ROBOT
        self.detail = 'waiting for Baxter'
        self.opmode = LIMP
        self.following = {side: False for side in SIDES}
        self.tracking = {side: False for side in SIDES}  # False while approaching
        self.gripper_closed = False
        self._angles = None        # newest finite puppet angles (rad)
        self._statuses = []        # newest encoder statuses
        self._state_t = None       # time of the newest joint states
        self._heartbeat_t = None
        self._fault_t = None
        self._robot_ok = False
        self._robot_pose = {}      # side -> 7 angles (rad)
        self._commands = {}        # side -> 7 angles last commanded (rad)
        self._claimed = {side: False for side in SIDES}  # driven by the other puppet
        self._button = 0
        self._pressed = []         # button presses not yet acted on
        self._grip_reading = None
        self._last_step_t = None
        self.ignored_angles = 0    # non-finite angles dropped so far

    # ---- inputs --------------------------------------------------------------------------

    def on_joint_states(self, t, statuses, angles_rad):
        """Take one set of puppet joint states: 7 status strings and 7 angles (rad)."""
        if self._angles is None:
            self._angles = [0.0] * len(angles_rad)
        for j, angle in enumerate(angles_rad):
            if math.isfinite(angle):
                self._angles[j] = angle
            else:
                self.ignored_angles += 1
        self._statuses = list(statuses)
        self._state_t = t

    def on_heartbeat(self, t):
        """Take a puppet heartbeat."""
        self._heartbeat_t = t

    def on_button(self, t, button):
        """Take the puppet's user-button reading (1-4, 0 none); a press acts once."""
        if button != self._button and button != 0:
            self._pressed.append(button)
        self._button = button

    def on_end_piece(self, t, reading):
        """Take the end-piece button reading (gripper 3: about 1 released, 0 pressed)."""
        if math.isfinite(reading):
            self._grip_reading = reading

    def on_other_puppet(self, t, follow_left, follow_right):
        """Take which Baxter arms the other puppet drives; this one will not take them too."""
        self._claimed = {'left': follow_left, 'right': follow_right}

    def on_robot(self, t, enabled, pose):
        """Take Baxter's state: enabled (bool) and {side: 7 joint angles rad} of its arms."""
        self._robot_ok = enabled
        self._robot_pose.update(pose)

    # ---- decisions -----------------------------------------------------------------------

    def heartbeat_age(self, t):
        """Return seconds since the last heartbeat, or -1.0 before the first."""
        return -1.0 if self._heartbeat_t is None else t - self._heartbeat_t

    def _silent(self, t):
        if self._state_t is None or self._heartbeat_t is None:
            return None
        if t - self._state_t > self.state_timeout_s:
            return 'no joint states from the puppet for %.2f s' % (t - self._state_t)
        if t - self._heartbeat_t > self.heartbeat_timeout_s:
            return 'no heartbeat from the puppet for %.2f s' % (t - self._heartbeat_t)
        return None

    def _fire(self, event, detail):
        new = TRANSITIONS.get((self.state, event))
        if new is None:
            if self.state == CALIBRATING and event == 'uncalibrated':
                self.detail = detail  # which joints are still missing
            return
        if new in STOP_FOLLOWING:
            self.following = {side: False for side in SIDES}
        if new == FAULT:
            self._fault_t = self._last_step_t
        self.state = new
        self.detail = detail

    def _events(self, t):
        """Yield (event, detail) for what changed since the last step."""
        silent = self._silent(t)
        if not self._robot_ok:
            yield 'robot_lost', 'Baxter is absent or not enabled'
        else:
            yield 'robot_ok', 'Baxter enabled'
        if silent:
            yield 'silent', silent
        elif self.state == FAULT and self._state_t > self._fault_t \
                and self._heartbeat_t > self._fault_t:
            yield 'fresh', 'puppet data is back; press 2 or 3 to follow again'
        if self._state_t is not None and not silent:
            waiting = {}
            for joint, status in enumerate(self._statuses):
                if status != 'Working':
                    waiting.setdefault(status, []).append(str(joint))
            if waiting:
                yield 'uncalibrated', '; '.join(
                    'joint%s %s %s' % ('s' if len(joints) > 1 else '', ', '.join(joints), status)
                    for status, joints in sorted(waiting.items())) + (
                    ': turn each through its index mark' if 'Uncalibrated' in waiting else '')
            else:
                yield 'calibrated', 'all joints Working; press 2 or 3 to follow'

    def _act_on_presses(self, actions):
        for button in self._pressed:
            if self.state not in (READY, FOLLOWING):
                continue  # a press in any other state does nothing, not even later
            if button == BUTTON_HOLD:
                self._toggle_hold(actions)
            elif button in (BUTTON_LEFT, BUTTON_RIGHT):
                side = 'left' if button == BUTTON_LEFT else 'right'
                self._toggle_follow(side)
        self._pressed = []

    def _toggle_hold(self, actions):
        if self.opmode == LIMP:
            pose = self._robot_pose.get(self.own_side)
            if pose is None:
                return
            self.opmode = HOLD
            actions.append(SetOpmode(HOLD))
            actions.append(SetSetpoints(list(pose)))  # the puppet moves to the robot
        else:
            self.opmode = LIMP
            actions.append(SetOpmode(LIMP))

    def _toggle_follow(self, side):
        if self.following[side]:
            self.following[side] = False
        elif self._claimed[side]:
            self.detail = 'the other puppet drives Baxter\'s %s arm already' % side
            return
        elif side in self._robot_pose:
            self.following[side] = True
            self.tracking[side] = False
            self._commands[side] = clamp(self._robot_pose[side], self.limits[side])
        followers = [s for s in SIDES if self.following[s]]
        self._fire('follow_on' if followers else 'follow_off', '')
        self.detail = ('Baxter follows with its %s arm%s' % (' and '.join(followers),
                                                             's' if len(followers) > 1 else '')
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
        actions.extend(Grip(side, self.gripper_closed) for side in SIDES if self.following[side])

    def _commands_now(self, dt):
        commands = {}
        for side in SIDES:
            if not self.following[side]:
                continue
            angles = self._angles if side == self.own_side else mirror(self._angles)
            target = clamp(angles, self.limits[side])
            current = self._commands[side]
            if self.tracking[side]:
                max_steps = [lim.velocity * dt for lim in self.limits[side]]
            else:
                max_steps = [self.approach_speed_rad_s * dt] * len(target)
            command = clamp(move_toward(current, target, max_steps), self.limits[side])
            if max(abs(c - g) for c, g in zip(command, target)) <= self.track_tolerance_rad:
                self.tracking[side] = True
            self._commands[side] = command
            commands[side] = command
        return commands

    def step(self, t):
        """Advance to time t (s) and return the Step to carry out now."""
        dt = 0.0 if self._last_step_t is None else min(max(t - self._last_step_t,
                                                            self.command_period_s), 0.1)
        self._last_step_t = t
        for event, detail in self._events(t):
            self._fire(event, detail)
        actions = []
        if self.state == FAULT and self.opmode == HOLD:
            # A silent puppet gets no setpoints: let it go limp, as a reconnect does anyway.
            self.opmode = LIMP
            actions.append(SetOpmode(LIMP))
        self._act_on_presses(actions)
        self._grip_actions(actions)
        commands = self._commands_now(dt) if self.state == FOLLOWING else {}
        return Step(commands, actions)
