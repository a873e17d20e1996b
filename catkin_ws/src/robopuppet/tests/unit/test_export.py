"""The exporter's pure core: resampling, ALOHA arrays, CSV rows and plot series, checked against
numbers computed by hand. Messages are plain objects with the ROS messages' fields."""
from types import SimpleNamespace as Msg

import numpy as np
import pytest

from robopuppet.episodes import export, export_plot, export_stream
from robopuppet.episodes.export import Samples

T0 = 100.0  # grid 100.0, 100.0625, 100.125 at 16 Hz: binary fractions, so sums are exact
RATE_HZ = 16.0
LEFT = ['left_s0', 'left_s1', 'left_e0', 'left_e1', 'left_w0', 'left_w1', 'left_w2']
RIGHT = [n.replace('left', 'right') for n in LEFT]


def joint_states(t, offset):
    """Baxter's joint states, right arm first and names reversed: order must not matter.
    left joint j: 0.1 j + offset; right joint j: -0.1 j - offset; velocity 1.0 j; effort 2 j."""
    names = (RIGHT + LEFT)[::-1] + ['head_pan']
    value = {n: (0.1 * (j % 7) + offset) * (1 if n.startswith('left') else -1)
             for j, n in enumerate(LEFT + RIGHT)}
    value['head_pan'] = 9.0
    joints = {n: j % 7 for j, n in enumerate(LEFT + RIGHT)}
    joints['head_pan'] = 0
    return ('/robot/joint_states',
            Msg(name=names, position=[value[n] for n in names],
                velocity=[1.0 * joints[n] for n in names],
                effort=[2.0 * joints[n] for n in names]), t)


def messages():
    """An episode of three grid steps: puppet R drives Baxter's right arm and gripper."""
    return [
        joint_states(T0, 0.0),
        joint_states(T0 + 0.125, 0.4),
        ('/robot/limb/right/joint_command', Msg(mode=2, names=RIGHT, command=[7.0] * 7), T0),
        ('/robot/limb/right/joint_command',
         Msg(mode=1, names=['right_e0'], command=[0.5]), T0 + 0.05),
        ('/robot/end_effector/right_gripper/state', Msg(position=40.0, force=10.0), T0),
        ('/robot/end_effector/right_gripper/state', Msg(position=100.0, force=30.0), T0 + 0.125),
        ('/robot/end_effector/right_gripper/command',
         Msg(command='calibrate', args=''), T0 + 0.01),
        ('/robot/end_effector/right_gripper/command',
         Msg(command='go', args='{"position": 0.0}'), T0 + 0.1),
        ('/puppet/arm_R/joint_states',
         Msg(name=['joint_%d' % j for j in range(7)], position=[0.3, 0.2, 0.1, 0, 0, 0, 0.6]),
         T0),
        ('/puppet/arm_R/gripper_3', Msg(data=1.0), T0),
        ('/puppet/arm_R/gripper_3', Msg(data=0.0), T0 + 0.125),
    ]


def test_the_columns_are_alohas_order_and_rethinks_header():
    assert ','.join(export.CSV_HEADER) == (
        'time,left_s0,left_s1,left_e0,left_e1,left_w0,left_w1,left_w2,left_gripper,'
        'right_s0,right_s1,right_e0,right_e1,right_w0,right_w1,right_w2,right_gripper')


def test_the_time_grid_steps_at_the_rate_and_stops_at_the_end():
    assert list(export.time_grid(10.0, 11.0, 4.0)) == [10.0, 10.25, 10.5, 10.75, 11.0]
    assert list(export.time_grid(0.0, 0.99, 2.0)) == [0.0, 0.5]
    assert list(export.time_grid(5.0, 5.0, 50.0)) == [5.0]
    with pytest.raises(export.ExportError):
        export.time_grid(0.0, 1.0, 0.0)


def test_interpolation_is_linear_per_column_over_finite_values():
    samples = Samples(np.array([0.0, 1.0, 2.0]),
                      np.array([[0.0, np.nan], [2.0, 4.0], [2.0, np.nan]]))
    got = export.interpolate(samples, np.array([-1.0, 0.0, 0.25, 0.5, 1.5, 3.0]))
    assert got[:, 0].tolist() == [0.0, 0.0, 0.5, 1.0, 2.0, 2.0]
    assert got[:, 1].tolist() == [4.0] * 6  # one finite value: held flat both ways


def test_hold_takes_the_last_value_at_or_before_each_time():
    samples = Samples(np.array([0.25, 0.75, 1.0]),
                      np.array([[1.0, 5.0], [3.0, np.nan], [4.0, 6.0]]))
    got = export.hold(samples, np.array([0.0, 0.25, 0.5, 0.75, 0.9, 2.0]))
    assert np.array_equal(got[:, 0], [np.nan, 1.0, 1.0, 3.0, 3.0, 4.0], equal_nan=True)
    assert np.array_equal(got[:, 1], [np.nan, 5.0, 5.0, 5.0, 5.0, 6.0], equal_nan=True)


def test_aloha_arrays_against_hand_computed_values():
    arrays = export.aloha_arrays(export.collect(messages()), RATE_HZ)
    assert arrays['time'].tolist() == [0.0, 0.0625, 0.125]
    for name in ('qpos', 'qvel', 'effort', 'action'):
        assert arrays[name].shape == (3, 16)
    col = export.COLUMNS.index
    # measured: left_w1 (j=5) 0.5 -> 0.9, right_w1 -0.5 -> -0.9, linear in between
    assert arrays['qpos'][:, col('left_w1')] == pytest.approx([0.5, 0.7, 0.9])
    assert arrays['qpos'][:, col('right_w1')] == pytest.approx([-0.5, -0.7, -0.9])
    assert arrays['qvel'][:, col('right_e1')].tolist() == [3.0] * 3
    assert arrays['effort'][:, col('left_w2')].tolist() == [12.0] * 3
    # gripper: 40 % -> 100 % opening, its rate (1.0 - 0.4) / 0.125 s, force 10 % -> 30 %
    assert arrays['qpos'][:, col('right_gripper')].tolist() == [0.4, 0.7, 1.0]
    assert arrays['qvel'][:, col('right_gripper')] == pytest.approx([4.8] * 3)
    assert arrays['effort'][:, col('right_gripper')] == pytest.approx([0.1, 0.2, 0.3])
    assert arrays['qpos'][:, col('left_gripper')].tolist() == [0.0] * 3  # no state: 0
    # action: right_e0 held at 0.5 from t = 0.05 s (the velocity command is no position);
    # uncommanded joints and the gripper before its 'go' take the measured position
    assert arrays['action'][:, col('right_e0')] == pytest.approx([-0.2, 0.5, 0.5])
    assert arrays['action'][:, col('right_s1')] == pytest.approx([-0.1, -0.3, -0.5])
    assert arrays['action'][:, col('right_gripper')].tolist() == [0.4, 0.7, 0.0]
    assert arrays['action'][:, col('left_s0')] == pytest.approx([0.0, 0.2, 0.4])


def test_an_episode_without_baxters_joints_does_not_export():
    with pytest.raises(export.ExportError, match='no /robot/joint_states'):
        export.aloha_arrays(export.collect(messages()[2:]), RATE_HZ)
    partial = Msg(name=LEFT, position=[0.0] * 7, velocity=[], effort=[])
    with pytest.raises(export.ExportError, match='right_s0'):
        export.aloha_arrays(export.collect([('/robot/joint_states', partial, 1.0)]), RATE_HZ)


def test_csv_lines_are_rethinks_rows():
    lines = export.csv_lines(export.aloha_arrays(export.collect(messages()), RATE_HZ))
    assert len(lines) == 4
    assert lines[0] == ','.join(export.CSV_HEADER)
    first = lines[1].split(',')
    assert first[0] == '0.000000'
    assert [float(v) for v in first[1:8]] == pytest.approx([0.1 * j for j in range(7)])
    assert first[8] == '0.0' and first[16] == '40.0'  # grippers in percent, as Rethink's
    last = lines[3].split(',')
    assert last[0] == '0.125000' and last[16] == '100.0'
    assert float(last[9]) == pytest.approx(-0.4)


def test_plot_series_maps_the_driving_puppet_onto_the_arm():
    recording = export.collect(messages())
    series = export_plot.plot_series(recording, export.aloha_arrays(recording, RATE_HZ))
    assert list(series) == ['right']
    right = series['right']
    assert right['driver'] == 'R'
    assert right['puppet'][0].tolist() == [0.3, 0.2, 0.1, 0, 0, 0, 0.6]  # same side: copied
    assert np.isnan(right['commanded'][0, 2]) and right['commanded'][1, 2] == 0.5
    assert right['error'][1, 2] == pytest.approx(0.5 - (-0.4))
    assert right['end_piece'].tolist() == [1.0, 0.5, 0.0]
    assert right['gripper_commanded'][2] == 0.0 and np.isnan(right['gripper_commanded'][0])


def test_the_opposite_arm_mirrors_joints_0_2_4_6():
    following = ('/puppet/arm_R/teleop_state', Msg(follow_left=True, follow_right=False), T0)
    command = ('/robot/limb/left/joint_command', Msg(mode=1, names=LEFT, command=[0.0] * 7), T0)
    recording = export.collect([m for m in messages() if 'right' not in m[0]]
                               + [following, command])
    series = export_plot.plot_series(recording, export.aloha_arrays(recording, RATE_HZ))
    assert list(series) == ['left'] and series['left']['driver'] == 'R'
    assert series['left']['puppet'][0].tolist() == [-0.3, 0.2, -0.1, 0, 0, 0, -0.6]


def long_messages(puppet_end_s):
    """An episode of 4 s in time order: Baxter's joint states at 64 Hz, the right arm's
    commands at 32 Hz, its gripper's state, the puppet's angles and end piece at 8 Hz (coarser
    than the 16 Hz grid: rows between two samples interpolate), until T0 + puppet_end_s for
    the puppet's. At each time the joint states come first: the stream's flushes (every 2 s)
    fall on them, before the other topics' messages of that time."""
    out = [('/puppet/arm_R/teleop_state', Msg(follow_left=False, follow_right=True), T0)]
    for k in range(4 * 64 + 1):
        t = T0 + k / 64.0
        out.append(joint_states(t, 0.5 * np.sin(k / 10.0)))
        if k % 2 == 0:
            out.append(('/robot/limb/right/joint_command',
                        Msg(mode=1, names=RIGHT, command=[np.cos(k / 7.0)] * 7), t))
        if k % 8:
            continue
        out.append(('/robot/end_effector/right_gripper/state',
                    Msg(position=100.0 if k % 16 else 30.0, force=float(k % 50)), t))
        if k % 64 == 0:
            out.append(('/robot/end_effector/right_gripper/command',
                        Msg(command='go', args='{"position": %d}' % (k % 128)), t))
        if t <= T0 + puppet_end_s:
            out.append(('/puppet/arm_R/joint_states',
                        Msg(name=['joint_%d' % j for j in range(7)],
                            position=[np.sin(k / 9.0 + j) for j in range(7)]), t))
            out.append(('/puppet/arm_R/gripper_3', Msg(data=float(k % 16 == 0)), t))
    return out


@pytest.mark.parametrize('puppet_end_s', [2.0, 4.0])
def test_the_streamed_rows_and_plot_series_are_the_whole_episodes(puppet_end_s):
    """export_stream hands out, block by block, aloha_arrays' rows and plot_series' series,
    also where a topic's last message comes after another topic's message of the same time
    (its rows must wait for it, not hold the value before)."""
    messages_ = long_messages(puppet_end_s)
    recording = export.collect(messages_)
    whole = export.aloha_arrays(recording, RATE_HZ)
    topic_end_s = {}
    for topic, _, t in messages_:
        topic_end_s[topic] = t
    times = recording.position.times
    stream = export_stream.EpisodeStream(RATE_HZ, times[0], times[-1], topic_end_s, plot=True)
    blocks = [block for m in messages_ for block in stream.add(*m)] + stream.finish()
    assert len(blocks) > 2 and [b['start'] for b in blocks] == list(np.cumsum(
        [0] + [len(b['time']) for b in blocks[:-1]]))
    rows = {key: np.concatenate([b[key] for b in blocks]) for key in whole}
    for key in whole:
        np.testing.assert_allclose(rows[key], whole[key], rtol=0, atol=1e-12, err_msg=key)
    streamed = export_plot.plot_rows(
        rows, *[{s: np.concatenate([b[key][s] for b in blocks]) for s in export.PUPPET_SIDES}
                for key in ('puppet', 'end_piece')],
        stream.commanded_sides, stream.puppet_sides, stream.follow)
    expected = export_plot.plot_series(recording, whole)
    assert list(streamed) == list(expected) == ['right']
    for key, value in expected['right'].items():
        if key == 'driver':
            assert streamed['right'][key] == value == 'R'
        else:
            np.testing.assert_allclose(streamed['right'][key], value, rtol=0, atol=1e-12,
                                       err_msg=key)


def flat_and_overshooting_series(steps=50):
    """Return plot series of the right arm: joint 0's puppet trace 10 deg above commanded and
    measured; joint 1 not moving (its error ~1e-15 rad); others a slow ramp."""
    ramp = np.linspace(0.0, 0.5, steps)[:, None] * np.ones((1, 7))
    measured = ramp.copy()
    measured[:, 1] = 0.3
    commanded = measured + 1e-3
    commanded[:, 1] = 0.3 + 1e-15 * np.sin(np.arange(steps))
    puppet = commanded.copy()
    puppet[:, 0] += np.radians(10.0)
    return {'right': {'driver': 'R', 'puppet': puppet, 'commanded': commanded,
                      'measured': measured, 'error': commanded - measured,
                      'gripper_commanded': np.ones(steps), 'gripper_measured': np.ones(steps),
                      'end_piece': np.ones(steps)}}


def test_plot_limits_hold_every_trace_and_a_flat_error_looks_flat():
    series = flat_and_overshooting_series()
    figure = export_plot.plot_figure(series, np.arange(50) * 0.02, 'test')
    axes = figure.axes
    try:
        s0, s1_error = axes[0], axes[3]  # rows of (value, error): s0 then s1's error panel
        low, high = s0.get_ylim()
        for line in s0.get_lines():  # the puppet's trace (10 deg above) included
            assert low <= np.nanmin(line.get_ydata()) and np.nanmax(line.get_ydata()) <= high
        assert np.degrees(series['right']['puppet'][:, 0]).max() < high
        figure.canvas.draw()  # the legend sits above the panel, not on its traces' tops
        assert s0.get_legend().get_window_extent().y0 >= s0.get_window_extent().y1 - 1
        low, high = s1_error.get_ylim()
        assert low <= -1.0 and high >= 1.0  # not 1e-15 blown up to fill the panel
        assert high - low < 2.5
    finally:
        import matplotlib.pyplot as plt
        plt.close(figure)


def test_y_limits_have_a_margin_a_minimum_range_and_ignore_nan():
    assert export_plot.y_limits([np.array([0.0, 10.0])], 1.0) == (-0.8, 10.8)
    assert export_plot.y_limits([np.array([5.0, 5.0]), np.array([np.nan])], 1.0) == (4.0, 6.0)
    assert export_plot.y_limits([np.array([1e-15, -1e-15])], 1.0, include_zero=True) == (
        -1.0, 1.0)
    assert export_plot.y_limits([np.array([0.5, 3.0])], 1.0, include_zero=True) == (
        -1.0, pytest.approx(3.24))  # at least 1 either side of 0
    assert export_plot.y_limits([np.array([np.nan])], 0.05) == (-0.05, 0.05)
