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
