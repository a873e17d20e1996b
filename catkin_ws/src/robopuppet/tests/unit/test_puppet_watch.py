"""robopuppet.arm.puppet_watch: what one puppet arm's stream tells arm_X (time passed in)."""
from robopuppet import interface
from robopuppet.arm.puppet_watch import PuppetWatch

WORKING = [interface.WORKING] * 7
ANGLES = [0.0] * 7
STATE_TIMEOUT_S, HEARTBEAT_TIMEOUT_S = 0.4, 2.5


def test_after_a_fault_on_a_silent_heartbeat_joint_states_alone_are_not_fresh_data():
    """The firmware's joint states flowed on while its heartbeat stopped (the fault at fault_t):
    fresh data needs joint states and a heartbeat after the fault."""
    watch = PuppetWatch(STATE_TIMEOUT_S, HEARTBEAT_TIMEOUT_S)
    watch.on_heartbeat(0.0)
    t = 0.0
    while not watch.silent(t):
        watch.on_joint_states(t, WORKING, ANGLES)
        t += 0.1
    fault_t = t
    assert 'heartbeat' in watch.silent(fault_t)
    watch.on_joint_states(fault_t + 0.1, WORKING, ANGLES)
    assert not watch.fresh_since(fault_t)
    watch.on_heartbeat(fault_t + 0.15)
    assert watch.fresh_since(fault_t)


def test_after_a_fault_on_silent_joint_states_a_heartbeat_alone_is_not_fresh_data():
    watch = PuppetWatch(STATE_TIMEOUT_S, HEARTBEAT_TIMEOUT_S)
    watch.on_heartbeat(0.0)
    watch.on_joint_states(0.0, WORKING, ANGLES)
    fault_t = 0.5
    assert 'no joint states' in watch.silent(fault_t)
    watch.on_heartbeat(0.6)
    assert not watch.fresh_since(fault_t)
    watch.on_joint_states(0.7, WORKING, ANGLES)
    assert watch.fresh_since(fault_t)
