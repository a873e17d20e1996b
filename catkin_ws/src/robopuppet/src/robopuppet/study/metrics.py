"""A trial's measures from MEASURED gripper motion and the arm controllers' state (docs/study.md).

TrialMetrics collects every update of a trial and gives its row of trials.csv: completion_s and
success, path_m, jerk, zone_s, clutches and idle_s, each over the task's arms (study.tasks.ARMS). Jerk and speed come from the tip positions resampled at
RESAMPLE_HZ and smoothed over SMOOTH_S (a moving average), so that a joint_states rate that
jitters or a millimetre of noise does not dominate them. Pure: numpy only.
"""
import numpy as np

from robopuppet.study import tasks

RESAMPLE_HZ = 50.0
SMOOTH_S = 0.1           # the moving average's width
IDLE_SPEED_M_S = 0.01    # a tip slower than this is idle


def smoothed(t, xyz, rate_hz=RESAMPLE_HZ, width_s=SMOOTH_S):
    """Return (N, 3) positions resampled at rate_hz from t[0] and smoothed by a moving average
    of width_s (the ends averaged over what there is)."""
    t, xyz = np.asarray(t, float), np.asarray(xyz, float)
    grid = np.arange(t[0], t[-1] + 0.5 / rate_hz, 1.0 / rate_hz)
    even = np.column_stack([np.interp(grid, t, xyz[:, k]) for k in range(3)])
    half = max(0, int(round(width_s * rate_hz / 2.0)))
    kernel = np.ones(2 * half + 1)
    counts = np.convolve(np.ones(len(grid)), kernel, mode='same')
    return np.column_stack([np.convolve(even[:, k], kernel, mode='same') / counts
                            for k in range(3)])


def mean_squared_jerk(t, xyz, rate_hz=RESAMPLE_HZ):
    """Return the mean over time of |d3 xyz / dt3|^2 (m^2/s^6) of smoothed positions (0 for
    fewer than 4 resampled positions)."""
    even = smoothed(t, xyz, rate_hz)
    if len(even) < 4:
        return 0.0
    jerk = np.diff(even, n=3, axis=0) * rate_hz ** 3
    return float(np.mean(np.sum(jerk ** 2, axis=1)))


class TrialMetrics:
    """Measure one trial.

    Args:
        trial: the tasks.Trial (its task names the arms measured); t0: its start (s).
        judge: its task_judge.TrialJudge, whose end time and success the row gives; without
            one, the trial ends at the last update and success is False.
    """

    def __init__(self, trial, t0, judge=None):
        self.t0, self.judge = float(t0), judge
        self.arms = tasks.ARMS[trial.task]
        self._t = []
        self._xyz = {arm: [] for arm in self.arms}
        self._following = None
        self.zone_s = 0.0
        self.clutches = 0
        self._last = None   # (t, any task arm held by a zone)

    def update(self, t, tips, following, zone_held, closed=None):
        """Add the state at time t (s): tips {arm: (xyz, rotation)} measured; following and
        zone_held {arm: bool} (teleop_state: the arm follows; zone_left/right non-empty);
        closed {arm: bool}, the grippers (not measured here). An update without every task
        arm's tip, or not after the last, is left out; updates after the judge's end too."""
        if any(arm not in tips for arm in self.arms) or (self._t and t <= self._t[-1]):
            return
        if t < self.t0 or (self.judge is not None and self.judge.end_t is not None
                           and t > self.judge.end_t):
            return
        if self._last is not None and self._last[1]:
            self.zone_s += t - self._last[0]
        self._last = (t, any(zone_held.get(arm, False) for arm in self.arms))
        now = {arm: bool(following.get(arm, False)) for arm in self.arms}
        if self._following is not None:
            self.clutches += sum(now[a] and not self._following[a] for a in self.arms)
        self._following = now
        self._t.append(float(t))
        for arm in self.arms:
            self._xyz[arm].append(np.asarray(tips[arm][0], float))

    def path_m(self):
        """Return the tips' path lengths (m), the task's arms summed."""
        return float(sum(np.linalg.norm(np.diff(self._xyz[a], axis=0), axis=1).sum()
                         for a in self.arms)) if len(self._t) > 1 else 0.0

    def jerk(self):
        """Return the mean squared jerk (m^2/s^6), the mean over the task's arms."""
        if len(self._t) < 2:
            return 0.0
        return float(np.mean([mean_squared_jerk(self._t, self._xyz[a]) for a in self.arms]))

    def idle_s(self):
        """Return how long (s) every task arm's smoothed tip moved slower than 1 cm/s."""
        if len(self._t) < 2:
            return 0.0
        speeds = [np.linalg.norm(np.diff(smoothed(self._t, self._xyz[a]), axis=0), axis=1)
                  * RESAMPLE_HZ for a in self.arms]
        return float(np.all(np.array(speeds) < IDLE_SPEED_M_S, axis=0).sum() / RESAMPLE_HZ)

    def row(self):
        """Return {completion_s, success, path_m, jerk, zone_s, clutches, idle_s} so far."""
        judge = self.judge
        end = self._t[-1] if self._t else self.t0
        if judge is not None and judge.end_t is not None:
            end = judge.end_t
        return {'completion_s': _figure(end - self.t0),
                'success': bool(judge is not None and judge.success),
                'path_m': _figure(self.path_m()), 'jerk': _figure(self.jerk()),
                'zone_s': _figure(self.zone_s), 'clutches': self.clutches,
                'idle_s': _figure(self.idle_s())}


def _figure(value):
    """Return value to 6 significant digits (what the CSV file needs)."""
    return float('%.6g' % value)
