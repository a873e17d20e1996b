"""What the "Link to the robot room" box says: pure, from a state.Snapshot and the time now.

arm_X on the robot host measures the operator-robot link and publishes it (LinkState, kept as
a state.RobotLink). The GUI adds what only the operator host knows:
- no LinkState for LINK_STATE_TIMEOUT_S, or none yet: the robot host is not heard at all, so
  the network or the robot host is down (this host runs: it draws the window);
- its own puppet's health (the serial link's /diagnostics and the heartbeat): while the puppet
  has a fault, a problem arm_X puts on the operator host or the network is the puppet's.
The texts are for the operator (a nurse), not for a network engineer. No Qt, no rospy.
"""
import collections
import math

from robopuppet import interface
from robopuppet.gui import state

LINK_STATE_TIMEOUT_S = 1.0  # arm_X publishes several times a second: 1 s of silence is a fault
SERIAL_STALE_S = 5.0        # serial link diagnostics older than this: the serial node is gone
STATUS_MAX_CHARS = 100      # longer statuses are cut ('…'; the whole in full_status): 3 lines

# diagnostic_msgs/DiagnosticStatus levels, as in LinkState.level
OK, WARN, ERROR = 0, 1, 2
# LinkState's fault constants (robopuppet_msgs/LinkState.NONE, OPERATOR, NETWORK, ROBOT)
NONE, OPERATOR, NETWORK, ROBOT = 'none', 'operator', 'network', 'robot'
UNHEARD = 'unheard'  # the GUI's own side: nothing heard, the network or the robot host

SIDE_TEXT = {
    NONE: 'none',
    OPERATOR: 'this room (puppet)',
    NETWORK: 'network',
    ROBOT: 'robot room (Baxter)',
    UNHEARD: 'network or robot room',
}

View = collections.namedtuple('View', 'level side status full_status rtt delay loss where')
View.__doc__ = """What the box shows: level (OK, WARN or ERROR: the colour), side (a key of
SIDE_TEXT, or arm_X's unknown fault text), status (the coloured line, at most STATUS_MAX_CHARS),
full_status (all of it) and one line per figure: rtt (round trip), delay (the age of the newest
puppet sample when the robot host got it, and its bound), loss (pings lost) and where (the side,
in words)."""


def duration(seconds):
    """Return a duration for the operator: '62 ms', '1.4 s', '12 s'; '—' when unknown."""
    if seconds is None or not math.isfinite(seconds) or seconds < 0:
        return '—'
    if seconds < 1.0:
        return '%.0f ms' % (seconds * 1000.0)
    return '%.1f s' % seconds if seconds < 10.0 else '%.0f s' % seconds


def shorten(text, max_chars=STATUS_MAX_CHARS):
    """Return text, or its first words and '…' within max_chars when it is longer."""
    if len(text) <= max_chars:
        return text
    cut = text[:max_chars].rpartition(' ')[0] or text[:max_chars - 1]
    return cut.rstrip(' ,;:.(') + '…'


def puppet_problem(snap, now_s):
    """Return what is wrong with this room's puppet, or None when it is well or not known yet.

    A fault: the serial link's diagnostics say ERROR or stopped coming for SERIAL_STALE_S, or
    the puppet's heartbeat stopped for interface.HEARTBEAT_TIMEOUT_S (arm_X's own rule).
    """
    link = snap.link
    if link is not None:
        old_s = now_s - link.received_s
        if old_s > SERIAL_STALE_S:
            return "the puppet's serial link has not reported for %s" % duration(old_s)
        if link.level >= ERROR:
            return 'puppet serial link: %s' % link.message
    age_s = state.heartbeat_age(snap, now_s)
    if age_s is not None and age_s > interface.HEARTBEAT_TIMEOUT_S:
        return 'the puppet is silent (no heartbeat for %s)' % duration(age_s)
    return None


def describe(snap, now_s):
    """Return the View of the link to the robot room in snap (a state.Snapshot) at now_s (s)."""
    link = snap.robot_link
    puppet = puppet_problem(snap, now_s)
    if link is None or now_s - link.received_s > LINK_STATE_TIMEOUT_S:
        if link is None:
            heard = 'nothing heard yet'
        else:
            heard = 'nothing heard for %s' % duration(now_s - link.received_s)
        status = ("No link to the robot room: %s; the network or the robot room's computer is "
                  "down" % heard)
        where = SIDE_TEXT[UNHEARD]
        if puppet:
            status += '. In this room too, %s' % puppet
            where += ', and this room (puppet)'
        return View(ERROR, UNHEARD, shorten(status), status, 'Round trip: —', 'Delay to Baxter: —',
                    'Pings lost: —', 'Problem: ' + where)
    side = link.fault
    if link.level not in (OK, WARN, ERROR):
        level, status = ERROR, 'Link state unreadable: level %r from the robot room' % link.level
    elif link.level == OK:
        level, status = OK, 'Link to the robot room: OK'
    else:
        level = link.level
        if side in (OPERATOR, NETWORK) and puppet:
            side = OPERATOR  # the puppet's own fault explains what arm_X sees
        headline = {OPERATOR: 'Problem in this room (the puppet)',
                    NETWORK: 'Network slow' if level == WARN else 'Network failing',
                    ROBOT: 'Problem in the robot room'}.get(side, 'Link problem')
        status = ': '.join(part for part in (headline, link.detail) if part)
        if side == OPERATOR and puppet:
            status += '; %s' % puppet
    if level == OK:
        side = NONE
    where = SIDE_TEXT.get(side, 'not known (the robot room says %r)' % side)
    return View(level, side, shorten(status), status, 'Round trip: ' + _rtt(link),
                'Delay to Baxter: ' + _age(link), 'Pings lost: ' + _loss(link),
                'Problem: ' + where)


def _rtt(link):
    if not math.isfinite(link.rtt_s) or link.rtt_s < 0:
        return 'not measured yet'
    return duration(link.rtt_s)


def _age(link):
    if not math.isfinite(link.sample_age_s) or link.sample_age_s < 0:
        return 'no puppet data received yet'
    if not link.clock_known:
        return 'not known yet'
    text = duration(link.sample_age_s)
    if math.isfinite(link.max_sample_age_s) and link.max_sample_age_s > 0:
        text += ' (limit %s)' % duration(link.max_sample_age_s)
    return text


def _loss(link):
    if not math.isfinite(link.loss) or link.loss < 0:
        return '—'
    return '%.0f %% in the last few seconds' % (100.0 * min(link.loss, 1.0))
