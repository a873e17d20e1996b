"""Whether the puppet's angle settings may change now: not while a Baxter arm follows (pure).

A change of a setting of settings.ANGLE_SETTINGS (home_angle, sign_angle, the angle and speed
limits) changes what the puppet reports with the hand still, and a following Baxter arm would
move by itself. config_X refuses such a change while its arm controller's teleop_state says an
arm follows this puppet (SettingsKeeper.request's `frozen`), and the GUI disables its
calibration's Apply; both tell the operator which button stops following. arm_X, on the robot
host, stops following on its own whatever reaches the device (robopuppet.arm.angle_settings):
this is the operator host's first, friendlier layer.
"""
from robopuppet.interface import BAXTER_SIDES, BUTTON_LEFT, BUTTON_RIGHT

FOLLOW_BUTTON = dict(zip(BAXTER_SIDES, (BUTTON_LEFT, BUTTON_RIGHT)))   # Baxter's arm -> button
# A teleop_state older than this no longer locks: arm_X reports at least every 0.5 s, and one
# that cannot reach config_X cannot get the puppet's samples either, so it stops on its own.
TELEOP_STALE_S = 2.0


def following(follow_left, follow_right):
    """Return '' when no Baxter arm follows, else e.g. "Baxter's right arm follows this puppet:
    stop following first: press 3"."""
    arms = [side for side, on in zip(BAXTER_SIDES, (follow_left, follow_right)) if on]
    if not arms:
        return ''
    return "Baxter's %s arm%s follow%s this puppet: stop following first: press %s" % (
        ' and '.join(arms), 's' if len(arms) > 1 else '', '' if len(arms) > 1 else 's',
        ' and '.join(str(FOLLOW_BUTTON[side]) for side in arms))


class FollowLock:
    """Follow one puppet arm's teleop_state; say why its angle settings may not change now."""

    def __init__(self):
        self._follows = (False, False)
        self._t = None

    def on_teleop_state(self, t, follow_left, follow_right):
        """Take the arm controller's teleop_state, received at t (s)."""
        self._follows, self._t = (bool(follow_left), bool(follow_right)), t

    def why(self, t):
        """Return '' when the angle settings may change at t, else why not (following())."""
        if self._t is None or t - self._t > TELEOP_STALE_S:
            return ''
        return following(*self._follows)
