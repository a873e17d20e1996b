"""The gamepad and the SpaceMouse as study devices: a Cartesian velocity of the gripper (pure).

Both give a twist in Baxter's base frame (x forward, away from Baxter's front; y to Baxter's
left; z up): (vx, vy, vz m/s, wx, wy, wz rad/s), which study.cartesian turns into joint steps.

Gamepad (one per participant, a stick per arm): stick up = +x, stick right = -y (to Baxter's
right), the shoulder button +z while down, the trigger -z in proportion; the gripper keeps its
orientation. SpaceMouse (6 axes, full deflection 350) in the kernel's axes of 3Dconnexion
devices (evdev): x right, y toward the user, z down, each turn right-handed about its axis (rx +
tilts the cap back, ry + rolls it left, rz + turns it right seen from above); spacenavd reports
the same device as x right, y up, z away. The user faces the way Baxter faces, so pushing the cap
away = +x, right = -y, up = +z, and the gripper turns as the cap turns. For side L the motion is
mirrored (y, roll and yaw negated): one SpaceMouse read by both sides moves the arms
symmetrically.
"""
from evdev import ecodes as e

from robopuppet import interface

STICK = {'L': (e.ABS_X, e.ABS_Y), 'R': (e.ABS_RX, e.ABS_RY)}
UP = {'L': e.BTN_TL, 'R': e.BTN_TR}
DOWN = {'L': e.ABS_Z, 'R': e.ABS_RZ}
FOLLOW = {'L': e.BTN_WEST, 'R': e.BTN_EAST}
GRIP = {'L': e.BTN_NORTH, 'R': e.BTN_SOUTH}
STICK_RANGE, TRIGGER_RANGE = (-32768, 32767), (0, 255)   # when the device gives no absinfo
DEAD_ZONE = 0.1               # of full deflection
DEFAULT_MAX_SPEED = 0.15      # m/s at full deflection
DEFAULT_MAX_TURN = 0.6        # rad/s at full deflection (SpaceMouse)
SPACEMOUSE_FULL = 350.0       # a SpaceMouse axis's full deflection
# Device axis (REL_X..REL_RZ, and ABS_X..ABS_RZ: the same codes 0..5) -> (twist component,
# sign): the device frame (right, toward the user, down) turned into Baxter's (forward, left, up)
SPACE_TWIST = {0: (1, -1.0), 1: (0, -1.0), 2: (2, -1.0), 3: (4, -1.0), 4: (3, -1.0),
               5: (5, -1.0)}
MIRROR_L = (1.0, -1.0, 1.0, -1.0, 1.0, -1.0)   # y, roll and yaw negated
SPACE_FOLLOW, SPACE_GRIP = e.BTN_0, e.BTN_1


def dead_zone(fraction):
    """Return a deflection in -1..1 with the dead zone cut out and the rest scaled to 0..1."""
    size = abs(fraction)
    if size <= DEAD_ZONE:
        return 0.0
    return min(1.0, (size - DEAD_ZONE) / (1.0 - DEAD_ZONE)) * (1.0 if fraction > 0 else -1.0)


def centred(value, low, high):
    """Return value in [low, high] as -1..1 (the middle 0)."""
    return max(-1.0, min(1.0, 2.0 * (value - low) / float(high - low) - 1.0))


class Buttons:
    """The follow button (down = pressed) and a grip button (each press toggles)."""

    def __init__(self, follow_code, grip_code):
        self._follow_code, self._grip_code = follow_code, grip_code
        self.follow, self.closed = False, False

    def on_key(self, event):
        """Take an EV_KEY event; return whether it was one of the two buttons."""
        if event.code == self._follow_code:
            self.follow = event.value != 0
        elif event.code == self._grip_code:
            if event.value == 1:
                self.closed = not self.closed
        else:
            return False
        return True


class Gamepad(Buttons):
    """The gamepad's stick, shoulder button and trigger of one side as a twist.

    Args:
        side: 'L' or 'R'.
        max_speed: m/s at full deflection.
        ranges: {ABS code: (min, max)} from the device's absinfo; missing codes: the defaults.
    """

    JOINT_SPACE = False

    def __init__(self, side, max_speed=DEFAULT_MAX_SPEED, ranges=None):
        interface.check_side(side)
        super().__init__(FOLLOW[side], GRIP[side])
        if not max_speed > 0.0:
            raise ValueError('max speed must be positive, got %r' % (max_speed,))
        ranges = ranges or {}
        self._x, self._y = STICK[side]
        self._up, self._down = UP[side], DOWN[side]
        self._ranges = {code: ranges.get(code, STICK_RANGE) for code in STICK[side]}
        self._ranges[self._down] = ranges.get(self._down, TRIGGER_RANGE)
        self._speed = float(max_speed)
        self._axes = {code: 0.0 for code in self._ranges}   # -1..1 (trigger 0..1)
        self._up_down = False

    def on_event(self, event):
        """Take one InputEvent; other codes are ignored."""
        if event.type == e.EV_KEY and not self.on_key(event) and event.code == self._up:
            self._up_down = event.value != 0
        elif event.type == e.EV_ABS and event.code in self._ranges:
            low, high = self._ranges[event.code]
            if event.code == self._down:
                value = max(0.0, min(1.0, (event.value - low) / float(high - low)))
            else:
                value = centred(event.value, low, high)
            self._axes[event.code] = dead_zone(value)

    def velocity(self):
        """Return the twist (vx, vy, vz m/s, 0, 0, 0): the gripper keeps its orientation."""
        vz = (1.0 if self._up_down else 0.0) - self._axes[self._down]
        return [-self._axes[self._y] * self._speed, -self._axes[self._x] * self._speed,
                vz * self._speed, 0.0, 0.0, 0.0]


class SpaceMouse(Buttons):
    """A SpaceMouse's six axes as a twist (REL_ or ABS_ events); BTN_0 follow, BTN_1 grip.

    Args:
        side: 'L' (mirrored) or 'R'.
        max_speed: m/s, max_turn: rad/s, at full deflection (350).
    """

    JOINT_SPACE = False
    SHARED_FOLLOW = True   # one SpaceMouse serves both sides: its follow button acts on both

    def __init__(self, side, max_speed=DEFAULT_MAX_SPEED, max_turn=DEFAULT_MAX_TURN):
        interface.check_side(side)
        super().__init__(SPACE_FOLLOW, SPACE_GRIP)
        if not (max_speed > 0.0 and max_turn > 0.0):
            raise ValueError('max speed and turn must be positive, got %r, %r' % (
                max_speed, max_turn))
        self._scale = [float(max_speed)] * 3 + [float(max_turn)] * 3
        self._mirror = MIRROR_L if side == 'L' else (1.0,) * 6
        self._axes = [0.0] * 6   # device axes, -1..1 after the dead zone

    def on_event(self, event):
        """Take one InputEvent; other codes are ignored. A value is the deflection now."""
        if event.type == e.EV_KEY:
            self.on_key(event)
        elif event.type in (e.EV_REL, e.EV_ABS) and event.code in SPACE_TWIST:
            self._axes[event.code] = dead_zone(event.value / SPACEMOUSE_FULL)

    def velocity(self):
        """Return the twist (vx, vy, vz m/s, wx, wy, wz rad/s) in Baxter's base frame."""
        twist = [0.0] * 6
        for axis, (component, sign) in SPACE_TWIST.items():
            twist[component] = sign * self._axes[axis] * self._scale[component]
        return [value * mirror for value, mirror in zip(twist, self._mirror)]
