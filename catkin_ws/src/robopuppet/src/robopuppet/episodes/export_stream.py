"""Resample an episode onto the export's time grid while its messages stream in, in blocks of
grid steps, so that memory holds a few seconds of messages whatever the episode's length.

Pure (numpy, no ROS): messages come in as (topic, msg, t) in time order, t in s on the clock
of robopuppet.episodes.export; the grid (first to last joint state) is known beforehand, from
the bag's index. The rows are export.aloha_arrays' numbers exactly: each block is resampled by
export.resample from the samples around it (a measured column keeps its last value at or before
the block, a step waits for the column's next value after it), so a step waits only for the
next value of every measured column; a column whose topic has no more messages (the messages
are past the index's last: another message of the same time may come after) is final. A
measured column that stops having values while its topic goes on (a joint state that stops
naming a joint) holds the steps, and so the messages, back until the end.
"""
import collections

import numpy as np

from robopuppet.episodes import export
from robopuppet.episodes.export import GRIPPER_COLUMNS, Recording, Samples

# Series interpolated (measured): a step waits for each of their columns' next value.
LINEAR = ('position', 'velocity', 'effort', 'gripper_state', 'gripper_force', 'puppet',
          'end_piece')
FLUSH_PERIOD_S = 2.0  # of episode time between attempts to hand out steps


class _Buffer:
    """One series' samples not needed any more dropped: times, rows, last value time per
    column."""

    def __init__(self, width):
        self.times, self.rows = [], []
        self.last_value_s = np.full(width, -np.inf)
        self.width = width

    def add(self, t_s, values):
        row = np.asarray(values, float)
        self.times.append(t_s)
        self.rows.append(row)
        self.last_value_s[np.isfinite(row)] = t_s

    def samples(self):
        if not self.rows:
            return Samples(np.zeros(0), np.zeros((0, self.width)))
        return Samples(np.array(self.times), np.array(self.rows).reshape(-1, self.width))

    def drop_before(self, t_s):
        """Drop the rows that no grid time from t_s on needs: those before each column's last
        value at or before t_s (all rows before a column's first value)."""
        samples = self.samples()
        keep = len(self.rows)
        for c in range(self.width):
            ok = np.flatnonzero(np.isfinite(samples.values[:, c]))
            if len(ok):
                before = np.searchsorted(samples.times[ok], t_s, side='right') - 1
                keep = min(keep, ok[max(before, 0)])
        del self.times[:keep], self.rows[:keep]


class EpisodeStream:
    """Hand out an episode's grid rows as its messages stream in.

    Args:
        rate_hz: the grid's rate.
        start_s, end_s: the first and last joint state's times (s): the grid.
        topic_end_s: {topic: time of its last message in the bag (s)}; a topic not in it has
            none.
        plot: also hand out the puppets' angles and end-piece readings (for the plot).
    """

    def __init__(self, rate_hz, start_s, end_s, topic_end_s, plot=False):
        self.rate_hz, self.start_s = rate_hz, start_s
        self.steps = len(export.time_grid(start_s, end_s, rate_hz)) if end_s >= start_s else 1
        self._topic_end_s = topic_end_s
        self._plot = plot
        self._buffers = {}
        for key, width in export.SERIES_WIDTH.items():
            sides = export.PUPPET_SIDES if key in ('puppet', 'end_piece') else export.BAXTER_SIDES
            for side in ([None] if key in ('position', 'velocity', 'effort') else sides):
                self._buffers[key if side is None else (key, side)] = _Buffer(width)
        self._topics = {series: topic for topic, entries in export._TOPIC_VALUES.items()
                        for series in [(key, side) for key, side, _ in entries]}
        self.follow = {side: [] for side in export.BAXTER_SIDES}
        self.commanded_sides, self.puppet_sides = set(), set()
        self._next_step = 0
        self._now_s = -np.inf
        self._flush_at_s = -np.inf
        self._held = None  # the last row handed out's block, its gripper qvel still open

    def add(self, topic, msg, t_s):
        """Take a message; return the blocks of rows it completes (see finish)."""
        for series, values in export.message_values(topic, msg):
            key = series if isinstance(series, str) else series[0]
            if key in ('puppet', 'end_piece') and not self._plot:
                continue
            self._buffers[series].add(t_s, values)
            if key == 'command':
                self.commanded_sides.add(series[1])
            elif key == 'puppet':
                self.puppet_sides.add(series[1])
        followed = export.follows(topic, msg)
        for baxter_side in (followed or (None, []))[1]:
            if followed[0] not in self.follow[baxter_side]:
                self.follow[baxter_side].append(followed[0])
        self._now_s = t_s
        if t_s < self._flush_at_s:
            return []
        self._flush_at_s = t_s + FLUSH_PERIOD_S
        return self._blocks(self._ready_steps())

    def finish(self):
        """Return the last blocks. A block is a dict of rows k0..k1-1 (keys start, time, qpos,
        qvel, effort, action, commanded, gripper_percent as export.aloha_arrays; with plot,
        puppet {side: (n, 7)} and end_piece {side: (n,)}).

        Raises:
            export.ExportError: an arm joint never measured.
        """
        return self._blocks(self.steps, final=True)

    def _grid(self, k0, k1):
        return self.start_s + np.arange(k0, k1) / self.rate_hz

    def _ready_steps(self):
        """Return how many steps every column can give now."""
        bound_s = self._now_s  # a command at the step's time may still come
        for series, buffer in self._buffers.items():
            key = series if isinstance(series, str) else series[0]
            topic = export.ROBOT_JOINT_STATES if isinstance(series, str) else self._topics[series]
            # final once past its last message: another of the same time may still come
            if key not in LINEAR or self._topic_end_s.get(topic, -np.inf) < self._now_s:
                continue
            if key in ('puppet', 'end_piece') and not self._plot:
                continue
            bound_s = min(bound_s, buffer.last_value_s.min())
        ready = int(np.ceil((bound_s - self.start_s) * self.rate_hz)) if bound_s > -np.inf else 0
        while ready > 0 and self._grid(ready - 1, ready)[0] >= bound_s:
            ready -= 1
        return min(max(ready, 0), self.steps - 1)  # the last row waits for finish

    def _blocks(self, stop, final=False):
        if stop <= self._next_step and not final:
            return []
        k0 = self._next_step
        grid = self._grid(k0, stop)
        recording = Recording(follow=self.follow, **self._series())
        block = export.resample(recording, grid)
        if k0 == 0:
            export.check_measured(block['qpos'])
        if self._plot:
            block['puppet'] = {s: export.interpolate(recording.puppet[s], grid)
                               for s in export.PUPPET_SIDES}
            block['end_piece'] = {s: export.interpolate(recording.end_piece[s], grid)[:, 0]
                                  for s in export.PUPPET_SIDES}
        block['start'] = k0
        block['time'] = grid - self.start_s
        block['action'] = np.where(np.isnan(block['commanded']), block['qpos'],
                                   block['commanded'])
        self._next_step = stop
        for buffer in self._buffers.values():
            buffer.drop_before(self._grid(stop, stop + 1)[0])
        return self._gripper_velocity(block, final)

    def _series(self):
        series = collections.defaultdict(dict)
        for key, buffer in self._buffers.items():
            if isinstance(key, str):
                series[key] = buffer.samples()
            else:
                series[key[0]][key[1]] = buffer.samples()
        return series

    def _gripper_velocity(self, block, final):
        """Fill the grippers' qvel (np.gradient's numbers over the whole grid) and return the
        blocks complete: a block's last row waits for the next block's first."""
        step_s = 1.0 / self.rate_hz
        if self._held is not None:
            block = _join(self._held, block)
        q = block['qpos'][:, GRIPPER_COLUMNS]
        n = len(q)
        before = [] if block['start'] == 0 else [self._before_q]
        q_all = np.concatenate([np.reshape(before, (-1, len(GRIPPER_COLUMNS))), q])
        rows = np.arange(n) + len(before)  # in q_all
        last = len(q_all) - 1
        if self.steps > 1:
            velocity = np.zeros_like(q)
            inner = (rows > 0) & (rows < last)
            velocity[inner] = (q_all[rows[inner] + 1] - q_all[rows[inner] - 1]) / (2. * step_s)
            if rows[0] == 0 and last > 0:
                velocity[0] = (q_all[1] - q_all[0]) / step_s
            if final and last > 0:
                velocity[n - 1] = (q_all[last] - q_all[last - 1]) / step_s
            block['qvel'][:, GRIPPER_COLUMNS] = velocity
        if final:
            self._held = None
            return [block]
        if n > 1:
            self._before_q = q[n - 2]
        self._held = _slice(block, n - 1, n)
        return [_slice(block, 0, n - 1)] if n > 1 else []


def _slice(block, i, j):
    """Return rows i..j-1 of a block."""
    out = {'start': block['start'] + i}
    for key, value in block.items():
        if key == 'start':
            continue
        out[key] = ({s: v[i:j] for s, v in value.items()} if isinstance(value, dict)
                    else value[i:j])
    return out


def _join(first, second):
    """Return two consecutive blocks as one."""
    out = {'start': first['start']}
    for key, value in first.items():
        if key == 'start':
            continue
        out[key] = ({s: np.concatenate([v, second[key][s]]) for s, v in value.items()}
                    if isinstance(value, dict) else np.concatenate([value, second[key]]))
    return out
