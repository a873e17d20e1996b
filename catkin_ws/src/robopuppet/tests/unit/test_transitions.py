"""robopuppet.arm.transitions: the teleop states' table and the events a step fires on it."""
import pytest

from robopuppet import interface
from robopuppet.arm.puppet_watch import PuppetWatch
from robopuppet.arm.transitions import STOP_FOLLOWING, TRANSITIONS, events
from robopuppet.interface import CALIBRATING, FAULT, FOLLOWING, NO_ROBOT, READY

WORKING = [interface.WORKING] * 7
ANGLES = [0.1] * 7


def watch(statuses=None, at=None, heartbeat=True):
    """Return a PuppetWatch (0.4 s state timeout) fed joint states (and a beat) at `at`, if any."""
    puppet = PuppetWatch(0.4, 2.5)
    if at is not None:
        puppet.on_joint_states(at, statuses or WORKING, ANGLES)
        if heartbeat:
            puppet.on_heartbeat(at)
    return puppet


def fired(t, state, puppet, fault_t=None, robot_ok=True, failure=None):
    return list(events(t, state, fault_t, robot_ok, puppet, failure))


def names(found):
    return [event for event, _ in found]


def test_only_baxter_leaving_or_a_fault_leads_out_of_following_but_a_release():
    assert {event: new for (state, event), new in TRANSITIONS.items() if state == FOLLOWING} == {
        'robot_lost': NO_ROBOT, 'uncalibrated': CALIBRATING, 'follow_off': READY,
        'silent': FAULT, 'controller_failed': FAULT}


def test_a_fault_ends_only_on_fresh_data_or_baxter_leaving_and_never_in_following():
    assert {event: new for (state, event), new in TRANSITIONS.items() if state == FAULT} == {
        'robot_lost': NO_ROBOT, 'fresh': CALIBRATING}
    assert (NO_ROBOT, 'follow_on') not in TRANSITIONS and (FAULT, 'follow_on') not in TRANSITIONS
    assert [s for s in interface.TELEOP_STATES if s not in STOP_FOLLOWING] == [FOLLOWING]


def test_the_controllers_failure_comes_first_and_names_why():
    found = fired(1.0, FOLLOWING, watch(at=0.9), failure='ZeroDivisionError: x')
    assert found[0] == ('controller_failed', 'the arm controller failed (ZeroDivisionError: x); '
                        'press 2 or 3 to follow again')
    assert names(found) == ['controller_failed', 'robot_ok', 'calibrated']


def test_before_any_puppet_data_only_baxter_is_judged():
    assert fired(1.0, NO_ROBOT, watch(), robot_ok=False) == [
        ('robot_lost', 'Baxter is absent or not enabled')]
    assert fired(1.0, NO_ROBOT, watch()) == [('robot_ok', 'Baxter enabled')]


def test_refused_joint_states_before_any_usable_ones_keep_it_calibrating_and_say_why():
    puppet = watch()
    puppet.on_refused(0.5, 'out of order')
    assert fired(1.0, CALIBRATING, puppet)[1:] == [
        ('uncalibrated', 'no usable puppet joint states yet: out of order')]


def test_a_joint_not_working_is_named_and_all_working_is_calibrated():
    statuses = WORKING[:3] + [interface.UNCALIBRATED] + WORKING[4:]
    assert fired(1.0, READY, watch(statuses, at=0.9))[1:] == [
        ('uncalibrated', 'joint 3 Uncalibrated: turn each through its index mark')]
    assert names(fired(1.0, READY, watch(at=0.9))) == ['robot_ok', 'calibrated']


def test_a_silent_puppet_is_silent_with_its_reason_and_not_calibrated():
    found = fired(2.0, FOLLOWING, watch(at=1.0))
    assert names(found) == ['robot_ok', 'silent']
    assert found[1][1].startswith('no joint states from the puppet for 1.00 s')


@pytest.mark.parametrize('data_t, fresh', [(1.5, True), (0.9, False)])
def test_in_a_fault_fresh_data_is_data_since_the_fault(data_t, fresh):
    found = names(fired(data_t + 0.1, FAULT, watch(at=data_t), fault_t=1.0))
    assert ('fresh' in found) == fresh


def test_in_a_fault_a_refusal_since_the_fault_says_why_data_is_not_back():
    puppet = watch(at=0.9)
    puppet.on_refused(0.95, 'too old')
    assert 'refused' not in names(fired(1.1, FAULT, puppet, fault_t=1.0))
    puppet.on_refused(1.05, 'stamped ahead')
    assert ('refused', 'stamped ahead') in fired(1.1, FAULT, puppet, fault_t=1.0)
    assert 'refused' not in names(fired(1.1, READY, puppet, fault_t=1.0))   # only in a fault
