"""The keyboard as a study device: joint jogging while a key is down (pure).

Each joint has a plus and a minus key per puppet side, so one keyboard serves two arms; the
follow key acts as the puppet's follow button (down = pressed) and the grip key toggles the
gripper. Values as the kernel sends them: 1 press, 2 autorepeat (still down), 0 release.
"""
from evdev import ecodes as e

from robopuppet import interface, settings

KEYS = {'L': list(zip((e.KEY_1, e.KEY_2, e.KEY_3, e.KEY_4, e.KEY_5, e.KEY_6, e.KEY_7),
                      (e.KEY_Q, e.KEY_W, e.KEY_E, e.KEY_R, e.KEY_T, e.KEY_Y, e.KEY_U))),
        'R': list(zip((e.KEY_A, e.KEY_S, e.KEY_D, e.KEY_F, e.KEY_G, e.KEY_H, e.KEY_J),
                      (e.KEY_Z, e.KEY_X, e.KEY_C, e.KEY_V, e.KEY_B, e.KEY_N, e.KEY_M)))}
FOLLOW_KEY = {'L': e.KEY_F2, 'R': e.KEY_F3}
GRIP_KEY = {'L': e.KEY_TAB, 'R': e.KEY_SPACE}
DEFAULT_JOG_SPEED = 0.4   # rad/s


class KeyJog:
    """Joint velocities, follow and grip of one side from key events.

    Args:
        side: the puppet side, 'L' or 'R' (its key table).
        jog_speed: rad/s of a joint while its key is down (positive).
    """

    JOINT_SPACE = True

    def __init__(self, side, jog_speed=DEFAULT_JOG_SPEED):
        if not jog_speed > 0.0:
            raise ValueError('jog speed must be positive, got %r' % (jog_speed,))
        interface.check_side(side)
        self._joint_of = {}
        for joint, (plus, minus) in enumerate(KEYS[side]):
            self._joint_of[plus], self._joint_of[minus] = (joint, 1.0), (joint, -1.0)
        self._follow_key, self._grip_key = FOLLOW_KEY[side], GRIP_KEY[side]
        self._speed = float(jog_speed)
        self._down = set()
        self.follow = False   # the follow button is pressed
        self.closed = False   # the gripper should be closed

    def on_event(self, event):
        """Take one InputEvent; other types and keys are ignored."""
        if event.type != e.EV_KEY:
            return
        down = event.value != 0
        if event.code == self._follow_key:
            self.follow = down
        elif event.code == self._grip_key:
            if event.value == 1:
                self.closed = not self.closed
        elif event.code in self._joint_of:
            (self._down.add if down else self._down.discard)(event.code)

    def velocity(self):
        """Return the 7 joint velocities (rad/s) the keys held ask for (plus and minus cancel)."""
        speeds = [0.0] * settings.NUM_JOINTS
        for code in self._down:
            joint, sign = self._joint_of[code]
            speeds[joint] += sign * self._speed
        return speeds
