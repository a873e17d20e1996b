"""One study device in the puppet's place: its events and Baxter's pose -> the puppet's outputs.

Pure: time is an argument. The device node (study.device_node) feeds it the device's events,
Baxter's measured angles of the arm the side drives (interface.BAXTER_SIDE) and whether arm_X
says that arm follows, and publishes what each step returns exactly as serial_X would: seven
angles, the follow button of the side, the end piece's reading.

While the arm does not follow, the target is Baxter's measured pose, so a follow press never
makes the arm jump; while it follows, the device moves the target from there: joint velocities
(keyboard) integrated, a twist (gamepad, SpaceMouse) turned into a joint step (study.cartesian),
or a pose solved elsewhere (marker: set_target). The target stays within the joint limits and
finite: nothing non-finite is ever handed out; a moved target leads Baxter's measured arm by at
most MAX_LEAD_RAD per joint, so that an arm held back (a keep-out zone) answers at once when the
user turns back. A follow control shared by both sides (one SpaceMouse) stops every arm when one
follows and else starts every arm: each side passes a press on only when it brings its own arm
there, so the two arms never stay split.
"""
import collections
import math

import numpy as np

from robopuppet import interface

PRESS_S = 0.2        # a follow press made by a menu (marker) holds the button this long
MAX_STEP_S = 0.1     # a longer gap between steps (a stopped process) moves no further than this
MAX_LEAD_RAD = 0.25  # a moved target leads Baxter's measured arm by at most this, per joint
RELEASED, PRESSED = 1.0, 0.0   # the end piece's reading: released (gripper open), pressed

Output = collections.namedtuple('Output', 'positions button grippers')
Output.__doc__ = """A step's outputs: positions (7 rad, puppet joint order, or None before Baxter's
pose is known), button (the side's follow button while pressed, else 0), grippers (the four
readings: the end piece's PRESSED while the gripper should be closed, else RELEASED; others 0)."""


class DeviceCore:
    """Turn a device's controls into the puppet's outputs of one side.

    Args:
        side: 'L' or 'R'.
        controls: a key_jog.KeyJog, pad_axes.Gamepad or pad_axes.SpaceMouse (on_event,
            velocity, follow, closed, JOINT_SPACE), or None for a device that sets its target
            itself (the marker).
        arm: a cartesian.CartesianArm of Baxter's arm interface.BAXTER_SIDE[side] (its limits;
            its step for a Cartesian device).
    """

    def __init__(self, side, controls, arm):
        self._button = (interface.BUTTON_LEFT if interface.check_side(side) == 'L'
                        else interface.BUTTON_RIGHT)
        self._controls, self._arm = controls, arm
        self._measured = None
        self._target = None
        self._following = self._other_following = False
        self._follow_down, self._pass_on = False, True   # the controls' follow; passed on
        self._last_s = None
        self._press_until_s = -math.inf
        self._closed = False

    def on_events(self, events):
        """Take the device's InputEvents (study.input_events) in order."""
        for event in events:
            self._controls.on_event(event)

    def on_robot(self, positions):
        """Take Baxter's measured angles of the driven arm (7 rad); a non-finite one is ignored."""
        positions = np.asarray(positions, dtype=float)
        if positions.shape == (7,) and np.all(np.isfinite(positions)):
            self._measured = positions

    def on_teleop(self, following):
        """Take whether arm_X says the driven arm follows now."""
        self._following = bool(following)

    def on_other_teleop(self, following):
        """Take whether the other side's arm controller says its arm follows now."""
        self._other_following = bool(following)

    def press_follow(self, t):
        """Press the follow button once, at t (s): held for PRESS_S."""
        self._press_until_s = t + PRESS_S

    def set_closed(self, closed):
        """Set the gripper wanted closed (True) or open (False), for a device without controls."""
        self._closed = bool(closed)

    def set_target(self, positions):
        """Set the target (7 rad) while the arm follows; return whether it was taken (finite,
        following); it is clipped into the joint limits."""
        positions = np.asarray(positions, dtype=float)
        if not (self._following and positions.shape == (7,) and np.all(np.isfinite(positions))):
            return False
        self._target = self._arm.clip(positions)
        return True

    def target(self):
        """Return the target now (7 rad; None before Baxter's pose is known)."""
        return None if self._target is None else self._target.copy()

    def following(self):
        """Return whether arm_X said last that the driven arm follows."""
        return self._following

    def step(self, t):
        """Return the Output at t (s): the target moved on by the controls since the last step."""
        dt_s = 0.0 if self._last_s is None else min(max(t - self._last_s, 0.0), MAX_STEP_S)
        self._last_s = t
        if not self._following or self._target is None:
            self._target = self._measured
        elif self._controls is not None and dt_s > 0.0:
            velocity = np.nan_to_num(np.asarray(self._controls.velocity(), dtype=float))
            if self._controls.JOINT_SPACE:
                moved = self._target + velocity * dt_s
            else:
                moved = self._arm.step(self._target, velocity, dt_s)
            if np.all(np.isfinite(moved)) and self._measured is not None:
                self._target = self._arm.clip(np.clip(moved, self._measured - MAX_LEAD_RAD,
                                                      self._measured + MAX_LEAD_RAD))
        controls = self._controls
        follow = controls is not None and controls.follow
        if follow and not self._follow_down:   # a press: a shared one stops all or starts all
            self._pass_on = not getattr(controls, 'SHARED_FOLLOW', False) or (
                self._following or not self._other_following)
        self._follow_down = follow
        pressed = t < self._press_until_s or (follow and self._pass_on)
        closed = controls.closed if controls is not None else self._closed
        grippers = [0.0] * interface.NUM_GRIPPERS
        grippers[interface.END_PIECE_GRIPPER] = PRESSED if closed else RELEASED
        positions = None if self._target is None else tuple(float(v) for v in self._target)
        return Output(positions, self._button if pressed else 0, tuple(grippers))
