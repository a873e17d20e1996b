"""state_topics: what the GUI keeps of a puppet arm's state topics (callbacks fed by hand)."""
import types

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus

from robopuppet.gui import state
from robopuppet.gui.state_topics import StateTopics, is_link_status
from robopuppet_msgs.msg import LinkState


def test_the_client_keeps_link_state_with_its_receive_time():
    arm = state.ArmState()
    fake = types.SimpleNamespace(state=arm, _clock=lambda: 7.0)
    msg = LinkState(rtt=0.25, clock_offset=3.0, clock_known=True, sample_age=0.125,
                    max_sample_age=0.5, loss=0.5, level=1, fault=LinkState.NETWORK, detail='slow')
    StateTopics._on_link_state(fake, msg)
    assert arm.snapshot().robot_link == state.RobotLink(0.25, 0.125, 0.5, True, 0.5, 1,
                                                        'network', 'slow', 7.0)


def test_the_link_status_is_found_by_namespace_and_name_whatever_the_node_is_called():
    ns = '/puppet/arm_R'
    link = DiagnosticStatus(level=1, name='my_serial: puppet serial link', message='slow',
                            hardware_id=ns)
    others = [
        DiagnosticStatus(name='serial_R: puppet serial link', hardware_id='/dev/ttyACM0'),
        DiagnosticStatus(name='serial_L: puppet serial link', hardware_id='/puppet/arm_L'),
        DiagnosticStatus(name='arm_R: teleoperation', hardware_id=ns),
    ]
    assert is_link_status(link, ns)
    assert not any(is_link_status(status, ns) for status in others)
    arm = state.ArmState()
    fake = types.SimpleNamespace(ns=ns, state=arm, _clock=lambda: 7.0)
    StateTopics._on_diagnostics(fake, DiagnosticArray(status=others + [link]))
    assert arm.snapshot().link == state.Link(1, 'my_serial: puppet serial link', 'slow', (), 7.0)
