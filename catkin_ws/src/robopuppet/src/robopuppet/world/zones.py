"""Keep-out zones: the arm commands that would take any part of a Baxter arm into one are cut.

A zone file (config/zones.yaml; docs/zones.md) is a shape file (world.shapes). Clearances are of
the arm's capsules (world.arm_capsules) from every zone (world.clearance); ArmCapsules.reach
bounds how far a capsule moves for a joint motion, which is what makes every proof here hold
between the configurations it checks. ZoneGuard.limit_box (arm_X, the replay) proves a whole box
of joint angles clear (docs/zones.md, "The guarantee"), ZoneGuard.limit (and slide, the
stand-in's contact) the straight motion from one configuration to the next (_sweep); either
stops the arm MARGIN_M outside a zone, not at it.

At a zone already (within NEAR_M, as after a cut) or inside it (a zone file can change under
the arm), a (capsule, zone) pair may not end a command nearer (deeper) than it started, and on
the way its clearance may dip at most SLACK_M, never into the zone from outside (floors);
otherwise the arm stays at q_from. So the arm can always move away and depth cannot creep.
Pure numpy, no ROS; with a few dozen capsules a numpy call's overhead is the cost, so each pass
is one batch of configurations.
"""
import collections
import math

import numpy as np

from robopuppet.world import shapes
from robopuppet.world.clearance import ShapeSet

RESOLUTION_M = 0.001    # the motion bound (m) of the smallest interval checked
MARGIN_M = 0.002        # a cut command stops the arm this far (and up to RESOLUTION_M more)
                        # outside the zone ...
SLACK_M = 0.001         # ... so that from there a motion may dip this much on its way out
NEAR_M = MARGIN_M + RESOLUTION_M + SLACK_M   # a pair this near at the start is at the zone
MAX_SPLIT = 32          # an interval not proven clear is split into at most this many
REFINE_AT_ONCE = 8      # intervals split in one pass at most ...
MAX_NEW = 64            # ... while their new configurations fit in this many (but one at least)
FIRST_STEP_M = 0.02     # the sweep starts with intervals of at most this motion bound (m) ...
MAX_FIRST = 64          # ... but no more than this many
MAX_CHECKED = 4096      # configurations checked per call at most (then the rest is refused)
FRACTIONS = (1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125)   # of a step that limit_box tries

Hit = collections.namedtuple('Hit', 'zone link')
Hit.__doc__ = 'Why a motion was cut: the zone name and the arm link (URDF name) that would enter.'


class ZoneFileError(shapes.ShapeFileError):
    """A zone file cannot be read or is not a shape file; the message names file and entry."""


def parse_zones(text, where='the zone file'):
    """Return the Shapes of a zone file's YAML text (an empty file: no zones).

    Raises:
        ZoneFileError: not YAML, or an entry not in the format (the message names it).
    """
    try:
        return shapes.parse_shapes(shapes.load_document(text, ('frame', 'shapes'), where), where)
    except shapes.ShapeFileError as error:
        raise ZoneFileError(str(error)) from None


def load_zones(path):
    """Return the Shapes of a zone file; raise ZoneFileError naming it and the entry."""
    return parse_zones(shapes.read_text(path, ZoneFileError, 'zone file'), path)


def floors(start):
    """Return (near, floor), (Z, C) each, for (capsule, zone) pairs with clearances `start`
    (m) where a motion starts: near, the pair is at (or in) a zone already (below NEAR_M);
    floor, the clearance the pair must keep on the motion: MARGIN_M, or for a near pair its
    start less SLACK_M, but never below 0 when it starts outside."""
    near = start < NEAR_M
    floor = np.where(near, start - SLACK_M, MARGIN_M)
    floor[(start > 0.0) & (floor < 0.0)] = 0.0
    return near, floor


class ZoneGuard:
    """Cut arm commands that would take one arm into a keep-out zone.

    Args:
        capsules: the arm's world.arm_capsules.ArmCapsules.
        zones: the zones, world.shapes.Shapes.
    """

    def __init__(self, capsules, zones):
        self.capsules = capsules
        self.zones = ShapeSet(zones)
        self.names = self.zones.names
        self.checked = 0   # configurations checked by the last call (for benchmarks)
        self._stuck = (None, None)   # slide's last (question, answer)
        self._boxed = (None, None)   # limit_box's last (question, answer)

    def _clearance(self, angles, needed):
        """Return (Z, M, C) clearances (m) at (M, 7) angles, exact where below `needed`."""
        arm = self.capsules
        return self.zones.clearance(arm.segments(angles), arm.half_lengths, arm.radii, needed)

    def clearance(self, angles):
        """Return the (Z, C) clearances (m) of every capsule from every zone at 7 angles."""
        return self._clearance(np.asarray(angles, np.float64)[None], np.inf)[:, 0]

    def limit(self, q_from, q_to):
        """Return (q_out, hit): q_to when the motion from q_from keeps the arm out of every zone,
        else the last configuration on it proven clear (q_from at worst) and the Hit (zone,
        link) that stopped it; hit is None when q_out is q_to.

        Args:
            q_from: the 7 angles (rad, s0 .. w2) of the last command sent.
            q_to: the 7 angles of the next command.
        """
        q_from, q_to = np.asarray(q_from, np.float64), np.asarray(q_to, np.float64)
        self.checked = 0
        if not self.names:
            return list(q_to), None
        motion = q_to - q_from
        speed = self.capsules.reach @ np.abs(motion)          # (C,) m per unit of s
        longest = float(speed.max())
        count = min(max(math.ceil(longest / FIRST_STEP_M), 1), MAX_FIRST)
        # Also the finest step from the start: an arm held at a zone's boundary is settled at
        # once, without splitting its way down to it.
        s = sorted({k / count for k in range(count + 1)} |
                   {min(RESOLUTION_M / max(longest, 1e-12), 1.0)})
        widest = max(b - a for a, b in zip(s, s[1:]))
        raw = self._clearance(q_from + np.array(s)[:, None] * motion, speed * widest + NEAR_M)
        self.checked = len(s)
        start = raw[:, 0]                                    # (Z, C)
        near, floor = floors(start)
        if near.any():
            closer = np.where(near, raw[:, -1] - start, np.inf)
            if closer.min() < 0.0:   # nearer at the end than at the start: stay
                z, c = np.unravel_index(np.argmin(closer), closer.shape)
                return list(q_from), Hit(self.names[z], self.capsules.links[c])
        floor = floor[:, None]
        end, pair, there = self._sweep(q_from, motion, speed, np.array(s), raw - floor, floor)
        if near.any() and 0.0 < end < 1.0:   # cut further on: still no nearer there, or stay
            # (there: lower bounds, exact below NEAR_M, so a near pair's is exact or farther)
            closer = np.where(near, there + floor[:, 0] - start, np.inf)
            if closer.min() < 0.0:
                end, pair = 0.0, np.unravel_index(np.argmin(closer), closer.shape)
        if end == 1.0:
            return list(q_to), None
        z, c = pair
        return list(q_from + end * motion), Hit(self.names[z], self.capsules.links[c])

    def limit_box(self, lo, hi, q_from, q_to, slide=True):
        """Return (q_out, hit) for the next command of an arm that may be anywhere in the box
        lo..hi (7 rad each: where it can be until the command takes effect) and whose last
        command was q_from: q_out is q_from + f (q_to - q_from) for the largest f of FRACTIONS
        whose box, lo..hi stretched to hold q_out, is proven clear; else (slide) the largest
        single-joint part of the step that is; else q_from. hit (zone, link) says what held
        the full step back, None when q_out is q_to.

        An arm whose every joint moves from where it is toward its target without overshoot
        stays inside that box until the next command: proving the box proves its motion,
        whatever each joint's speed. Box test: with a and b opposite corners, no point of a
        capsule can be nearer a zone than (clearance at a + clearance at b - reach @ width) / 2.
        """
        asked = tuple(np.concatenate([lo, hi, q_from, q_to, [slide]]).tolist())
        if asked != self._boxed[0]:   # else pushing on at a zone, Baxter at rest: the same
            self._boxed = (asked, self._limit_box(lo, hi, q_from, q_to, slide))
        return list(self._boxed[1][0]), self._boxed[1][1]

    def _limit_box(self, lo, hi, q_from, q_to, slide):
        lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
        q_from, q_to = np.asarray(q_from, np.float64), np.asarray(q_to, np.float64)
        self.checked = 0
        step = q_to - q_from
        if not self.names or not step.any():   # the same target: proven when it was sent
            return list(q_to), None
        gaps, spread = self._corners(lo, hi, q_to[None], True, q_from)
        start = gaps[:, 0]                                                 # (Z, C)
        near, floor = floors(start)
        passed, short, closer = self._proven(gaps[:, 1:], spread, start, near, floor)
        if passed[0]:
            return list(q_to), None
        worst = np.where(closer[:, 0] < 0.0, -np.inf, short[:, 0])
        z, c = np.unravel_index(np.argmin(worst), worst.shape)
        hit = Hit(self.names[z], self.capsules.links[c])
        tries = [np.array([q_from + f * step for f in FRACTIONS[1:]])]
        if slide:   # each joint's part of the step alone
            tries.append(np.array([q_from + f * step[j] * np.eye(7)[j]
                                   for j in np.flatnonzero(step) for f in FRACTIONS[::2]]))
        for targets in tries:
            gaps, spread = self._corners(lo, hi, targets, near.any())
            passed = self._proven(gaps, spread, start, near, floor)[0]
            if passed.any():
                moved = np.abs(targets[passed] - q_from) @ self.capsules.reach.T
                return list(targets[passed][np.argmax(moved.max(axis=1))]), hit
        return list(q_from), hit

    def _corners(self, lo, hi, targets, with_targets, *more):
        """Return (gaps (Z, M, C), spread (N, C)) for (N, 7) targets: clearances at the more
        configurations, then each target's box's corners a, then its corners b, then (when
        with_targets) the targets (a box: lo..hi stretched to hold the target); spread: how
        far a capsule point in a box can be from its corners a and b together (reach @ the
        box's width). Exact where below half the spread (and NEAR_M), lower bounds elsewhere."""
        low, high = np.minimum(lo, targets), np.maximum(hi, targets)
        toward = targets >= (lo + hi) / 2.0        # corner b on the target's side of the box
        spread = (high - low) @ self.capsules.reach.T
        configs = [np.array(more).reshape(-1, 7), np.where(toward, low, high),
                   np.where(toward, high, low)] + ([targets] if with_targets else [])
        configs = np.concatenate(configs)
        self.checked += len(configs)
        return self._clearance(configs, spread.max(axis=0) / 2.0 + NEAR_M), spread

    @staticmethod
    def _proven(gaps, spread, start, near, floor):
        """Return (passed (N,), short, closer (Z, N, C)) from _corners' gaps for N targets:
        whether each box is proven to keep every capsule above its floor (short: by how much,
        > 0 proven) and, for the pairs near a zone, its target no nearer than at the start."""
        n = len(spread)
        short = gaps[:, :n] + gaps[:, n:2 * n] - 2.0 * floor[:, None] - spread[None]
        closer = np.full(short.shape, np.inf)
        if near.any():
            closer = np.where(near[:, None], gaps[:, 2 * n:] - start[:, None], np.inf)
        return ((short > 0.0) & (closer >= 0.0)).all(axis=(0, 2)), short, closer

    def slide(self, q_from, q_to):
        """Return (q_out, hit) like limit, but when limit cannot move at all, take the joints
        whose own step leaves every pair at a zone no nearer (tried alone, in one batch) and
        go straight to where those steps lead, as limit allows (the largest of them alone if
        together they cannot move): an arm held at a zone's boundary follows the parts of the
        next command that lead along or away from the zone. The returned motion is always the
        straight one from q_from, checked by limit.
        """
        asked = (tuple(q_from), tuple(q_to))
        if asked == self._stuck[0]:   # pushing on at a zone: the same answer as last time
            return self._stuck[1]
        q_out, hit = self.limit(q_from, q_to)
        if hit is None or list(q_out) != list(q_from):
            return q_out, hit
        start = np.asarray(q_from, np.float64)
        step = np.asarray(q_to, np.float64) - start
        joints = np.flatnonzero(step)
        tried = np.repeat(start[None], len(joints) + 1, axis=0)
        tried[np.arange(1, len(joints) + 1), joints] += step[joints]
        reach = self.capsules.reach[:, joints] * np.abs(step[joints])      # (C, J)
        gaps = self._clearance(tried, reach.max(axis=1) + NEAR_M)          # (Z, 1 + J, C)
        near = gaps[:, :1] < NEAR_M
        free = joints[~(near & (gaps[:, 1:] < gaps[:, :1])).any(axis=(0, 2))]
        choices = [free] if len(free) else []
        if len(free) > 1:   # together they may still come nearer: the largest step alone
            choices.append(free[[np.argmax(np.abs(step[free]))]])
        for chosen in choices:
            reached = start.copy()
            reached[chosen] += step[chosen]
            q_out, _ = self.limit(start, reached)
            if list(q_out) != list(q_from):
                break
        self._stuck = (asked, (q_out, hit))
        return q_out, hit

    def _sweep(self, q_from, motion, speed, s, gaps, floor):
        """Return (end, (zone, capsule), gaps at end): the motion is proven clear for s in
        [0, end]; of the pairs not proven clear in the first interval that is not, the nearest
        (None when end is 1).

        s: (M,) checked points in order, gaps: (Z, M, C) their clearances above the floor. An
        interval between neighbours is clear when, for every pair, the clearances at its ends
        add up to more than the capsule can move across it; the first one that is not is split
        until its motion bound is below RESOLUTION_M, and the motion ends at its start. An
        interval is split into as many as its pairs' clearance suggests would prove it (down
        to RESOLUTION_M at once where a pair is at its floor), so that most cuts and near
        misses take one more pass.
        """
        longest = float(speed.max())
        while True:
            width = s[1:] - s[:-1]
            short = gaps[:, :-1] + gaps[:, 1:] - speed * width[:, None]     # (Z, M-1, C)
            failing = short <= 0.0
            open_ = np.flatnonzero(failing.any(axis=(0, 2)))
            if not len(open_):
                return 1.0, None, None
            i = open_[0]
            if longest * width[i] <= RESOLUTION_M or self.checked >= MAX_CHECKED:
                failed = np.where(failing[:, i], gaps[:, i] + gaps[:, i + 1], np.inf)
                pair = np.unravel_index(np.argmin(failed), failed.shape)  # the nearest of them
                return float(s[i]), pair, gaps[:, i]
            # Split the first few open intervals at once (up to the first one already fine):
            # a pass costs about the same for one interval or many.
            fine = longest * width[open_] <= RESOLUTION_M
            chosen = open_[:min(REFINE_AT_ONCE, int(np.argmax(fine)) if fine.any()
                                else len(open_))]
            lowest = np.where(failing[:, chosen],
                              np.minimum(gaps[:, chosen], gaps[:, chosen + 1]), np.inf)
            pieces = np.clip(np.ceil(longest * width[chosen] /
                                     np.maximum(lowest.min(axis=(0, 2)), RESOLUTION_M)),
                             2, MAX_SPLIT)
            bounds, new = s.tolist(), set()
            for k, n in zip(chosen.tolist(), pieces.astype(int).tolist()):
                if new and len(new) + n > MAX_NEW:
                    break
                new.update(bounds[k] + (bounds[k + 1] - bounds[k]) * m / n for m in range(1, n))
            if bounds[i] + RESOLUTION_M / longest < bounds[i + 1]:
                new.add(bounds[i] + RESOLUTION_M / longest)
            new = np.array(sorted(new))
            more = self._clearance(q_from + new[:, None] * motion,
                                   speed * float((width[chosen] / pieces).max()) + NEAR_M) - floor
            self.checked += len(new)
            order = np.argsort(np.concatenate([s, new]), kind='stable')
            s = np.concatenate([s, new])[order]
            gaps = np.concatenate([gaps, more], axis=1)[:, order]
