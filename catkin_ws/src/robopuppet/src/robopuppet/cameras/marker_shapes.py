"""The solid shapes a visualization_msgs/MarkerArray draws, as world.shapes Shapes: the study's
task objects (interface.STUDY_MARKERS), which the simulated cameras draw where RViz shows them.

Reads messages only (no rospy): markers in, Shapes out (shape_markers.shape_marker's inverse).
"""
import math

from visualization_msgs.msg import Marker

from robopuppet.world.shapes import Shape


def _rpy(q):
    """Return (roll, pitch, yaw) of a geometry_msgs/Quaternion (identity when not unit-like)."""
    x, y, z, w = q.x, q.y, q.z, q.w
    norm = math.sqrt(x * x + y * y + z * z + w * w)
    if not 0.5 < norm < 2.0:
        return 0.0, 0.0, 0.0
    x, y, z, w = x / norm, y / norm, z / norm, w / norm
    return (math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y)),
            math.asin(max(-1.0, min(1.0, 2.0 * (w * y - z * x)))),
            math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z)))


def marker_shape(marker):
    """Return the Shape a CUBE, SPHERE or CYLINDER marker draws (in its own frame, taken as
    Baxter's base), or None for any other marker or a non-finite or non-positive size."""
    kinds = {Marker.CUBE: 'box', Marker.SPHERE: 'sphere', Marker.CYLINDER: 'cylinder'}
    scale, point, c = marker.scale, marker.pose.position, marker.color
    numbers = (scale.x, scale.y, scale.z, point.x, point.y, point.z)
    if marker.type not in kinds or not all(math.isfinite(v) for v in numbers) or \
            min(scale.x, scale.y, scale.z) <= 0.0:
        return None
    kind = kinds[marker.type]
    return Shape('%s/%d' % (marker.ns, marker.id), kind,
                 (scale.x, scale.y, scale.z) if kind == 'box' else None,
                 None if kind == 'box' else scale.x / 2.0,
                 scale.z if kind == 'cylinder' else None, (point.x, point.y, point.z),
                 _rpy(marker.pose.orientation), (c.r, c.g, c.b))


def apply_markers(shown, markers):
    """Update {(ns, id): Shape} by a MarkerArray's markers (ADD/MODIFY, DELETE, DELETEALL) and
    return it: what RViz would show of them as solid shapes."""
    for marker in markers:
        key = (marker.ns, marker.id)
        if marker.action == Marker.DELETEALL:
            shown.clear()
        elif marker.action == Marker.DELETE:
            shown.pop(key, None)
        else:
            shape = marker_shape(marker)
            if shape is None:
                shown.pop(key, None)
            else:
                shown[key] = shape
    return shown
