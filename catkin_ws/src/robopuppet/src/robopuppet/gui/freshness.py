"""How old what the GUI shows from the robot room is, and when it no longer counts as current.

The robot host (arm_X, Baxter) sends the arm controller's state (teleop_state: its state,
which Baxter arms follow, the keep-out zone line), the link figures (link_state) and Baxter's
joint states. When the link or the robot host goes, the last of each stays in the ArmState:
the main tab then shows it greyed with its age, never as if it were current.

Pure: no Qt, no rospy, no clock (times are arguments).
"""
from robopuppet.arm import controller
from robopuppet.gui import link_view, tracking

# arm_X reports at least every controller.STATE_PERIOD_S (0.5 s): three reports missed.
TELEOP_STALE_S = 3 * controller.STATE_PERIOD_S
# link_state: the link box's own silence rule (1 s); Baxter's joint states (100 Hz): 1 s.
LINK_STALE_S = link_view.LINK_STATE_TIMEOUT_S
BAXTER_STALE_S = tracking.BAXTER_STALE_S
STALE_TEXT_COLOUR = '#616161'  # greyed text of a value that is not current


def age_s(received_s, now_s):
    """Return how long ago (s, at least 0) something received at received_s was, at now_s;
    None when it was never received (received_s None)."""
    return None if received_s is None else max(0.0, now_s - received_s)


def is_stale(received_s, now_s, limit_s):
    """Return True when something received at received_s (None: never) is older than limit_s."""
    age = age_s(received_s, now_s)
    return age is None or age > limit_s


def age_text(received_s, now_s, limit_s, what='robot room'):
    """Return the age line for the operator: 'robot room: 0.2 s ago' while current,
    'NOT CURRENT: robot room last heard 15 s ago' once older than limit_s."""
    age = age_s(received_s, now_s)
    if age is None:
        return 'NOT CURRENT: nothing heard from the %s yet' % what
    if age > limit_s:
        return 'NOT CURRENT: %s last heard %s ago' % (what, link_view.duration(age))
    return '%s: %s ago' % (what, link_view.duration(age))
