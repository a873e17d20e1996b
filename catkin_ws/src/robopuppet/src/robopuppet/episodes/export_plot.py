"""The episode's plot (export --plot, <name>.png): per plotted Baxter arm the puppet's,
commanded and measured angles of each joint and the tracking error, then the gripper.

Pure (numpy, matplotlib through png_plot: no display needed, imported where the figure is
made, so that the commands that only read bags start sooner).
"""
import numpy as np

from robopuppet import png_plot
from robopuppet.arm.joint_motion import mirror
from robopuppet.baxter_description import arm_joint_names
from robopuppet.episodes import export
from robopuppet.interface import BAXTER_SIDE

JOINT_LABELS = ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')
# The smallest half range of a panel's y axis: a joint that did not move has an error of
# ~1e-15 rad, which autoscaling would blow up into what looks like a real error.
MIN_HALF_RANGE = {'angle_deg': 1.0, 'error_deg': 1.0, 'opening': 0.05}
MARGIN = 0.08  # of the traces' span, above and below them


def y_limits(traces, min_half_range, include_zero=False):
    """Return (low, high) that hold every finite value of traces (arrays) with a margin, at
    least min_half_range either side of their middle (of 0 with include_zero: an error)."""
    values = np.concatenate([np.ravel(np.asarray(t, float)) for t in traces] or [np.zeros(0)])
    values = values[np.isfinite(values)]
    low, high = (values.min(), values.max()) if len(values) else (0.0, 0.0)
    if include_zero:
        low, high = min(low, 0.0), max(high, 0.0)
    pad = MARGIN * (high - low)
    low, high = low - pad, high + pad
    middle = 0.0 if include_zero else (low + high) / 2.0
    return (min(low, middle - min_half_range), max(high, middle + min_half_range))


def _panel(axis, time_s, traces, min_half_range, include_zero=False, also=()):
    """Plot traces [(values, style, kwargs)] on axis and set y-limits that hold them all (and
    the values also)."""
    for values, style, kwargs in traces:
        axis.plot(time_s, values, style, **kwargs)
    axis.set_ylim(*y_limits([values for values, _, _ in traces] + list(also), min_half_range,
                            include_zero))


def plot_figure(series, time_s, title):
    """Return the figure (matplotlib): per plotted arm two columns of 8 panels. Left: per
    joint the puppet's angle as that arm takes it, the commanded and the measured angle (deg),
    then the gripper's commanded and measured opening with the puppet's end-piece reading
    (0..1). Right: the tracking error commanded - measured of each (deg; opening for the
    gripper). Each panel's y-limits hold all its traces; legends sit above the panels."""
    plt = png_plot.pyplot()
    arms = max(len(series), 1)
    figure, axes = plt.subplots(8, 2 * arms, sharex=True, squeeze=False,
                                figsize=(11 * arms, 17),
                                gridspec_kw={'width_ratios': [3, 2] * arms})
    figure.suptitle(title)
    for c, (side, data) in enumerate(sorted(series.items())):
        value_axes, error_axes = axes[:, 2 * c], axes[:, 2 * c + 1]
        for j, label in enumerate(JOINT_LABELS):
            _panel(value_axes[j], time_s, [
                (np.degrees(data['puppet'][:, j]), '-',
                 {'color': '0.6', 'lw': 3, 'label': 'puppet %s, mapped' % data['driver']}),
                (np.degrees(data['commanded'][:, j]), 'C0-', {'lw': 1, 'label': 'commanded'}),
                (np.degrees(data['measured'][:, j]), 'C1--', {'lw': 1, 'label': 'measured'})],
                MIN_HALF_RANGE['angle_deg'])
            value_axes[j].set_ylabel('%s_%s (deg)' % (side, label))
            error_axes[j].axhline(0.0, color='0.7', lw=0.5)
            _panel(error_axes[j], time_s, [(np.degrees(data['error'][:, j]), 'C3-',
                                            {'lw': 0.8})],
                   MIN_HALF_RANGE['error_deg'], include_zero=True)
            error_axes[j].set_ylabel('%s_%s error (deg)' % (side, label))
        value_axes[0].legend(fontsize=7, loc='lower right', bbox_to_anchor=(1.0, 1.0), ncol=3)
        error_axes[0].set_title('tracking error: commanded - measured', fontsize=9)
        _panel(value_axes[7], time_s, [
            (data['end_piece'], '-', {'color': '0.6', 'lw': 3,
                                      'label': 'puppet end piece (1 released)'}),
            (data['gripper_commanded'], 'C0-', {'lw': 1, 'label': 'commanded opening'}),
            (data['gripper_measured'], 'C1--', {'lw': 1, 'label': 'measured opening'})],
            MIN_HALF_RANGE['opening'], also=[[0.0, 1.0]])  # the whole 0..1 range, at least
        value_axes[7].set_ylabel('%s gripper (0..1)' % side)
        value_axes[7].legend(fontsize=7, loc='lower right', bbox_to_anchor=(1.0, 1.0), ncol=3)
        _panel(error_axes[7], time_s, [(data['gripper_commanded'] - data['gripper_measured'],
                                        'C3-', {'lw': 0.8})],
               MIN_HALF_RANGE['opening'], include_zero=True)
        error_axes[7].set_ylabel('%s gripper error' % side)
        for axis in (value_axes[7], error_axes[7]):
            axis.set_xlabel('time (s)')
    figure.tight_layout(rect=(0, 0, 1, 0.98))
    return figure


def write_plot(path, series, time_s, title):
    """Write plot_figure's figure as a PNG."""
    png_plot.write_png(path, plot_figure(series, time_s, title))


def puppet_driver(follow, puppet_sides, baxter_side):
    """Return the puppet side that drove a Baxter arm: the first whose teleop_state said it
    followed (follow: {Baxter side: puppet sides}), else the puppet side with angles
    (puppet_sides) on that side, else any with angles (None)."""
    with_angles = [s for s in export.PUPPET_SIDES if s in puppet_sides]
    if follow[baxter_side]:
        return follow[baxter_side][0]
    same = [s for s in with_angles if BAXTER_SIDE[s] == baxter_side]
    return (same or with_angles or [None])[0]


def plot_series(recording, arrays):
    """Return plot_rows' series of a Recording and its aloha_arrays."""
    grid = arrays['time'] + recording.position.times[0]
    sides = export.PUPPET_SIDES
    return plot_rows(arrays, {s: export.interpolate(recording.puppet[s], grid) for s in sides},
                     {s: export.interpolate(recording.end_piece[s], grid)[:, 0] for s in sides},
                     {s for s in export.BAXTER_SIDES if len(recording.command[s].times)},
                     {s for s in export.PUPPET_SIDES if len(recording.puppet[s].times)},
                     recording.follow)


def plot_rows(arrays, puppet, end_piece, commanded_sides, puppet_sides, follow):
    """Return {Baxter side: dict} for the plot, of each arm that got position commands
    (commanded_sides; of the recorded puppet sides' arms if none did): puppet (T, 7) the
    driving puppet's angles as that arm takes them (mirrored on the opposite side; NaN without
    a puppet), commanded, measured and error = commanded - measured (T, 7) rad,
    gripper_commanded and gripper_measured (T,) opening 0..1, end_piece (T,) the puppet's
    end-piece reading (~1 released). puppet, end_piece: {puppet side: its rows on the grid}."""
    steps = len(arrays['time'])
    sides = [s for s in export.BAXTER_SIDES if s in commanded_sides]
    sides = sides or [BAXTER_SIDE[s] for s in export.PUPPET_SIDES
                      if s in puppet_sides]
    series = {}
    for side in sides:
        columns = [export.COLUMNS.index(name) for name in arm_joint_names(side)]
        g = export.COLUMNS.index('%s_gripper' % side)
        driver = puppet_driver(follow, puppet_sides, side)
        angles, piece = np.full((steps, 7), np.nan), np.full(steps, np.nan)
        if driver is not None:
            angles, piece = puppet[driver], end_piece[driver]
            if BAXTER_SIDE[driver] != side:
                angles = np.array([mirror(row) for row in angles])
        commanded = arrays['commanded'][:, columns]
        measured = arrays['qpos'][:, columns]
        series[side] = {'driver': driver, 'puppet': angles, 'commanded': commanded,
                        'measured': measured, 'error': commanded - measured,
                        'gripper_commanded': arrays['commanded'][:, g],
                        'gripper_measured': arrays['qpos'][:, g], 'end_piece': piece}
    return series
