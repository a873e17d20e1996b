"""robopuppet.arm.teleop_topics: the teleop report as arm_X publishes it, and its last word on
shutdown (rospy's publishers replaced by recorders; no ROS master)."""
import os

import pytest
import rospy
from diagnostic_msgs.msg import DiagnosticStatus
from visualization_msgs.msg import Marker, MarkerArray

from robopuppet import baxter_description as bd, interface
from robopuppet.arm import controller, teleop_topics, zone_topics
from robopuppet.world import zones
from ros_stand_ins import record_publishers, sent_on

NS = interface.puppet_ns('R')
ZONES_FILE = os.path.join(os.path.dirname(bd.URDF_PATH), '..', 'config', 'zones.yaml')


@pytest.fixture
def logged(monkeypatch):
    """Return [(level, text)] of the log lines; publishers record (ros_stand_ins)."""
    lines = []
    record_publishers(monkeypatch)
    monkeypatch.setattr(rospy.Time, 'now', staticmethod(lambda: rospy.Time(5)))
    for level in ('loginfo', 'logwarn'):
        monkeypatch.setattr(rospy, level, lambda text, *args, level=level: lines.append(
            (level, text % args)))
    return lines


def report(changed=True, zone_right='', opmode=interface.FEEL):
    return controller.Report(
        changed, interface.FOLLOWING, False, True, opmode, 0.4, 'Baxter follows', '', zone_right,
        'arm_R: teleoperation', NS, 'WARN', 'following: Baxter follows', [('state', 'following')])


def test_a_report_is_teleop_state_and_its_diagnostics_status_and_logged_when_it_changed(logged):
    topics = teleop_topics.TeleopTopics(NS, [], 'arm_R')
    topics.publish(report())
    topics.publish(report(changed=False))
    state, _ = sent_on(NS + '/' + interface.TELEOP_STATE)
    assert (state.state, state.follow_left, state.follow_right, state.opmode) == (
        interface.FOLLOWING, False, True, interface.FEEL)
    assert (state.heartbeat_age, state.detail) == (pytest.approx(0.4), 'Baxter follows')
    status = sent_on(interface.DIAGNOSTICS)[0].status[0]
    assert (status.level, status.name, status.hardware_id) == (
        DiagnosticStatus.WARN, 'arm_R: teleoperation', NS)
    assert [(kv.key, kv.value) for kv in status.values] == [('state', 'following')]
    assert logged == [('loginfo', 'arm_R: following (Baxter follows)')]


def test_the_zone_holding_an_arm_back_is_shown_again(logged):
    found = zones.load_zones(ZONES_FILE)
    topics = teleop_topics.TeleopTopics(NS, found, 'arm_R')
    assert len(sent_on(interface.ZONE_MARKERS)) == 1   # the zones at once
    assert len(sent_on(interface.ZONE_HOLD_MARKERS)) == 1   # and no highlight
    topics.publish(report(zone_right=found[0].name))
    assert len(sent_on(interface.ZONE_MARKERS)) == 1
    markers = sent_on(interface.ZONE_HOLD_MARKERS)
    assert len(markers) == 2 and isinstance(markers[1], MarkerArray)
    assert any(m.ns == zone_topics.HELD_NAMESPACE + ' (arm_R)' and m.action == Marker.ADD
               for m in markers[1].markers)


@pytest.mark.parametrize('master_answers, level, why', [
    (True, 'loginfo', 'shut down'),
    (False, 'logwarn', 'the ROS master does not answer')])
def test_on_shutdown_a_last_teleop_state_says_nothing_follows_and_why(
        logged, monkeypatch, master_answers, level, why):
    monkeypatch.setattr(teleop_topics, 'answers', lambda uri: master_answers)
    topics = teleop_topics.TeleopTopics(NS, [], 'arm_R')
    topics.publish(report())
    topics.shut_down()
    last = sent_on(NS + '/' + interface.TELEOP_STATE)[-1]
    assert (last.state, last.opmode) == (interface.FAULT, interface.FEEL)
    assert last.detail.startswith('arm_R stopped: %s' % why)
    assert last.detail.endswith('; Baxter stops at its last command until arm_R runs again')
    assert logged[-1] == (level, last.detail)
