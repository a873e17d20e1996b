"""The room in RViz (shape_markers.room_markers): config/world.yaml's shapes and the obstacles,
one muted marker each, as the simulated cameras draw them."""
import colorsys
import os

import numpy as np
import pytest
import rospy
from visualization_msgs.msg import Marker

from robopuppet import baxter_description as bd, shape_markers
from robopuppet.cameras import scene
from robopuppet.world import obstacles, shapes

CONFIG = os.path.join(os.path.dirname(bd.URDF_PATH), '..', 'config')
WORLD = scene.load_world(os.path.join(CONFIG, 'world.yaml'))
BED = obstacles.load_obstacles(os.path.join(CONFIG, 'bed_obstacles.yaml'))
POLE = shapes.parse_shape({'name': 'drip stand', 'type': 'cylinder', 'radius': 0.05,
                           'length': 1.8, 'xyz': [0.2, 0.95, -0.03], 'rpy': [0.0, 0.3, 0.0]})


def drawn(found):
    markers = shape_markers.room_markers(found, rospy.Time(3)).markers
    assert markers[0].action == Marker.DELETEALL
    return markers[1:]


def test_one_marker_per_shape_of_the_world_and_the_obstacles_it_lacks():
    found = shape_markers.room_shapes(WORLD.shapes, BED + [POLE])
    assert BED and all(b in WORLD.shapes for b in BED)   # the shipped bed is the world's own
    assert [s.name for s in found] == [s.name for s in WORLD.shapes] + ['drip stand']
    markers = drawn(found)
    assert len(markers) == len(found) == len({m.id for m in markers})
    assert all(m.header.frame_id == bd.BASE_FRAME and m.header.stamp == rospy.Time(3)
               and m.ns == shape_markers.ROOM_NAMESPACE and m.action == Marker.ADD
               for m in markers)


def test_sizes_and_poses_come_from_the_file():
    found = list(WORLD.shapes) + [POLE]
    by_name = dict(zip((s.name for s in found), drawn(found)))
    mattress = by_name['mattress']
    assert mattress.type == Marker.CUBE
    assert (mattress.scale.x, mattress.scale.y, mattress.scale.z) == (0.90, 1.98, 0.15)
    assert (mattress.pose.position.x, mattress.pose.position.y,
            mattress.pose.position.z) == (0.85, 0.0, -0.36)
    head = by_name['patient_head']
    assert head.type == Marker.SPHERE and head.scale.x == head.scale.z == pytest.approx(0.20)
    arm = by_name['patient_right_arm']
    assert arm.type == Marker.CYLINDER
    assert (arm.scale.x, arm.scale.z) == (pytest.approx(0.09), pytest.approx(0.58))
    for shape, marker in ((s, by_name[s.name]) for s in (POLE, WORLD.shapes[11])):
        q = marker.pose.orientation
        assert np.allclose(bd.matrix_quaternion(bd.rpy_matrix(*shape.rpy)), (q.x, q.y, q.z, q.w))
        assert (q.x, q.y, q.z, q.w) != (0.0, 0.0, 0.0, 1.0)   # the file's rpy, not upright


def test_colours_are_the_files_muted():
    for shape, marker in zip(WORLD.shapes, drawn(WORLD.shapes)):
        c = marker.color
        assert c.a < 1.0
        own = colorsys.rgb_to_hsv(*shape.colour)[1]
        shown = colorsys.rgb_to_hsv(c.r, c.g, c.b)[1]
        assert shown <= own * 0.75 + 1e-9, shape.name          # less saturated
        assert np.dot((c.r - 0.55, c.g - 0.55, c.b - 0.55),     # towards the file's colour
                      np.subtract(shape.colour, 0.55)) >= 0.0
    default, = drawn([POLE])
    assert (default.color.r, default.color.g, default.color.b) == pytest.approx(
        shape_markers.muted(shape_markers.ROOM_DEFAULT_COLOUR)[:3])
