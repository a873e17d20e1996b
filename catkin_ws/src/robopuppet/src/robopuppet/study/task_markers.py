"""A study trial's RViz markers (an adapter): study.task_shapes' shapes and lines as messages.

The study runner publishes task_markers(judge, stamp) on interface.STUDY_MARKERS (latched); the
simulated cameras draw its solid shapes too (cameras.marker_shapes).
"""
from geometry_msgs.msg import Point, Pose, Quaternion, Vector3
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker

from robopuppet import shape_markers
from robopuppet.study import task_shapes as drawing

NAMESPACE, LINE_NAMESPACE, TEXT_NAMESPACE = 'study task', 'study task path', 'study task detail'
LINE_WIDTH_M = 0.008
TEXT_RGBA = (1.0, 1.0, 1.0, 0.9)


def task_markers(judge, stamp):
    """Return the MarkerArray of a trial now (task_judge.TrialJudge): a DELETEALL (what an
    earlier state drew goes), the shapes, the trace's path and the judge's detail above the
    first goal or object."""
    markers = [Marker(ns=NAMESPACE, action=Marker.DELETEALL)]
    shapes = drawing.task_shapes(judge)
    markers += [shape_markers.shape_marker(shape, NAMESPACE, n, rgba)
                for n, (shape, rgba) in enumerate(shapes)]
    for n, (_, points, rgba) in enumerate(drawing.task_lines(judge)):
        markers.append(Marker(ns=LINE_NAMESPACE, id=n, type=Marker.LINE_STRIP,
                              action=Marker.ADD, pose=Pose(orientation=Quaternion(0, 0, 0, 1)),
                              scale=Vector3(LINE_WIDTH_M, 0.0, 0.0), color=ColorRGBA(*rgba),
                              points=[Point(*xyz) for xyz in points]))
    if shapes:
        markers.append(shape_markers.text_marker(TEXT_NAMESPACE, 0, judge.detail,
                                                 shape_markers.label_xyz(shapes[0][0]),
                                                 TEXT_RGBA))
    return shape_markers.marker_array(markers, stamp)
