"""Play an episode's recorded puppet angles back into the puppet (kinesthetic playback).

Pure: no rospy, time (s) is an argument; angles in rad, speeds in rad/s. The ROS side
(robopuppet.episodes.puppet_player) feeds it what the puppet reports and sends what step()
returns: per puppet side seven setpoints (joint_J/setpoint) first, then an opmode when a Step
names one. The nurse feels the demonstration in her hand; Baxter follows only if she makes it
(buttons 2/3: arm_X follows the puppet as always).

How the setpoints move, never faster than a bounded speed per joint (joint_motion.SpeedBudget,
so never a step):
- start(): setpoints = where the puppet is, then hold (the firmware holds the setpoints it has:
  they go first), so nothing moves yet;
- approach: from there to the episode's first recorded pose at approach_speed_rad_s; the episode
  plays once the puppet measures that pose (APPROACH_TOLERANCE_RAD) or SETTLE_TIMEOUT_S after
  the setpoints got there;
- play: the recorded angles at episode time (t - play start) x speed, at most play_speed_rad_s
  per joint (and each joint's stored velocity limit), clamped to its angle_min/angle_max (the
  live stored settings, else the recorded range);
- the end: finished once the puppet measures the last setpoints (within
  tracking_watch.FINAL_TOLERANCE_RAD) and holds the last recorded pose; not there
  FINAL_TIMEOUT_S after them: stopped, limp.
Stops (button 1, a stop request, the puppet silent or a joint not Working, someone else's limp):
the setpoints stay where they are (the last ones sent: no step) and the puppet holds there.
A side that another node puts limp (the GUI's Limp, arm_X releasing a puppet it held on
button 1, arm_X's fault) is left limp: it gets no more setpoints.
The puppet not following (robopuppet.episodes.tracking_watch: far from its setpoints at its
voltage limit, saturated too long, or the last pose not reached in time) stops the playback
too, and the sides that broke a rule are put limp (they get no more setpoints); the others hold.
"""
import collections
import math

import numpy as np

from robopuppet import settings
from robopuppet.arm.joint_motion import SpeedBudget, all_finite, clamp
from robopuppet.episodes.replay import (APPROACH, FINISHED, MAX_SPEED, PLAY, STOPPED,
                                        ReplayError)
from robopuppet.episodes.tracking_watch import FINAL_TIMEOUT_S, TrackingWatch, voltage_limits
from robopuppet.interface import (BUTTON_OPMODE, HEARTBEAT_TIMEOUT_S, HOLD, LIMP, UNCALIBRATED,
                                  WORKING)

APPROACH_SPEED_RAD_S = 0.3     # setpoint speed on the way to the first recorded pose
PLAY_SPEED_RAD_S = 1.5         # the fastest a setpoint moves while playing (a brisk hand)
APPROACH_TOLERANCE_RAD = 0.02  # measured this close to the first pose: the episode plays
SETTLE_TIMEOUT_S = 3.0         # ... or this long after the setpoints got there
SILENT_S = HEARTBEAT_TIMEOUT_S  # no joint states for this long: the puppet is silent (2.5 s)

Limit = collections.namedtuple('Limit', 'lower upper velocity')
Limit.__doc__ = 'A puppet joint: angles lower..upper (rad), setpoint speed at most velocity.'
Step = collections.namedtuple('Step', 'phase setpoints opmodes')
Step.__doc__ = """What to send now: the phase (APPROACH, PLAY, FINISHED or STOPPED), setpoints
{puppet side: 7 rad} and then opmodes {puppet side: 'hold' or 'limp'}."""


def puppet_paths(recording, sides):
    """Return {side: Samples of the recorded 7 puppet angles} of a Recording (export.collect);
    a joint state with a missing or non-finite angle is left out.

    Raises:
        ReplayError: a side has no complete joint states in the episode.
    """
    paths = {}
    for side in sides:
        samples = recording.puppet.get(side)
        keep = (np.isfinite(samples.values).all(axis=1) if samples is not None
                else np.zeros(0, bool))
        if not keep.any():
            raise ReplayError('the episode holds no joint states of puppet arm %s' % side)
        paths[side] = samples._replace(times=samples.times[keep], values=samples.values[keep])
    return paths


def joint_limits(stored, path, play_speed_rad_s=PLAY_SPEED_RAD_S):
    """Return (7 Limits, where they come from) of one puppet side.

    Args:
        stored: the live stored settings {joint: {name: value}}, or None: then each joint's
            recorded range (path: its Samples) and play_speed_rad_s.
    Raises:
        ReplayError: stored angle limits that are no range (min above max, not finite).
    """
    if stored is None:
        return [Limit(float(lo), float(hi), play_speed_rad_s) for lo, hi in
                zip(path.values.min(axis=0), path.values.max(axis=0))], 'the recorded range'
    limits = []
    for joint in settings.JOINTS:
        values = stored[joint]
        lower, upper = values['angle_min'], values['angle_max']
        if not (math.isfinite(lower) and math.isfinite(upper) and lower <= upper):
            raise ReplayError('joint %d: stored angle_min %r and angle_max %r are no range'
                              % (joint, lower, upper))
        speed = min(play_speed_rad_s, values['velocity_max'], -values['velocity_min'])
        limits.append(Limit(lower, upper, speed if speed > 0.0 else play_speed_rad_s))
    return limits, 'the stored settings'


class PuppetPlayback:
    """Stream recorded puppet angles as setpoints into the puppet arms they were recorded on.

    Args:
        paths: {puppet side: Samples of 7 angles} (puppet_paths()).
        speed: the speed factor, 0 < speed <= MAX_SPEED (episode seconds per second).
        period_s: the setpoint period (s), the speed budget's burst.
        approach_speed_rad_s, play_speed_rad_s: setpoint speeds (rad/s per joint).
        silent_s: no joint states for this long: the puppet is silent (refused, or stopped).
    Raises:
        ReplayError: the speed is out of range.
    """

    def __init__(self, paths, speed=1.0, period_s=0.02, approach_speed_rad_s=APPROACH_SPEED_RAD_S,
                 play_speed_rad_s=PLAY_SPEED_RAD_S, silent_s=SILENT_S):
        if not 0.0 < speed <= MAX_SPEED:
            raise ReplayError('speed must be within 0 (exclusive) and %g, got %g'
                              % (MAX_SPEED, speed))
        self.paths, self.speed, self._period_s = paths, speed, period_s
        self._approach_speed, self._play_speed = approach_speed_rad_s, play_speed_rad_s
        self._silent_s = silent_s
        self.start_s = min(p.times[0] for p in paths.values())   # episode time of the start
        self.end_s = max(p.times[-1] for p in paths.values())
        self.phase, self.why = None, ''
        self.limits, self.limit_source = {}, {}
        self.limp_by = {}            # side -> the node that put it limp during the playback
        self.let_go = set()          # the sides this playback put limp (they did not follow)
        self._limp_now = set()       # ... whose limp is still to be sent
        self._watches, self._final_t = {}, None
        self._angles, self._heard_t, self._stored = {}, {}, {}
        self._statuses = {side: [None] * settings.NUM_JOINTS for side in paths}
        self._budgets, self._start_pose, self._stay = {}, {}, {}
        self._reached_t = self._play_t = None
        self._episode_s = self.start_s

    # ---- inputs --------------------------------------------------------------------------

    def on_puppet(self, t, side, angles, voltages=None):
        """Take a puppet arm's 7 measured angles (rad) and motor voltages (V; None: unknown);
        non-finite angles are ignored. A sample that breaks a tracking rule stops."""
        if side not in self.paths or not all_finite(angles):
            return
        self._angles[side], self._heard_t[side] = list(angles), t
        if self.phase in (APPROACH, PLAY) and side in self._watches:
            verdict = self._watches[side].on_sample(t, self._budgets[side].command, angles,
                                                    voltages)
            if verdict:
                self._give_up(t, {side: verdict})

    def on_status(self, t, side, joint, status):
        """Take a joint's encoder status; one not Working stops a running playback."""
        if side not in self.paths:
            return
        self._statuses[side][joint] = status
        if status != WORKING:
            self.stop(t, 'puppet arm %s joint %d is %s' % (side, joint, status))

    def on_settings(self, t, side, stored):
        """Take a side's live stored settings {joint: {name: value}} (used at start())."""
        self._stored[side] = stored

    def on_button(self, t, side, button):
        """Take a puppet arm's user button reading (0 none, 1..4); button 1 stops."""
        if side in self.paths and button == BUTTON_OPMODE:
            self.stop(t, 'button %d pressed on puppet arm %s' % (BUTTON_OPMODE, side))

    def on_opmode(self, t, side, mode, sender):
        """Take an opmode that another node (sender) sent a played side: a limp stops the
        playback and that side stays limp. A hold from elsewhere changes nothing: the next
        setpoints overwrite the ones it came with."""
        if side in self.paths and mode == LIMP and self.phase in (APPROACH, PLAY, STOPPED):
            self.limp_by[side] = sender
            self.stop(t, 'puppet arm %s was put limp by %s' % (side, sender))

    def stop(self, t, why):
        """Stop at once: the setpoints stay at the last ones sent, the puppet holds there."""
        if self.phase not in (APPROACH, PLAY):
            return
        self.phase, self.why = STOPPED, why
        self._stay = {side: list(budget.command) for side, budget in self._budgets.items()}

    def _give_up(self, t, verdicts):
        """Stop because the sides of verdicts {side: tracking_watch.Verdict} did not follow:
        they go limp."""
        self.stop(t, '; '.join(v.why for _, v in sorted(verdicts.items())))
        self.let_go |= set(verdicts)
        self._limp_now |= set(verdicts)

    # ---- steps ---------------------------------------------------------------------------

    def missing_settings(self):
        """Return the played sides whose stored settings have not come (yet)."""
        return sorted(set(self.paths) - set(self._stored))

    def refusal(self, t):
        """Return why the playback cannot start at t ('' when it can)."""
        for side in sorted(self.paths):
            heard_t = self._heard_t.get(side)
            if heard_t is None:
                return 'puppet arm %s is silent: no joint states (is serial_%s running?)' % (
                    side, side)
            if t - heard_t > self._silent_s:
                return 'puppet arm %s is silent: no joint states for %.1f s' % (side, t - heard_t)
            waiting = collections.defaultdict(list)
            for joint, status in enumerate(self._statuses[side]):
                if status != WORKING:
                    waiting[status or 'with no encoder status yet'].append(str(joint))
            if waiting:
                return 'puppet arm %s is not calibrated: %s%s' % (side, '; '.join(
                    'joints %s %s' % (', '.join(joints), status)
                    for status, joints in sorted(waiting.items())), (
                    ' (turn each through its index mark)' if UNCALIBRATED in waiting else ''))
        return ''

    def start(self, t):
        """Hold each puppet where it is and begin the approach; return the Step at t.

        Raises:
            ReplayError: refusal(t) says why not, or the stored settings are no limits.
        """
        why = self.refusal(t)
        if why:
            raise ReplayError(why)
        here = {}
        for side, path in sorted(self.paths.items()):
            self.limits[side], self.limit_source[side] = joint_limits(
                self._stored.get(side), path, self._play_speed)
            here[side] = list(self._angles[side])
            self._start_pose[side] = clamp(list(path.values[0]), self.limits[side])
            self._budgets[side] = SpeedBudget(here[side], self._period_s, t)
            self._watches[side] = TrackingWatch(side, voltage_limits(self._stored.get(side)))
        self.phase = APPROACH
        return Step(APPROACH, here, {side: HOLD for side in here})

    def step(self, t):
        """Return the Step at time t (call at the setpoint rate after start())."""
        for side, heard_t in self._heard_t.items():
            if t - heard_t > self._silent_s:
                self.stop(t, 'puppet arm %s went silent: no joint states for %.1f s'
                          % (side, t - heard_t))
        if self.phase == APPROACH:
            return self._approach(t)
        if self.phase == PLAY:
            return self._play(t)
        if self.phase == STOPPED:
            return self._stopped()
        return Step(self.phase, {}, {})

    def _stopped(self):
        limp, self._limp_now = self._limp_now, set()
        return Step(STOPPED, {side: list(stay) for side, stay in self._stay.items()
                              if side not in self.limp_by and side not in self.let_go},
                    {side: LIMP for side in sorted(limp)})

    def progress(self):
        """Return (episode seconds played, the episode's duration s)."""
        return self._episode_s - self.start_s, self.end_s - self.start_s

    def outcome(self, side):
        """Return what the puppet arm on side does now the playback is over, in words."""
        if side in self.limp_by:
            return 'puppet arm %s is limp (put limp by %s)' % (side, self.limp_by[side])
        if side in self.let_go:
            return 'puppet arm %s went limp' % side
        if self.phase == FINISHED:
            return 'puppet arm %s holds the last recorded pose (measured within %.2f rad)' % (
                side, self._watches[side].distance(self._budgets[side].command))
        return 'puppet arm %s holds where it is' % side

    def _approach(self, t):
        setpoints = {side: self._budgets[side].move(
            self._start_pose[side], [min(self._approach_speed, lim.velocity)
                                     for lim in self.limits[side]], t)
            for side in sorted(self.paths)}
        if all(setpoints[s] == self._start_pose[s] for s in setpoints):
            self._reached_t = t if self._reached_t is None else self._reached_t
            settled = all(max(abs(a - b) for a, b in zip(self._angles[s], self._start_pose[s]))
                          <= APPROACH_TOLERANCE_RAD for s in setpoints)
            if settled or t - self._reached_t >= SETTLE_TIMEOUT_S:
                self.phase, self._play_t = PLAY, t
        return Step(APPROACH, setpoints, {})

    def _play(self, t):
        self._episode_s = min(self.start_s + (t - self._play_t) * self.speed, self.end_s)
        setpoints, arrived = {}, True
        for side, path in sorted(self.paths.items()):
            target = clamp([float(np.interp(self._episode_s, path.times, column))
                            for column in path.values.T], self.limits[side])
            setpoints[side] = self._budgets[side].move(
                target, [lim.velocity for lim in self.limits[side]], t)
            arrived = arrived and setpoints[side] == target
        if self._episode_s >= self.end_s and arrived:
            self._final_t = t if self._final_t is None else self._final_t
            if all(self._watches[s].reached(setpoints[s], self._final_t) for s in setpoints):
                self.phase = FINISHED
            elif t - self._final_t >= FINAL_TIMEOUT_S:
                self._give_up(t, {s: self._watches[s].not_reached(
                    setpoints[s], t - self._final_t) for s in setpoints
                    if not self._watches[s].reached(setpoints[s], self._final_t)})
                return self._stopped()
        return Step(PLAY, setpoints, {})
