"""The simulated participant's hands on each study device (pure).

Each class turns the participant's intentions (press follow, set the gripper, move an arm along
a reference toward its goal) into the device's own outputs: evdev events of key_jog's and
pad_axes' tables (keyboard, gamepad, SpaceMouse), interactive-marker poses and menu selects
(marker), hand angles, follow presses and end-piece grips (puppet). Time is an argument.
"""
import collections

import numpy as np
from evdev import ecodes as e

from robopuppet import baxter_description as bd, interface
from robopuppet.baxter_sim.baxter_ik import rotation_error
from robopuppet.study import key_jog, pad_axes

Event = collections.namedtuple('Event', 'type code value')   # to each trial side's source
MarkerPose = collections.namedtuple('MarkerPose', 'side xyz quat')   # POSE_UPDATE feedback
MarkerMenu = collections.namedtuple('MarkerMenu', 'side entry')      # MENU_SELECT feedback
Hand = collections.namedtuple('Hand', 'side angles')      # the puppet shows Baxter angles
Press = collections.namedtuple('Press', 'side')           # the puppet's follow button, once
EndPiece = collections.namedtuple('EndPiece', 'side closed')   # the puppet's end-piece button
Calibrate = collections.namedtuple('Calibrate', 'side angles')  # turn through the index marks
Want = collections.namedtuple(
    'Want', 'xyz velocity rotation turn tip tip_rotation joints goal_joints angles hold')
Want.__doc__ = """Where one arm should be now: the reference xyz (m) and velocity (m/s),
rotation (3x3) and angular velocity turn (rad/s, base) of its tip, the measured tip and
tip_rotation, the reference joints and the goal's
joints (7 rad, None for a Cartesian device), the measured angles, and hold (on the goal: keep
still)."""

SIDE = {'left': 'L', 'right': 'R'}
MENU_FOLLOW, MENU_CLOSE, MENU_OPEN = 1, 2, 3    # marker_device.MENU's entries
PRESS_S = 0.2            # a button or key is held down this long for one press
# Cartesian correction: m/s per m off the reference, small: the arm lags the device's target
# (arm_X's leash, Baxter's speed), and a person who pushed on while it lagged would overshoot;
# what is left after a reach is corrected by the next (participant.SETTLE_S)
GAIN_PER_S = 0.5
TURN_GAIN_PER_S = 0.3    # rad/s per rad off the reference orientation
SLOWEST = 0.02           # a wanted speed below this fraction of full deflection: let go
KEY_DEADBAND_RAD = 0.01  # a joint this near its goal gets no more taps
KEY_SETTLE_S = 0.3       # after a tap, watch the arm this long before the next tap of the joint
MAX_TAP_S = 1.5          # the longest single key press; then look again
KEYS_AT_ONCE = 4         # the joints furthest from their goals get their keys at once
PWM_PERIOD_S = 0.2       # the +z button is pressed this share of each period for a slow +z
MARKER_PERIOD_S = 0.05   # a mouse drag sends a pose this often
PUPPET_RAD_S = 0.6       # the hand's peak joint speed on the puppet
SPEEDS = {'jog_speed': key_jog.DEFAULT_JOG_SPEED, 'max_speed': pad_axes.DEFAULT_MAX_SPEED,
          'max_turn': pad_axes.DEFAULT_MAX_TURN}   # the devices' own, by default


def reach_time(device, distance_m, turn_rad, joints_rad, speeds):
    """Return the duration (s) of a reach: Fitts-like, and never faster than the device."""
    fitts = 0.6 + 1.5 * distance_m + 0.3 * turn_rad
    if device == 'keyboard':
        return max(fitts, joints_rad / speeds['jog_speed'])
    if device == 'puppet':
        return max(fitts, 1.875 * joints_rad / PUPPET_RAD_S)
    if device == 'marker':
        return fitts
    # minimum jerk peaks at 1.875 times the mean speed: stay within 80 % of full deflection
    return max(fitts, 1.875 * distance_m / (0.8 * speeds['max_speed']),
               1.875 * turn_rad / (0.8 * speeds['max_turn']))


class Hands:
    """A device's controls in a participant's hands; the base keeps timed releases.

    Attributes: joint_space (drives from joint goals: needs IK), turns (controls the gripper's
    orientation), shared (one control serves every side: follow and grip act on all),
    toggles (a grip control toggles; else it sets open or closed).
    """

    joint_space, turns, shared, toggles = False, True, False, True

    def __init__(self):
        self._later = []

    def due(self, t):
        """Return the actions scheduled for t or before (releases of presses)."""
        now = [a for when, a in self._later if when <= t]
        self._later = [(when, a) for when, a in self._later if when > t]
        return now

    def _tap(self, code, t, hold_s=PRESS_S):
        self._later.append((t + hold_s, Event(e.EV_KEY, code, 0)))
        return [Event(e.EV_KEY, code, 1)]

    def calibrate(self, arm, angles):
        """Return the actions that get an uncalibrated device working ([]: none needed)."""
        return []

    def rest(self, t):
        """Return the actions that let go of everything (between trials)."""
        return self.due(float('inf'))


def cartesian_velocity(want):
    """Return the tip velocity (m/s) that tracks the reference: feed-forward plus correction."""
    if want.hold:
        return np.zeros(3)
    return np.asarray(want.velocity) + GAIN_PER_S * (np.asarray(want.xyz) - want.tip)


def deflection(speed, full):
    """Return the deflection (-1..1) beyond the 10 % dead zone that asks for `speed`."""
    share = min(abs(speed) / full, 1.0)
    if share < SLOWEST:
        return 0.0
    return np.sign(speed) * (pad_axes.DEAD_ZONE + (1.0 - pad_axes.DEAD_ZONE) * share)


class KeyboardHands(Hands):
    """Joint jogging by taps: each key held as long as its joint's error asks at jog_speed."""

    joint_space = True

    def __init__(self, jog_speed=key_jog.DEFAULT_JOG_SPEED, rng=None):
        super().__init__()
        self._speed, self._rng = jog_speed, rng or np.random.default_rng(0)
        self._down = {}     # (side, joint) -> (code, release_t)
        self._settle = {}   # (side, joint) -> no new tap before this t

    def follow(self, arms, t, angles):
        return [a for arm in arms for a in self._tap(key_jog.FOLLOW_KEY[SIDE[arm]], t)]

    def grip(self, arms, closed, t):
        return [a for arm in arms for a in self._tap(key_jog.GRIP_KEY[SIDE[arm]], t)]

    def drive(self, t, wants):
        out = []
        for (side, joint), (code, release_t) in list(self._down.items()):
            if t >= release_t:
                out.append(Event(e.EV_KEY, code, 0))
                del self._down[(side, joint)]
        for arm, want in wants.items():
            if want.goal_joints is None or want.hold:
                continue
            side = SIDE[arm]
            error = np.subtract(want.goal_joints, want.angles)
            busy = sum(1 for s, _ in self._down if s == side)
            for joint in np.argsort(-np.abs(error)):
                key = (side, int(joint))
                if (busy >= KEYS_AT_ONCE or key in self._down or abs(error[joint]) <
                        KEY_DEADBAND_RAD or t < self._settle.get(key, -np.inf)):
                    continue
                plus, minus = key_jog.KEYS[side][joint]
                hold_s = min(abs(error[joint]) / self._speed, MAX_TAP_S)
                hold_s *= 1.0 + 0.05 * self._rng.standard_normal()
                code = plus if error[joint] > 0 else minus
                self._down[key] = (code, t + hold_s)
                self._settle[key] = t + hold_s + KEY_SETTLE_S
                out.append(Event(e.EV_KEY, code, 1))
                busy += 1
        return out

    def rest(self, t):
        out = [Event(e.EV_KEY, code, 0) for code, _ in self._down.values()]
        self._down.clear()
        return super().rest(t) + out


class GamepadHands(Hands):
    """A stick per arm for x and y, the shoulder button (pulsed when slow) and trigger for z."""

    turns = False

    def __init__(self, max_speed=pad_axes.DEFAULT_MAX_SPEED):
        super().__init__()
        self._speed, self._sent = max_speed, {}

    def follow(self, arms, t, angles):
        return [a for arm in arms for a in self._tap(pad_axes.FOLLOW[SIDE[arm]], t)]

    def grip(self, arms, closed, t):
        return [a for arm in arms for a in self._tap(pad_axes.GRIP[SIDE[arm]], t)]

    def _set(self, kind, code, value):
        if self._sent.get((kind, code)) == value:
            return []
        self._sent[(kind, code)] = value
        return [Event(kind, code, value)]

    def drive(self, t, wants):
        out = []
        for arm, want in wants.items():
            side = SIDE[arm]
            vx, vy, vz = cartesian_velocity(want)
            (low, high), (t_low, t_high) = pad_axes.STICK_RANGE, pad_axes.TRIGGER_RANGE
            x_code, y_code = pad_axes.STICK[side]
            for code, speed in ((y_code, -vx), (x_code, -vy)):
                value = (low + high) / 2.0 + deflection(speed, self._speed) * (high - low) / 2.0
                out += self._set(e.EV_ABS, code, int(round(value)))
            down = max(0.0, deflection(-vz, self._speed))
            out += self._set(e.EV_ABS, pad_axes.DOWN[side],
                             int(round(t_low + down * (t_high - t_low))))
            duty = min(max(vz, 0.0) / self._speed, 1.0)
            pressed = duty >= SLOWEST and (t % PWM_PERIOD_S) < duty * PWM_PERIOD_S
            out += self._set(e.EV_KEY, pad_axes.UP[side], int(pressed))
        return out

    def rest(self, t):
        out = [Event(kind, code, 0) for (kind, code), value in self._sent.items() if value]
        self._sent.clear()
        return super().rest(t) + out


class SpaceMouseHands(Hands):
    """Six axes sent every step; one SpaceMouse serves both sides (side L sees it mirrored), so
    the arms get the twist that suits them best together."""

    shared = True

    def __init__(self, max_speed=pad_axes.DEFAULT_MAX_SPEED, max_turn=pad_axes.DEFAULT_MAX_TURN):
        super().__init__()
        self._full = [max_speed] * 3 + [max_turn] * 3

    def follow(self, arms, t, angles):
        return self._tap(pad_axes.SPACE_FOLLOW, t)

    def grip(self, arms, closed, t):
        return self._tap(pad_axes.SPACE_GRIP, t)

    def drive(self, t, wants):
        twists = []
        for arm, want in wants.items():
            turn = (np.zeros(3) if want.hold else np.asarray(want.turn) + TURN_GAIN_PER_S
                    * rotation_error(want.rotation, want.tip_rotation))
            twist = np.concatenate([cartesian_velocity(want), turn])
            twists.append(twist * (pad_axes.MIRROR_L if arm == 'left' else 1.0))
        twist = np.mean(twists, axis=0) if twists else np.zeros(6)
        return [Event(e.EV_REL, axis, int(round(pad_axes.SPACEMOUSE_FULL * deflection(
            sign * twist[component], self._full[component]))))
            for axis, (component, sign) in sorted(pad_axes.SPACE_TWIST.items())]

    def rest(self, t):
        return super().rest(t) + [Event(e.EV_REL, axis, 0) for axis in pad_axes.SPACE_TWIST]


class MarkerHands(Hands):
    """The gripper marker dragged along the reference; the menu for follow and grip."""

    toggles = False

    def __init__(self):
        super().__init__()
        self._sent_t = {}

    def follow(self, arms, t, angles):
        return [MarkerMenu(SIDE[arm], MENU_FOLLOW) for arm in arms]

    def grip(self, arms, closed, t):
        return [MarkerMenu(SIDE[arm], MENU_CLOSE if closed else MENU_OPEN) for arm in arms]

    def drive(self, t, wants):
        out = []
        for arm, want in wants.items():
            if want.hold or t < self._sent_t.get(arm, -np.inf) + MARKER_PERIOD_S:
                continue
            self._sent_t[arm] = t
            out.append(MarkerPose(SIDE[arm], tuple(want.xyz),
                                  bd.matrix_quaternion(want.rotation)))
        return out


class PuppetHands(Hands):
    """The hand poses the simulated puppet along the joint path; its buttons as they are."""

    joint_space, toggles = True, False

    def follow(self, arms, t, angles):
        # The hand first shows where Baxter is, so that following starts without a jump.
        return [a for arm in arms for a in (Hand(SIDE[arm], tuple(angles[arm])),
                                            Press(SIDE[arm]))]

    def grip(self, arms, closed, t):
        return [EndPiece(SIDE[arm], closed) for arm in arms]

    def calibrate(self, arm, angles):
        return [Calibrate(SIDE[arm], tuple(angles))]

    def drive(self, t, wants):
        return [Hand(SIDE[arm], tuple(want.joints)) for arm, want in wants.items()
                if want.joints is not None]


def make_hands(device, rng, jog_speed=key_jog.DEFAULT_JOG_SPEED,
               max_speed=pad_axes.DEFAULT_MAX_SPEED, max_turn=pad_axes.DEFAULT_MAX_TURN):
    """Return the Hands of a study device (interface.STUDY_DEVICES; ValueError: another)."""
    makers = {'keyboard': lambda: KeyboardHands(jog_speed, rng),
              'gamepad': lambda: GamepadHands(max_speed),
              'spacemouse': lambda: SpaceMouseHands(max_speed, max_turn),
              'marker': MarkerHands, 'puppet': PuppetHands}
    if device not in makers or device not in interface.STUDY_DEVICES:
        raise ValueError('no such study device: %r' % (device,))
    return makers[device]()
