"""A trial's MarkerArray: earlier markers cleared, its solid shapes as the cameras read them back,
the trace's path and the judge's detail."""
import numpy as np
import pytest
from visualization_msgs.msg import Marker

from robopuppet.cameras import marker_shapes
from robopuppet.study import task_markers, tasks
from robopuppet.study.task_judge import TrialJudge


def test_the_markers_clear_draw_and_read_back_as_the_shapes():
    trial = tasks.make_trial('pick_place', 2)
    a = trial.plan[0].goals[0]
    judge = TrialJudge(trial, 0.0)
    array = task_markers.task_markers(judge, 0)
    assert array.markers[0].action == Marker.DELETEALL
    assert all(m.header.frame_id == 'base' for m in array.markers)
    shown = marker_shapes.apply_markers({}, array.markers)
    cube = [s for s in shown.values() if s.type == 'box']
    assert len(cube) == 1 and cube[0].xyz == pytest.approx(a.xyz)
    texts = [m for m in array.markers if m.type == Marker.TEXT_VIEW_FACING]
    assert [m.text for m in texts] == [judge.detail]


def test_the_trace_has_a_line_through_its_waypoints():
    trial = tasks.make_trial('trace', 1)
    array = task_markers.task_markers(TrialJudge(trial, 0.0), 0)
    (line,) = [m for m in array.markers if m.type == Marker.LINE_STRIP]
    points = [(p.x, p.y, p.z) for p in line.points]
    assert np.allclose(points, [stage.goals[0].xyz for stage in trial.plan])
