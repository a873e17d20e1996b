"""How well Baxter follows the puppet, as the main tab shows it: Baxter's pose in puppet space,
the error per joint, and a line with the keep-out zone holding Baxter back or "Baxter lags".

Pure: no rospy, no Qt, no clock (times are arguments). Baxter's measured pose is mapped back into
the puppet's joint space by the rule arm_X's feel mode uses (arm.joint_motion.driven_arm and
in_puppet_space): the arm this puppet drives, its own side as is, the other side mirrored; when
both or neither arm follows, its own side.
"""
import collections
import math

from robopuppet import interface
from robopuppet.arm import joint_motion

# Error bands (rad, |puppet - Baxter|). Below SMALL_ERROR_RAD (~3 deg) Baxter is where the
# puppet is, up to its position control and the 14-bit encoders' resolution. Up to
# LARGE_ERROR_RAD (~11 deg) is the lag of a hand in motion: at 1 rad/s, the 10 Hz state sets
# plus the link and the arm controller's command period put Baxter 0.1-0.15 rad behind. Above it
# something holds Baxter back: a joint limit, its speed limit, a keep-out zone or an obstacle
# (in feel mode the puppet then pulls back noticeably).
SMALL_ERROR_RAD = 0.05
LARGE_ERROR_RAD = 0.2
# A following arm "lags" when its largest error stays above LARGE_ERROR_RAD this long: longer
# than a quick move takes to catch up.
LAG_AFTER_S = 1.0
# Baxter's joint states older than this are not shown (the link to the robot room is cut or
# Baxter is gone): errors against an old pose would mislead.
BAXTER_STALE_S = 1.0
SMALL, MEDIUM, LARGE = 'small', 'medium', 'large'

Tracking = collections.namedtuple('Tracking', 'arm mirrored baxter_rad error_rad')
Tracking.__doc__ = """Baxter's arm `arm` ('left' or 'right') in puppet space: `mirrored` (True for
the other side), `baxter_rad` its 7 angles mapped back (rad), `error_rad` puppet - Baxter per
joint (rad; NaN where the puppet's angle is unknown)."""
Line = collections.namedtuple('Line', 'text level')
Line.__doc__ = """The zone or lag line: its text and level (ZONE, LAGS, TRACKS or IDLE)."""
ZONE, LAGS, TRACKS, IDLE = 'zone', 'lags', 'tracks', 'idle'


def driven_arm(puppet_side, follow_left, follow_right):
    """Return the Baxter arm whose pose the puppet shows (joint_motion.driven_arm)."""
    return joint_motion.driven_arm(interface.BAXTER_SIDE[puppet_side], follow_left, follow_right)


def tracking(puppet_side, arm, poses, puppet_rad):
    """Return the Tracking of Baxter arm `arm`, or None when its pose is unknown.

    Args:
        poses: {Baxter side: 7 measured angles rad, puppet joint order}.
        puppet_rad: the puppet's 7 reported angles (rad; NaN unknown).
    """
    if arm not in poses:
        return None
    baxter = joint_motion.in_puppet_space(interface.BAXTER_SIDE[puppet_side], arm, poses[arm])
    return Tracking(arm, arm != interface.BAXTER_SIDE[puppet_side], baxter,
                    [p - b for p, b in zip(puppet_rad, baxter)])


def error_level(error_rad):
    """Return SMALL, MEDIUM or LARGE for an error (rad), or None when it is unknown (NaN)."""
    if error_rad is None or math.isnan(error_rad):
        return None
    size = abs(error_rad)
    return SMALL if size < SMALL_ERROR_RAD else MEDIUM if size < LARGE_ERROR_RAD else LARGE


def largest_error(track):
    """Return (joint, error rad) of a Tracking's largest known error, or None."""
    known = [(abs(e), j, e) for j, e in enumerate(track.error_rad) if not math.isnan(e)]
    return max(known)[1:] if known else None


class LagWatch:
    """Tell when an error stays large: fed once per frame, True after LAG_AFTER_S of it.

    A gap of more than LAG_AFTER_S between updates (the tab was hidden) starts over.
    """

    def __init__(self):
        self._large_since_s = None
        self._last_s = None

    def update(self, now_s, large):
        """Record whether the error is large at now_s (s); return True when it stays large."""
        if not large or (self._last_s is not None and now_s - self._last_s > LAG_AFTER_S):
            self._large_since_s = None
        if large and self._large_since_s is None:
            self._large_since_s = now_s
        self._last_s = now_s
        return large and now_s - self._large_since_s >= LAG_AFTER_S


def zone_text(zone_left, zone_right):
    """Return 'keep-out zone ... holds back ...' for the zones of TeleopState, or ''."""
    held = [(zone, arm) for zone, arm in zip((zone_left, zone_right), interface.BAXTER_SIDES)
            if zone]
    if not held:
        return ''
    if len(held) == 2 and held[0][0] == held[1][0]:
        return "keep-out zone '%s' holds back Baxter's arms" % held[0][0]
    return '; '.join("keep-out zone '%s' holds back Baxter's %s arm" % h for h in held)


def status_line(teleop, lagging, baxter_known, teleop_age_s=None, baxter_age_s=None):
    """Return the Line under the joint table.

    Args:
        teleop: the state.Teleop, or None.
        lagging: {Baxter side: (joint, error rad)} of the following arms that lag.
        baxter_known: whether Baxter's pose is recent (BAXTER_STALE_S).
        teleop_age_s: set when the teleop state is no longer current (s since it came): its
            zones and following arms are then not shown as if they were (IDLE, with the age).
        baxter_age_s: the age of Baxter's last pose (s), None when none came.
    """
    if teleop is None:
        return Line('no arm controller', IDLE)
    if teleop_age_s is not None:
        return Line('NOT CURRENT: no report from the arm controller for %.0f s; zones and '
                    'lag unknown' % teleop_age_s, IDLE)
    zones = zone_text(teleop.zone_left, teleop.zone_right)
    if zones:  # a zone explains the lag that comes with it
        return Line(zones, ZONE)
    if lagging:
        return Line('Baxter lags: ' + '; '.join(
            '%s arm, joint %d off by %+.2f rad' % (arm, joint, error)
            for arm, (joint, error) in sorted(lagging.items())), LAGS)
    if not (teleop.follow_left or teleop.follow_right):
        return Line('Baxter not following', IDLE)
    if not baxter_known:
        if baxter_age_s is None:
            return Line("no /robot/joint_states yet: Baxter's pose unknown", IDLE)
        return Line("NOT CURRENT: no /robot/joint_states for %.0f s: Baxter's pose unknown"
                    % baxter_age_s, IDLE)
    return Line('Baxter tracks the puppet', TRACKS)
