"""arm_X's keep-out zone markers (arm.zone_topics): what RViz gets for config/zones.yaml."""
import os

import pytest
import rospy
from visualization_msgs.msg import Marker

from robopuppet import baxter_description as bd
from robopuppet.arm import zone_topics
from robopuppet.world import shapes, zones

ZONES_FILE = os.path.join(os.path.dirname(bd.URDF_PATH), '..', 'config', 'zones.yaml')


def test_every_zone_is_a_translucent_shape_with_its_name_above_it():
    found = zones.load_zones(ZONES_FILE) + [shapes.parse_shape(
        {'name': 'pole', 'type': 'cylinder', 'radius': 0.05, 'length': 1.2,
         'xyz': [0.2, 0.9, 0.0], 'colour': [0.2, 0.2, 0.9]})]
    markers = zone_topics.zone_markers(found, rospy.Time(5)).markers
    assert markers[0].action == Marker.DELETEALL
    shapes_drawn = [m for m in markers if m.ns == zone_topics.NAMESPACE and m.action == Marker.ADD]
    names = [m for m in markers if m.ns == zone_topics.NAME_NAMESPACE]
    assert [m.text for m in names] == [z.name for z in found]
    assert all(m.header.frame_id == bd.BASE_FRAME and m.header.stamp == rospy.Time(5)
               for m in markers)
    head, body, bed, pole = shapes_drawn
    assert head.type == Marker.SPHERE and head.scale.x == pytest.approx(0.36)
    assert body.type == Marker.CUBE and (body.scale.x, body.scale.y) == (0.66, 1.62)
    assert (pole.type, pole.scale.x, pole.scale.z) == (Marker.CYLINDER, 0.1, 1.2)
    assert (pole.color.b, pole.color.a) == (pytest.approx(0.9), pytest.approx(0.3))
    assert (head.color.r, head.color.a) == (pytest.approx(0.9), pytest.approx(0.3))
    assert len({m.id for m in shapes_drawn}) == 4
    assert names[0].pose.position.z > head.pose.position.z + 0.18   # above the sphere


def colours(array):
    """Return {(namespace, id): (r, g, b, a)} of a MarkerArray's ADD shape markers."""
    return {(m.ns, m.id): (m.color.r, m.color.g, m.color.b, m.color.a) for m in array.markers
            if m.action == Marker.ADD and m.type != Marker.TEXT_VIEW_FACING}


HELD_R = zone_topics.HELD_NAMESPACE + ' (arm_R)'


def added(array, ns):
    """Return the ADD markers of a namespace."""
    return [m for m in array.markers if m.ns == ns and m.action == Marker.ADD]


def test_a_zone_holding_an_arm_is_drawn_over_in_a_strong_colour_with_its_arm_named():
    found = zones.load_zones(ZONES_FILE)
    plain = zone_topics.zone_markers(found, rospy.Time(5))
    assert not [m for m in plain.markers if m.ns.startswith(zone_topics.HELD_NAMESPACE)]
    held = zone_topics.held_markers(found, rospy.Time(5), {'patient head': ['left']}, 'arm_R')
    head = [z.name for z in found].index('patient head')
    shape, text = added(held, HELD_R)
    assert (shape.id, text.id) == (head, len(found) + head)
    r, g, b, a = shape.color.r, shape.color.g, shape.color.b, shape.color.a
    assert a >= 0.8 and r == pytest.approx(1.0) and b < 0.2   # opaque-ish orange, not red
    assert shape.type == Marker.SPHERE and shape.scale.x > 0.36   # over the zone
    assert shape.pose.position.y == pytest.approx(0.80)
    assert text.text == "'patient head' holds back Baxter's left arm"
    assert all(m.header.frame_id == bd.BASE_FRAME for m in held.markers)
    both = zone_topics.held_markers(found, rospy.Time(5), zone_topics.holding_zones(
        'bed', 'bed'), 'arm_R')
    assert [m.text for m in added(both, HELD_R) if m.text] == [
        "'bed' holds back Baxter's left and right arms"]


def test_highlights_are_whole_and_leave_the_other_controllers_alone():
    # Both arm controllers publish on one topic: neither may wipe the other's highlight (no
    # DELETEALL), and each message says all of its own (a zone no longer holding is deleted).
    found = zones.load_zones(ZONES_FILE)
    none = zone_topics.held_markers(found, rospy.Time(5), {}, 'arm_L')
    assert {m.action for m in none.markers} == {Marker.DELETE}
    assert {m.ns for m in none.markers} == {zone_topics.HELD_NAMESPACE + ' (arm_L)'}
    assert sorted(m.id for m in none.markers) == list(range(2 * len(found)))
    held = zone_topics.held_markers(found, rospy.Time(5), {'bed': ['right']}, 'arm_R')
    assert {m.ns for m in held.markers} == {HELD_R}
    assert len(held.markers) == 2 * len(found)   # each id added or deleted


def test_holding_zones_from_teleop_states_fields():
    assert zone_topics.holding_zones('', '') == {}
    assert zone_topics.holding_zones('bed', '') == {'bed': ['left']}
    assert zone_topics.holding_zones('bed', 'patient head') == {'bed': ['left'],
                                                                'patient head': ['right']}


class Recorder:
    def __init__(self, fail=False):
        self.sent, self.fail = [], fail

    def publish(self, array):
        if self.fail:
            raise RuntimeError('publisher closed')
        self.sent.append(array)


def held_texts(array):
    return [m.text for m in added(array, HELD_R) if m.text]


def test_the_view_republishes_only_when_the_holding_zones_change(monkeypatch):
    monkeypatch.setattr(rospy.Time, 'now', staticmethod(lambda: rospy.Time(9)))
    found = zones.load_zones(ZONES_FILE)
    out = Recorder()
    view = zone_topics.ZoneView(out, found, 'arm_R')
    view.show(0.0, '', '')                       # as published at start: nothing new
    assert out.sent == []
    view.show(1.0, 'patient head', '')
    view.show(1.01, 'patient head', '')          # every report at the command rate: once
    assert [held_texts(a) for a in out.sent] == [["'patient head' holds back Baxter's left arm"]]
    view.show(1.05, '', '')                      # too soon after the last: held back ...
    assert len(out.sent) == 1
    view.show(1.3, '', '')                       # ... and sent with a later report
    assert len(out.sent) == 2 and held_texts(out.sent[-1]) == []


def test_a_failed_publish_never_reaches_the_caller(monkeypatch):
    monkeypatch.setattr(rospy.Time, 'now', staticmethod(lambda: rospy.Time(9)))
    view = zone_topics.ZoneView(Recorder(fail=True), zones.load_zones(ZONES_FILE), 'arm_R')
    view.show(1.0, 'bed', '')                    # logged, not raised
    zone_topics.ZoneView(Recorder(), [], 'arm_R').show(1.0, 'bed', '')   # no zones: nothing
