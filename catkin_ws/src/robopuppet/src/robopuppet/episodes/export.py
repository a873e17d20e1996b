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
from robopuppet.baxter_description import arm_joint_names
from robopuppet.interface import (BAXTER_SIDES, END_PIECE_GRIPPER, JOINT_STATES,
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


def message_values(topic, msg):
    """Return [(series, values)] that one message adds to a Recording: series a key of
    Recording (position, velocity, effort) or a (key, side) pair; [] for any other topic."""
    if topic == ROBOT_JOINT_STATES:
        return [(field, _by_name(msg.name, getattr(msg, field), ARM_JOINTS))
                for field in ('position', 'velocity', 'effort')]
    return [((key, side), value(msg)) for key, side, value in _TOPIC_VALUES.get(topic, ())
            if value(msg) is not None]


def _topic_values():
    """Return {topic: [(Recording key, side, msg -> values or None)]} of the series topics."""
    table = collections.defaultdict(list)
    for side in BAXTER_SIDES:
        names = arm_joint_names(side)
        table[limb_topic(side, 'joint_command')].append((
            'command', side, lambda m, names=names: _by_name(m.names, m.command, names)
            if m.mode in POSITION_MODES else None))
        state = baxter_gripper_topic(side, 'state')
        table[state].append(('gripper_state', side, lambda m: [m.position]))
        table[state].append(('gripper_force', side, lambda m: [m.force]))
        table[baxter_gripper_topic(side, 'command')].append((
            'gripper_go', side, lambda m: [_go_position(m.args)]
            if m.command == CMD_GO and _go_position(m.args) is not None else None))
    joints = ['joint_%d' % j for j in range(7)]
    for side in PUPPET_SIDES:
        table['%s/%s' % (puppet_ns(side), JOINT_STATES)].append((
            'puppet', side, lambda m: _by_name(m.name, m.position, joints)))
        table[gripper_topic(side, END_PIECE_GRIPPER)].append(('end_piece', side,
                                                              lambda m: [m.data]))
    return dict(table)


_TOPIC_VALUES = _topic_values()
SERIES_WIDTH = {'position': len(ARM_JOINTS), 'velocity': len(ARM_JOINTS),
                'effort': len(ARM_JOINTS), 'command': 7, 'gripper_state': 1, 'gripper_force': 1,
                'gripper_go': 1, 'puppet': 7, 'end_piece': 1}


def follows(topic, msg):
    """Return the Baxter sides a puppet's teleop_state message says it follows, with the
    puppet side: (puppet side, [Baxter sides]); None for any other topic."""
    for side in PUPPET_SIDES:
        if topic == '%s/%s' % (puppet_ns(side), TELEOP_STATE):
            return side, [s for s in BAXTER_SIDES if getattr(msg, 'follow_' + s)]
    return None


def collect(messages):
    """Return the Recording of an episode's (topic, msg, t) messages; other topics are ignored."""
    rows = collections.defaultdict(list)
    follow = {side: [] for side in BAXTER_SIDES}
    for topic, msg, t in messages:
        for series, values in message_values(topic, msg):
            rows[series].append((t, values))
        followed = follows(topic, msg)
        for baxter_side in (followed or (None, []))[1]:
            if followed[0] not in follow[baxter_side]:
                follow[baxter_side].append(followed[0])
    recording = {key: _samples(rows[key], SERIES_WIDTH[key])
                 for key in ('position', 'velocity', 'effort')}
    for key, sides in (('command', BAXTER_SIDES), ('gripper_state', BAXTER_SIDES),
                       ('gripper_force', BAXTER_SIDES), ('gripper_go', BAXTER_SIDES),
                       ('puppet', PUPPET_SIDES), ('end_piece', PUPPET_SIDES)):
        recording[key] = {side: _samples(rows[(key, side)], SERIES_WIDTH[key])
                          for side in sides}
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


def resample(recording, grid):
    """Return the episode's rows at the grid times (s, the messages' clock): qpos, qvel, effort
    and commanded (n, 16), gripper_percent (n, 2), as aloha_arrays describes them, but for the
    grippers' qvel (0 here: aloha_arrays and the streamed export take its differences). The
    recording needs only the samples around the grid's times."""
    qpos, qvel, effort, commanded = (np.zeros((len(grid), len(COLUMNS))) for _ in range(4))
    qpos[:, ARM_COLUMNS] = interpolate(recording.position, grid)
    qvel[:, ARM_COLUMNS] = _fill(interpolate(recording.velocity, grid), 0.0)
    effort[:, ARM_COLUMNS] = _fill(interpolate(recording.effort, grid), 0.0)
    percent = np.zeros((len(grid), len(BAXTER_SIDES)))
    for s, side in enumerate(BAXTER_SIDES):
        percent[:, s] = _fill(interpolate(recording.gripper_state[side], grid)[:, 0], 0.0)
        g = GRIPPER_COLUMNS[s]
        qpos[:, g] = percent[:, s] / POSITION_OPEN
        effort[:, g] = _fill(interpolate(recording.gripper_force[side], grid)[:, 0],
                             0.0) / POSITION_OPEN
        arm = [c for c, name in enumerate(COLUMNS) if name in arm_joint_names(side)]
        commanded[:, arm] = hold(recording.command[side], grid)
        commanded[:, g] = hold(recording.gripper_go[side], grid)[:, 0] / POSITION_OPEN
    return {'qpos': qpos, 'qvel': qvel, 'effort': effort, 'commanded': commanded,
            'gripper_percent': percent}


def check_measured(qpos):
    """Raise ExportError when an arm joint of the first row (n, 16) was never measured."""
    missing = [COLUMNS[c] for c in ARM_COLUMNS if np.isnan(qpos[0, c])]
    if missing:
        raise ExportError('%s never measured %s' % (ROBOT_JOINT_STATES, ', '.join(missing)))


def no_joint_states():
    """Return the ExportError of an episode without Baxter's joint states."""
    return ExportError('the episode has no %s: nothing to export' % ROBOT_JOINT_STATES)


def aloha_arrays(recording, rate_hz=DEFAULT_RATE_HZ):
    """Return the episode resampled at rate_hz on a grid from the first to the last joint state.

    Returns a dict of arrays: time (T,) s from the first joint state; qpos, qvel, effort and
    action (T, 16) in COLUMNS order; gripper_percent (T, 2) measured (left, right); and
    commanded (T, 16), the commands alone (NaN before an arm's or gripper's first command).
    Gripper columns: qpos the opening 0..1 (EndEffectorState position / 100, 0 without any
    state), qvel its rate of change (1/s, central differences on the grid), effort force / 100
    (0 without state), action the last 'go' position / 100. Action where nothing was commanded
    yet: the measured qpos. Velocity or effort never reported: 0.

    Raises:
        ExportError: no /robot/joint_states, or an arm joint it never named.
    """
    if not len(recording.position.times):
        raise no_joint_states()
    grid = time_grid(recording.position.times[0], recording.position.times[-1], rate_hz)
    arrays = resample(recording, grid)
    check_measured(arrays['qpos'])
    if len(grid) > 1:
        for g in GRIPPER_COLUMNS:
            arrays['qvel'][:, g] = np.gradient(arrays['qpos'][:, g], 1.0 / rate_hz)
    arrays['time'] = grid - grid[0]
    arrays['action'] = _fill(arrays['commanded'], arrays['qpos'])
    return arrays


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
