"""Bounded joint motion for Baxter commands: clamping to joint limits and a speed budget.

Pure: angles in rad, speeds in rad/s, times in s passed as arguments.
"""
import math

MIRRORED_JOINTS = (0, 2, 4, 6)  # negated on the Baxter arm opposite the puppet's side


def mirror(angles):
    """Return puppet angles as the opposite Baxter arm takes them (joints 0, 2, 4, 6 negated)."""
    return [-a if j in MIRRORED_JOINTS else a for j, a in enumerate(angles)]


def driven_arm(own_side, follow_left, follow_right):
    """Return the Baxter arm ('left' or 'right') whose pose a puppet feels and shows: the only
    one following it, else the arm on its own side (own_side) when both or neither follow."""
    if follow_left != follow_right:
        return 'left' if follow_left else 'right'
    return own_side


def in_puppet_space(own_side, arm, angles):
    """Return Baxter arm `arm`'s angles (rad) as a puppet on Baxter's side own_side takes them:
    as they are on its own side, mirrored on the other (mirror is its own inverse)."""
    return list(angles) if arm == own_side else mirror(angles)


def clamp(angles, limits):
    """Return angles clamped to limits, a sequence of objects with lower and upper (rad)."""
    return [min(max(a, lim.lower), lim.upper) for a, lim in zip(angles, limits)]


def all_finite(angles):
    """Return True when every angle is a finite number."""
    return all(math.isfinite(a) for a in angles)


class SpeedBudget:
    """Move commands toward targets no faster than a speed per joint, without slicing moves.

    Each joint has a budget of travel that refills at its speed up to speed x burst_s and is
    spent by each move. Over any interval of T seconds a joint moves at most speed x (T +
    burst_s), however the commands are spaced in time; a move that fits the burst goes out in
    one command even when it comes right after another command (fresh puppet data arriving just
    after a steady-stream command).

    Args:
        command: the starting command (rad), e.g. where the robot is.
        burst_s: the budget's capacity in seconds of motion, normally one command period.
        t: the current time (s).
    """

    def __init__(self, command, burst_s, t):
        self.command = list(command)
        self._burst_s = burst_s
        self._budget = None  # rad per joint; full at the first move
        self._t = t

    def move(self, target, speeds, t):
        """Return the command moved toward target at most as far as the budget allows.

        Args:
            target: the wanted angles (rad).
            speeds: the speed per joint (rad/s) at which the budget refills.
            t: the current time (s); a time before the previous call counts as no time.
        """
        dt = max(t - self._t, 0.0)
        self._t = max(t, self._t)
        caps = [speed * self._burst_s for speed in speeds]
        if self._budget is None:
            self._budget = list(caps)
        else:
            self._budget = [min(b + speed * dt, cap)
                            for b, speed, cap in zip(self._budget, speeds, caps)]
        moved = []
        for j, (current, wanted) in enumerate(zip(self.command, target)):
            step = min(max(wanted - current, -self._budget[j]), self._budget[j])
            self._budget[j] -= abs(step)
            moved.append(current + step)
        self.command = moved
        return moved
