"""The Baxter arm the assist drives through arm_X: when it is engaged, toward what, when it holds.

Pure: time is an argument. robopuppet's assist node predicts one Baxter arm (the follower) from
the motion of the other (the leader, the arm on this puppet's side) and sends each prediction to
the leader's arm controller on <ns>/assist_target (robopuppet_msgs/AssistTarget). This keeps the
newest target per arm and plans each step of an assisted arm; teleop.Teleop carries the plan out
through the same path as puppet following (clamp to the joint limits, SpeedBudget with a slow
approach first, keep-out zone cut) and stops the arm on every stop of following.

The rules (docs/teleop.md, "The assisted arm"):
- The follow button of the other Baxter arm engages the assist when a target for that arm came
  at most ASSIST_TIMEOUT_S ago, even one that says hold (the arm then holds at once: while an
  assist runs, that button never makes the arm mirror the puppet unbidden); with no target
  for that long the button mirrors the puppet.
- A target that says hold, or none for ASSIST_TIMEOUT_S: the arm holds where Baxter measures it
  ("assist holding: unfamiliar motion"); fresh targets that do not say hold move it again.
- The gripper closes and opens as the target says, on engaging and while the arm moves; a
  holding arm keeps its grip (a tray is not dropped because the prediction is unsure).
"""
import collections
import math

from robopuppet.interface import BAXTER_SIDES

ASSIST_TIMEOUT_S = 0.2   # a target older than this (s, since it arrived) holds the arm
HOLDING = 'assist holding: '
NO_PREDICTION = 'no prediction for %g s' % ASSIST_TIMEOUT_S

Target = collections.namedtuple('Target', 't positions gripper_closed hold detail')
Target.__doc__ = """An AssistTarget as it arrived at t (s): 7 positions (rad), gripper_closed,
hold (bool) and detail (why it holds)."""
Plan = collections.namedtuple('Plan', 'positions changed grip')
Plan.__doc__ = """A step of an assisted arm: positions (7 rad) to move toward, None to hold
still; changed: it holds now and did not at the last step, or the other way round; grip: True
(close) or False (open) to send now, None for no gripper command."""


def refusal(own_side, side, positions):
    """Return why an assist target for Baxter's `side` arm cannot be used by the arm controller
    of the puppet on Baxter's own_side, '' when it can."""
    if side not in BAXTER_SIDES:
        return 'assist target for an unknown arm %r refused (left or right)' % (side[:20],)
    if side == own_side:
        return ("assist target for Baxter's %s arm refused: this puppet drives that arm itself"
                % side)
    if len(positions) != 7 or not all(math.isfinite(p) for p in positions):
        return 'assist target refused: its positions are not 7 finite angles: %s' % (
            ', '.join('%.3g' % p for p in positions[:9]))
    return ''


def who_drives(followers, assisted):
    """Return the teleop detail naming the Baxter arms that follow the puppet and the one the
    assist drives, e.g. "Baxter follows with its right arm; the assist drives its left arm"."""
    parts = ['Baxter follows with its %s arm%s' % (' and '.join(followers),
                                                    's' if len(followers) > 1 else '')
             ] if followers else []
    parts += ['the assist drives %s %s arm' % ('its' if followers else "Baxter's", side)
              for side in assisted]
    return '; '.join(parts) or 'no Baxter arm follows; press 2 or 3 to follow'


class AssistFollow:
    """Keep the newest assist target per Baxter arm; engage, plan and let go of assisted arms.

    Args:
        own_side: the Baxter arm of the puppet's own side ('left' or 'right'), never assisted.
    Attributes:
        assisted: {side: bool}, the arms the assist drives now.
        holding: {side: bool}, the assisted arms held still now.
    """

    def __init__(self, own_side):
        self.own_side = own_side
        self.assisted = {side: False for side in BAXTER_SIDES}
        self.holding = {side: False for side in BAXTER_SIDES}
        self._targets = {side: None for side in BAXTER_SIDES}
        self._grip = {side: None for side in BAXTER_SIDES}   # the grip commanded last
        self.refused = 0    # targets refused (refusal)

    def on_target(self, t, side, positions, gripper_closed, hold, detail):
        """Take an assist target received at t; return '' or why it was refused (to log)."""
        why = refusal(self.own_side, side, positions)
        if why:
            self.refused += 1
            return why
        self._targets[side] = Target(t, [float(p) for p in positions], bool(gripper_closed),
                                     bool(hold), detail)
        return ''

    def _fresh(self, side, t):
        """Return the target that came at most ASSIST_TIMEOUT_S before t, else None."""
        target = self._targets[side]
        return None if target is None or t - target.t > ASSIST_TIMEOUT_S else target

    def _moving(self, side, t):
        """Return the target to move toward at t: fresh and not saying hold; else None."""
        target = self._fresh(side, t)
        return None if target is None or target.hold else target

    def engage(self, side, t):
        """Start driving Baxter's `side` arm when a fresh target is there, even one saying hold
        (the arm then holds); return whether it did. It approaches slowly, and grips as the
        target says once it moves."""
        if side == self.own_side or self._fresh(side, t) is None:
            return False
        self.assisted[side], self.holding[side], self._grip[side] = True, False, None
        return True

    def release(self, side):
        """Stop driving Baxter's `side` arm (it then stays where it is)."""
        self.assisted[side] = self.holding[side] = False

    def release_all(self):
        """Stop driving every arm: a stop of following stops the assisted arm too."""
        for side in BAXTER_SIDES:
            self.release(side)

    def plan(self, side, t):
        """Return the Plan of the assisted arm `side` at t."""
        target = self._moving(side, t)
        changed = self.holding[side] != (target is None)
        self.holding[side] = target is None
        if target is None:
            return Plan(None, changed, None)
        grip = None if target.gripper_closed == self._grip[side] else target.gripper_closed
        self._grip[side] = target.gripper_closed
        return Plan(target.positions, changed, grip)

    def gripper_closed(self, side):
        """Return whether the assist holds Baxter's `side` gripper closed."""
        return self.assisted[side] and bool(self._grip[side])

    def hold_detail(self, t):
        """Return why an assisted arm holds, '' when none does: the target's detail ("assist
        holding: unfamiliar motion", "assist stopped: ..."; others get "assist holding: " put
        before them) or NO_PREDICTION."""
        whys = []
        for side in BAXTER_SIDES:
            if self.assisted[side] and self.holding[side]:
                target = self._targets[side]
                why = NO_PREDICTION if t - target.t > ASSIST_TIMEOUT_S else (
                    target.detail or 'the assist says hold')
                whys.append(why if why.startswith('assist ') else HOLDING + why)
        return '; '.join(whys)
