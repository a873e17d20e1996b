"""Turn a recorded episode's messages into fixed-rate arrays: ALOHA's layout, the rows of
Rethink's joint_recorder CSV, and the series the episode's plot draws.

Pure: messages come in as (topic, msg, t), t the arrival time (s); a message is read by its
fields only, so no ROS import. Angles in rad, velocities rad/s, efforts as Baxter reports them
(Nm), gripper positions in percent of travel (0 closed, 100 open) or as an opening 0..1.
Measured values are interpolated linearly onto the time grid; commands are held (zero-order
hold: the last command at or before each grid time).
"""
import collections
import json

import numpy as np

from robopuppet.arm.baxter_upkeep import CMD_GO, POSITION_OPEN
from robopuppet.arm.joint_motion import mirror
from robopuppet.baxter_description import arm_joint_names
from robopuppet.interface import (BAXTER_SIDE, BAXTER_SIDES, END_PIECE_GRIPPER, JOINT_STATES,
                                  PUPPET_SIDES, ROBOT_JOINT_STATES, TELEOP_STATE,
                                  baxter_gripper_topic, gripper_topic, limb_topic, puppet_ns)

DEFAULT_RATE_HZ = 50.0
POSITION_MODES = (1, 4)  # JointCommand POSITION_MODE and RAW_POSITION_MODE carry angles (rad)
ARM_JOINTS = [name for side in BAXTER_SIDES for name in arm_joint_names(side)]  # 14
# The 16 columns of qpos, qvel, effort and action, and of the CSV after its time column.
COLUMNS = [name for side in BAXTER_SIDES
           for name in arm_joint_names(side) + ['%s_gripper' % side]]
CSV_HEADER = ['time'] + COLUMNS
GRIPPER_COLUMNS = [COLUMNS.index('%s_gripper' % side) for side in BAXTER_SIDES]
ARM_COLUMNS = [c for c in range(len(COLUMNS)) if c not in GRIPPER_COLUMNS]

Samples = collections.namedtuple('Samples', 'times values')
Samples.__doc__ = """Time series: times (n,) in s and values (n, k), NaN where a message
lacked a column."""


class ExportError(ValueError):
    """The episode's messages cannot make the export (e.g. Baxter's joints never measured)."""


def _samples(rows, width):
    if not rows:
        return Samples(np.zeros(0), np.zeros((0, width)))
    rows.sort(key=lambda row: row[0])
    return Samples(np.array([r[0] for r in rows], float),
                   np.array([r[1] for r in rows], float).reshape(len(rows), width))


def _by_name(names, values, wanted):
    """Return values of the wanted names in order, NaN for a missing name or value."""
    index = {name: i for i, name in enumerate(names)}
    return [values[index[w]] if w in index and index[w] < len(values) else np.nan
            for w in wanted]


Recording = collections.namedtuple('Recording', 'position velocity effort command gripper_state '
                                                'gripper_force gripper_go puppet end_piece follow')
Recording.__doc__ = """An episode's messages as time series (each a Samples).

position, velocity, effort: Baxter's 14 arm joints (ARM_JOINTS order) from /robot/joint_states.
command, gripper_state, gripper_force, gripper_go: {Baxter side: Samples} of position commands
(7 joints, NaN for joints a command did not name), gripper position (%), force (%), 'go'
positions (%). puppet, end_piece: {puppet side: Samples} of its 7 angles and gripper_3 reading.
follow: {Baxter side: the puppet sides whose teleop_state ever said it followed them}."""


def episode_topics():
    """Return the topics collect() reads."""
    topics = [ROBOT_JOINT_STATES]
    for side in BAXTER_SIDES:
        topics += [limb_topic(side, 'joint_command'), baxter_gripper_topic(side, 'state'),
                   baxter_gripper_topic(side, 'command')]
    for side in PUPPET_SIDES:
        topics += ['%s/%s' % (puppet_ns(side), name) for name in (JOINT_STATES, TELEOP_STATE)]
        topics.append(gripper_topic(side, END_PIECE_GRIPPER))
    return topics


def collect(messages):
    """Return the Recording of an episode's (topic, msg, t) messages; other topics are ignored."""
    rows = collections.defaultdict(list)
    follow = {side: [] for side in BAXTER_SIDES}
    for topic, msg, t in messages:
        rows[topic].append((t, msg))
    joint_rows = rows[ROBOT_JOINT_STATES]
    recording = {
        field: _samples([(t, _by_name(m.name, getattr(m, field), ARM_JOINTS))
                         for t, m in joint_rows], len(ARM_JOINTS))
        for field in ('position', 'velocity', 'effort')}
    for key in ('command', 'gripper_state', 'gripper_force', 'gripper_go', 'puppet',
                'end_piece'):
        recording[key] = {}
    for side in BAXTER_SIDES:
        names = arm_joint_names(side)
        recording['command'][side] = _samples(
            [(t, _by_name(m.names, m.command, names))
             for t, m in rows[limb_topic(side, 'joint_command')] if m.mode in POSITION_MODES], 7)
        states = rows[baxter_gripper_topic(side, 'state')]
        recording['gripper_state'][side] = _samples([(t, m.position) for t, m in states], 1)
        recording['gripper_force'][side] = _samples([(t, m.force) for t, m in states], 1)
        recording['gripper_go'][side] = _samples(
            [(t, _go_position(m.args)) for t, m in rows[baxter_gripper_topic(side, 'command')]
             if m.command == CMD_GO and _go_position(m.args) is not None], 1)
    for side in PUPPET_SIDES:
        joints = ['joint_%d' % j for j in range(7)]
        recording['puppet'][side] = _samples(
            [(t, _by_name(m.name, m.position, joints))
             for t, m in rows['%s/%s' % (puppet_ns(side), JOINT_STATES)]], 7)
        recording['end_piece'][side] = _samples(
            [(t, m.data) for t, m in rows[gripper_topic(side, END_PIECE_GRIPPER)]], 1)
        for _, m in rows['%s/%s' % (puppet_ns(side), TELEOP_STATE)]:
            for baxter_side in BAXTER_SIDES:
                if getattr(m, 'follow_' + baxter_side) and side not in follow[baxter_side]:
                    follow[baxter_side].append(side)
    return Recording(follow=follow, **recording)


def _go_position(args):
    """Return the position (%) of a 'go' command's JSON args, None when it names none."""
    try:
        position = json.loads(args).get('position')
    except (ValueError, AttributeError):
        return None
    return float(position) if isinstance(position, (int, float)) else None


def time_grid(start_s, end_s, rate_hz):
    """Return the times start_s + k / rate_hz (s) up to end_s (inclusive within 1e-6 step)."""
    if rate_hz <= 0 or not np.isfinite(rate_hz):
        raise ExportError('the rate must be a positive number of Hz, got %r' % (rate_hz,))
    count = int(np.floor((end_s - start_s) * rate_hz + 1e-6)) + 1
    return start_s + np.arange(max(count, 1)) / rate_hz


def interpolate(samples, grid):
    """Return samples linearly interpolated at grid times (held flat beyond the first and last
    sample), column by column over the column's finite values; NaN for a column without any."""
    out = np.full((len(grid), samples.values.shape[1]), np.nan)
    for c in range(samples.values.shape[1]):
        ok = np.isfinite(samples.values[:, c])
        if ok.any():
            out[:, c] = np.interp(grid, samples.times[ok], samples.values[ok, c])
    return out


def hold(samples, grid):
    """Return, per column, the last finite value at or before each grid time (NaN before the
    column's first value): a zero-order hold."""
    out = np.full((len(grid), samples.values.shape[1]), np.nan)
    for c in range(samples.values.shape[1]):
        ok = np.isfinite(samples.values[:, c])
        index = np.searchsorted(samples.times[ok], grid, side='right') - 1
        values = samples.values[ok, c]
        out[index >= 0, c] = values[index[index >= 0]]
    return out


def _fill(values, fallback):
    return np.where(np.isnan(values), fallback, values)


def aloha_arrays(recording, rate_hz=DEFAULT_RATE_HZ):
    """Return the episode resampled at rate_hz on a grid from the first to the last joint state.

    Returns a dict of arrays: time (T,) s from the first joint state; qpos, qvel, effort and
    action (T, 16) in COLUMNS order; gripper_percent (T, 2) measured (left, right); and
    commanded (T, 16), the commands alone (NaN before an arm's or gripper's first command).
    Gripper columns: qpos the opening 0..1 (EndEffectorState position / 100, 0 without any
    state), qvel its rate of change (1/s), effort force / 100 (0 without state), action the
    last 'go' position / 100. Action where nothing was commanded yet: the measured qpos.
    Velocity or effort never reported: 0.

    Raises:
        ExportError: no /robot/joint_states, or an arm joint it never named.
    """
    if not len(recording.position.times):
        raise ExportError('the episode has no %s: nothing to export' % ROBOT_JOINT_STATES)
    grid = time_grid(recording.position.times[0], recording.position.times[-1], rate_hz)
    arm_position = interpolate(recording.position, grid)
    missing = [ARM_JOINTS[c] for c in range(len(ARM_JOINTS)) if np.isnan(arm_position[0, c])]
    if missing:
        raise ExportError('%s never measured %s' % (ROBOT_JOINT_STATES, ', '.join(missing)))
    qpos, qvel, effort, commanded = (np.zeros((len(grid), len(COLUMNS))) for _ in range(4))
    qpos[:, ARM_COLUMNS] = arm_position
    qvel[:, ARM_COLUMNS] = _fill(interpolate(recording.velocity, grid), 0.0)
    effort[:, ARM_COLUMNS] = _fill(interpolate(recording.effort, grid), 0.0)
    percent = np.zeros((len(grid), len(BAXTER_SIDES)))
    for s, side in enumerate(BAXTER_SIDES):
        percent[:, s] = _fill(interpolate(recording.gripper_state[side], grid)[:, 0], 0.0)
        g = GRIPPER_COLUMNS[s]
        qpos[:, g] = percent[:, s] / POSITION_OPEN
        if len(grid) > 1:
            qvel[:, g] = np.gradient(qpos[:, g], 1.0 / rate_hz)
        effort[:, g] = _fill(interpolate(recording.gripper_force[side], grid)[:, 0],
                             0.0) / POSITION_OPEN
        arm = [c for c, name in enumerate(COLUMNS) if name in arm_joint_names(side)]
        commanded[:, arm] = hold(recording.command[side], grid)
        commanded[:, g] = hold(recording.gripper_go[side], grid)[:, 0] / POSITION_OPEN
    return {'time': grid - grid[0], 'qpos': qpos, 'qvel': qvel, 'effort': effort,
            'action': _fill(commanded, qpos), 'commanded': commanded,
            'gripper_percent': percent}


def csv_lines(arrays):
    """Return the lines of Rethink's joint_recorder CSV: the header, then per grid time the time
    (s from the start, '%f'), the measured angles (rad) and gripper positions (0..100, as
    baxter_interface.Gripper.position() gives them) in CSV_HEADER order, floats as repr."""
    lines = [','.join(CSV_HEADER)]
    for k, t in enumerate(arrays['time']):
        row = [float(v) for v in arrays['qpos'][k]]
        for s, g in enumerate(GRIPPER_COLUMNS):
            row[g] = float(arrays['gripper_percent'][k, s])
        lines.append('%f,' % t + ','.join(repr(v) for v in row))
    return lines


def puppet_driver(recording, baxter_side):
    """Return the puppet side that drove a Baxter arm: the first whose teleop_state said it
    followed, else the puppet side with angles on that side, else any with angles (None)."""
    with_angles = [s for s in PUPPET_SIDES if len(recording.puppet[s].times)]
    if recording.follow[baxter_side]:
        return recording.follow[baxter_side][0]
    same = [s for s in with_angles if BAXTER_SIDE[s] == baxter_side]
    return (same or with_angles or [None])[0]


def plot_series(recording, arrays):
    """Return {Baxter side: dict} for the plot, of each arm that got position commands (of the
    recorded puppet sides' arms if none did): puppet (T, 7) the driving puppet's angles as that
    arm takes them (mirrored on the opposite side; NaN without a puppet), commanded, measured
    and error = commanded - measured (T, 7) rad, gripper_commanded and gripper_measured
    (T,) opening 0..1, end_piece (T,) the puppet's end-piece reading (~1 released)."""
    grid = arrays['time'] + recording.position.times[0]
    sides = [s for s in BAXTER_SIDES if len(recording.command[s].times)]
    sides = sides or [BAXTER_SIDE[s] for s in PUPPET_SIDES if len(recording.puppet[s].times)]
    series = {}
    for side in sides:
        columns = [COLUMNS.index(name) for name in arm_joint_names(side)]
        g = COLUMNS.index('%s_gripper' % side)
        driver = puppet_driver(recording, side)
        puppet = np.full((len(grid), 7), np.nan)
        end_piece = np.full(len(grid), np.nan)
        if driver is not None:
            puppet = interpolate(recording.puppet[driver], grid)
            if BAXTER_SIDE[driver] != side:
                puppet = np.array([mirror(row) for row in puppet])
            end_piece = interpolate(recording.end_piece[driver], grid)[:, 0]
        commanded = arrays['commanded'][:, columns]
        measured = arrays['qpos'][:, columns]
        series[side] = {'driver': driver, 'puppet': puppet, 'commanded': commanded,
                        'measured': measured, 'error': commanded - measured,
                        'gripper_commanded': arrays['commanded'][:, g],
                        'gripper_measured': arrays['qpos'][:, g], 'end_piece': end_piece}
    return series
