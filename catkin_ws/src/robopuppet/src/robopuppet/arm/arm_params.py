"""arm_X's ~parameters: read, checked and logged, and the arm controller made from them.

ArmNode's docstring lists the parameters; this reads them (robopuppet.params checks them).
Besides those, ~leash (s, 0.1; 0: off): no command leads Baxter's measured pose by more than this
much of each joint's mode-1 travel, so a Baxter whose commands stop coasts little (arm.leash).
"""
import time

import rospy

from robopuppet import baxter_description, interface as ifc, params
from robopuppet.arm import controller, timing, zone_topics

MIN_COMMAND_RATE_HZ = 10.0   # Baxter drops a position command after 0.2 s; keep well inside it
DEFAULT_LEASH_S = 0.1        # no tracking lost in the stand-in; 0.05 s slows it (docs/zones.md)


def param(name, default, minimum=0.0):
    """Return the private parameter ~name as a positive float (ValueError: it is not one)."""
    return params.positive('~' + name, rospy.get_param('~' + name, default), minimum)


def leash_param():
    """Return ~leash (s) as 0 (off) or a positive float (ValueError: it is neither)."""
    value = rospy.get_param('~leash', DEFAULT_LEASH_S)
    off = value == 0 and not isinstance(value, bool)
    return 0.0 if off else params.positive('~leash', value)


def make_controller(side, guard, name):
    """Return (controller.ArmController, command period s, keep-out zone Shapes) from arm_X's
    ~parameters; log what the state timeout and the sample age bound mean, and the zones.

    Args:
        side: the puppet's side, 'L' or 'R'.
        guard: the node's robopuppet.periodic.Guard (its errors go into the teleop report).
        name: the node's name for log lines (arm_X).
    Raises:
        ValueError: a parameter out of range, or a bad zone file (named in the message).
    """
    period_s = 1.0 / param('command_rate', 100.0, MIN_COMMAND_RATE_HZ)
    rate = timing.state_timeout(param('comm_rate', ifc.DEFAULT_COMM_RATE_HZ))
    bound = timing.sample_age_bound(param('max_sample_age', timing.DEFAULT_MAX_SAMPLE_AGE_S))
    for told in (rate, bound):
        (rospy.loginfo if told.meets_stop else rospy.logwarn)('%s: %s', name, told.describe())
    path = zone_topics.zones_file()
    zone_guards, found = zone_topics.load_guards(path)
    rospy.loginfo('%s: %d keep-out zones%s', name, len(found),
                  ' from %s' % path if path else ' (~zones_file is empty)')
    core = controller.ArmController(
        side, {s: baxter_description.arm_limits(s) for s in ifc.BAXTER_SIDES}, rate,
        param('heartbeat_timeout', ifc.HEARTBEAT_TIMEOUT_S), param('approach_speed', 0.5),
        period_s, guard, time.monotonic(), bound, zone_guards, leash_param())
    return core, period_s, found
