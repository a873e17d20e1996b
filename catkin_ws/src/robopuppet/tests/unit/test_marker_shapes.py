"""A MarkerArray's solid markers come back as the Shapes they draw (the cameras' task objects)."""
import numpy as np
from visualization_msgs.msg import Marker

from robopuppet import baxter_description as bd, shape_markers
from robopuppet.cameras import marker_shapes
from robopuppet.world import shapes


def test_the_shapes_a_marker_array_draws_come_back_as_shapes():
    box = shapes.parse_shape({'name': 'tray', 'type': 'box', 'size': [0.4, 0.3, 0.02],
                              'xyz': [0.7, -0.2, 0.1], 'rpy': [0.0, 0.0, 0.5],
                              'colour': [0.2, 0.6, 0.9]})
    ball = shapes.parse_shape({'name': 'cup', 'type': 'sphere', 'radius': 0.03,
                               'xyz': [0.6, 0.1, 0.0]})
    can = shapes.parse_shape({'name': 'can', 'type': 'cylinder', 'radius': 0.04, 'length': 0.1,
                              'xyz': [0.5, 0.0, 0.05], 'rpy': [0.1, 0.2, 0.3]})
    markers = [shape_markers.shape_marker(s, 'task', i, (0.2, 0.6, 0.9, 1.0))
               for i, s in enumerate((box, ball, can))]
    markers.append(shape_markers.text_marker('task', 9, 'hold', (0, 0, 1), (1, 1, 1, 1)))
    shown = marker_shapes.apply_markers({}, markers)
    assert sorted(shown) == [('task', 0), ('task', 1), ('task', 2)]   # the text is no solid
    for index, shape in enumerate((box, ball, can)):
        back = shown['task', index]
        assert back.type == shape.type
        assert np.allclose(back.xyz, shape.xyz)
        assert np.allclose(bd.rpy_matrix(*back.rpy), bd.rpy_matrix(*shape.rpy), atol=1e-9)
        for field in ('size', 'radius', 'length'):
            assert (getattr(back, field) is None) == (getattr(shape, field) is None)
            if getattr(shape, field) is not None:
                assert np.allclose(getattr(back, field), getattr(shape, field))
    gone = Marker(ns='task', id=1, action=Marker.DELETE)
    assert sorted(marker_shapes.apply_markers(shown, [gone])) == [('task', 0), ('task', 2)]
    assert marker_shapes.apply_markers(shown, [Marker(action=Marker.DELETEALL)]) == {}


def test_a_marker_of_nonsense_size_is_no_shape():
    marker = shape_markers.shape_marker(shapes.parse_shape(
        {'name': 'b', 'type': 'sphere', 'radius': 0.1, 'xyz': [0, 0, 0]}), 'task', 0,
        (1, 1, 1, 1))
    marker.scale.x = float('nan')
    assert marker_shapes.marker_shape(marker) is None
    marker.scale.x = 0.0
    assert marker_shapes.marker_shape(marker) is None
    assert marker_shapes.apply_markers({('task', 0): 'old'}, [marker]) == {}
