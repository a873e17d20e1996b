"""RViz markers of shape-file shapes (world.shapes' Shape: box, sphere, cylinder) in Baxter's
base frame: the keep-out zones (arm.zone_topics) and the room (cameras.sim_camera_node).

Builds messages only (no rospy): shapes in, visualization_msgs/Marker out.
"""
from geometry_msgs.msg import Point, Pose, Quaternion, Vector3
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from robopuppet import baxter_description as bd

TEXT_HEIGHT_M = 0.05
UPRIGHT = Quaternion(0.0, 0.0, 0.0, 1.0)
ROOM_NAMESPACE = 'room'
ROOM_GREY, ROOM_MIX, ROOM_ALPHA = 0.55, 0.5, 0.6   # muted: half the shape's colour, half grey
ROOM_DEFAULT_COLOUR = (0.7, 0.7, 0.7)              # cameras.scene's default


def shape_marker(shape, ns, index, rgba, grow_m=0.0):
    """Return the ADD marker drawing a Shape in colour rgba (4 floats 0..1), each side grown
    by 2 * grow_m (a highlight drawn over the shape itself)."""
    quaternion = bd.matrix_quaternion(bd.rpy_matrix(*shape.rpy))
    marker = Marker(ns=ns, id=index, action=Marker.ADD,
                    pose=Pose(Point(*shape.xyz), Quaternion(*quaternion)),
                    color=ColorRGBA(*rgba))
    grow = 2.0 * grow_m
    if shape.type == 'box':
        marker.type, marker.scale = Marker.CUBE, Vector3(*[s + grow for s in shape.size])
    elif shape.type == 'sphere':
        marker.type, marker.scale = Marker.SPHERE, Vector3(*[2.0 * shape.radius + grow] * 3)
    else:
        marker.type = Marker.CYLINDER
        width = 2.0 * shape.radius + grow
        marker.scale = Vector3(width, width, shape.length + grow)
    return marker


def top_z(shape):
    """Return the height (m) of the top of a Shape's bounding sphere or box (rpy ignored)."""
    return shape.xyz[2] + (shape.size[2] / 2.0 if shape.type == 'box' else
                           shape.radius if shape.type == 'sphere' else shape.length / 2.0)


def label_xyz(shape):
    """Return where a shape's label goes: one text height above its top."""
    return shape.xyz[0], shape.xyz[1], top_z(shape) + TEXT_HEIGHT_M


def text_marker(ns, index, text, xyz, rgba, height_m=TEXT_HEIGHT_M):
    """Return a text marker facing the viewer at xyz."""
    return Marker(ns=ns, id=index, action=Marker.ADD, type=Marker.TEXT_VIEW_FACING, text=text,
                  scale=Vector3(0.0, 0.0, height_m), pose=Pose(Point(*xyz), UPRIGHT),
                  color=ColorRGBA(*rgba))


def marker_array(markers, stamp):
    """Return a MarkerArray of markers, each stamped and in Baxter's base frame."""
    for marker in markers:
        marker.header.frame_id, marker.header.stamp = bd.BASE_FRAME, stamp
    return MarkerArray(markers=markers)


def muted(rgb):
    """Return a room shape's colour, half its own and half grey, at ROOM_ALPHA."""
    return tuple(ROOM_MIX * c + (1.0 - ROOM_MIX) * ROOM_GREY for c in rgb) + (ROOM_ALPHA,)


def room_markers(found, stamp):
    """Return the MarkerArray of the room: a DELETEALL (shapes of an earlier file go), then one
    marker per Shape (namespace 'room', id its index), muted so that zones and robots stand
    out."""
    markers = [Marker(ns=ROOM_NAMESPACE, action=Marker.DELETEALL)]
    markers += [shape_marker(shape, ROOM_NAMESPACE, index,
                             muted(shape.colour or ROOM_DEFAULT_COLOUR))
                for index, shape in enumerate(found)]
    return marker_array(markers, stamp)


def room_shapes(world_shapes, obstacles):
    """Return the world file's shapes, then the obstacles it does not hold already (the
    shipped bed obstacles are the world's own bed shapes)."""
    return list(world_shapes) + [s for s in obstacles if s not in world_shapes]
