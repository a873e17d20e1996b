"""The teleop states' transition table and the events teleop fires at each step (pure).

The states are robopuppet_msgs/TeleopState's; README.md, "Operating the puppet", describes them
as the operator sees them.
"""
import math

from robopuppet.interface import CALIBRATING, FAULT, FOLLOWING, NO_ROBOT, READY

# (state, event) -> next state. Events not listed for a state leave it unchanged.
TRANSITIONS = {
    (NO_ROBOT, 'robot_ok'): CALIBRATING,
    (CALIBRATING, 'robot_lost'): NO_ROBOT,
    (CALIBRATING, 'calibrated'): READY,
    (CALIBRATING, 'silent'): FAULT,
    (READY, 'robot_lost'): NO_ROBOT,
    (READY, 'uncalibrated'): CALIBRATING,
    (READY, 'follow_on'): FOLLOWING,
    (READY, 'silent'): FAULT,
    (FOLLOWING, 'robot_lost'): NO_ROBOT,
    (FOLLOWING, 'uncalibrated'): CALIBRATING,
    (FOLLOWING, 'follow_off'): READY,
    (FOLLOWING, 'silent'): FAULT,
    (FAULT, 'robot_lost'): NO_ROBOT,
    (FAULT, 'fresh'): CALIBRATING,
}
# From any state but these, the arm controller's own failure is a fault.
for _state in (CALIBRATING, READY, FOLLOWING):
    TRANSITIONS[_state, 'controller_failed'] = FAULT
# Following is switched off on entering these states.
STOP_FOLLOWING = (NO_ROBOT, CALIBRATING, READY, FAULT)


def events(t, state, fault_t, robot_ok, puppet, failure):
    """Yield (event, detail) for what teleop in `state` takes at its step at time t, in order.

    Args:
        fault_t: when the fault began (in FAULT).
        robot_ok: whether Baxter is present and enabled.
        puppet: the teleop's puppet_watch.PuppetWatch.
        failure: why the arm controller failed since the last step, or None.
    state and fault_t stay as at the step's start: an event fired before 'fresh' and 'refused'
    only leaves FAULT or enters it at t, and then neither applies.
    """
    silent = puppet.silent(t)
    if failure is not None:
        yield 'controller_failed', 'the arm controller failed (%s); press 2 or 3 to follow ' \
            'again' % failure
    if not robot_ok:
        yield 'robot_lost', 'Baxter is absent or not enabled'
    else:
        yield 'robot_ok', 'Baxter enabled'
    if silent:
        yield 'silent', silent
    elif state == FAULT and puppet.fresh_since(fault_t):
        yield 'fresh', 'puppet data is back; press 2 or 3 to follow again'
    if state == FAULT and (puppet.refusal or (-math.inf,))[0] > fault_t:
        yield 'refused', puppet.refusal[1]   # why fresh data is not back
    if puppet.state_t is None and puppet.refusal is not None:
        yield 'uncalibrated', 'no usable puppet joint states yet: %s' % puppet.refusal[1]
    if puppet.state_t is not None and not silent:
        waiting = puppet.not_calibrated()
        if waiting:
            yield 'uncalibrated', waiting
        else:
            yield 'calibrated', 'all joints Working; press 2 or 3 to follow'
