"""Replay a recorded episode's Baxter commands: what to command now, when it is done, why it
stopped.

Pure: no rospy, time (s) is an argument; angles in rad, speeds in rad/s, gripper positions in
percent of travel (0 closed, 100 open). The player (robot_player) feeds it what Baxter and the
puppet report and publishes what step() returns.

Safety, the arm controller's rules: every command is clamped to the URDF's joint limits and
moves through a joint_motion.SpeedBudget (never faster than the joint's velocity limit, so no
speed factor can exceed it, and never a jump); the replay first moves slowly to the episode's
start pose; when a stop rule fires (button 1, a stop request, the puppet moved, Baxter
disabled, the puppet starts following, a keep-out zone) each replayed arm is commanded to stay
where Baxter measures it, at once.

Keep-out zones (docs/zones.md), as arm_X keeps them for teleoperation: every command of an arm
with a guard (world.zones.ZoneGuard), on the approach and in play, is checked for Baxter's
motion from wherever it can be (arm.arm_reach: its measured pose and the commands on their way)
to the command (ZoneGuard.limit_box). A command the guard holds back goes out only as far along
its step as is proven clear and the episode's clock waits (Baxter lagging near a zone catches
up; the recorded path is not bent, only slowed); held for ZONE_WAIT_S, the replay stops, naming
the zone, the link and the arm, and whether it was on the way to the start pose. A guarded
arm's stay command is where Baxter measures the arm, moved into the box where it can be.
"""
import collections

import numpy as np

from robopuppet.arm.arm_reach import ArmReach
from robopuppet.arm.baxter_watch import BaxterWatch
from robopuppet.arm.joint_motion import SpeedBudget, all_finite, clamp
from robopuppet.interface import BUTTON_OPMODE

MAX_SPEED = 2.0                 # the fastest speed factor; the velocity limits apply on top
APPROACH_SPEED_RAD_S = 0.3      # joint speed on the way to the start pose (capped per joint)
APPROACH_TOLERANCE_RAD = 0.02   # measured this close to the start pose: the episode plays
SETTLE_TIMEOUT_S = 3.0          # ... or this long after the command reached the start pose
PUPPET_MOVED_RAD = 0.1          # a puppet joint moved this far since the start stops the replay
ZONE_WAIT_S = 2.0               # a keep-out zone holding an arm back this long stops the replay
# The replay may run on the operator host (the GUI starts it there), its commands and Baxter's
# joint states crossing the link to the robot room: a command may reach Baxter this late, and a
# joint state's age (from its stamp, on another host's clock) counts at most MAX_POSE_AGE_S.
COMMAND_DELAY_S = 0.3
MAX_POSE_AGE_S = 0.1
APPROACH, PLAY, FINISHED, STOPPED = 'approach', 'play', 'finished', 'stopped'
ZONE_CUT = "keep-out zone '%s': %s of the %s arm would enter it"   # zone, link, Baxter side
ON_THE_WAY = ' on the way to the start pose'                       # ... added on the approach

Grip = collections.namedtuple('Grip', 'side position')
Grip.__doc__ = "Send Baxter's gripper on `side` a 'go' to position (% of travel)."
Step = collections.namedtuple('Step', 'phase commands grips')
Step.__doc__ = """What to do now: the phase (APPROACH, PLAY, FINISHED or STOPPED), commands
{Baxter side: 7 joint positions rad} and grips (a list of Grip, in order)."""


class ReplayError(ValueError):
    """An episode cannot be replayed (no commands, a bad speed, Baxter's pose unknown)."""


def episode_script(recording, arms=None):
    """Return (paths, grips) of a Recording (robopuppet.episodes.export.collect).

    paths: {Baxter side: Samples of 7 commanded angles, each joint held from its previous
    command (NaN only for a joint never commanded)}; grips: {side: [(t s, position %)]}.
    Args:
        arms: the Baxter sides to replay; default those the episode commands.
    Raises:
        ReplayError: an arm to replay has no position commands.
    """
    commanded = [side for side, samples in sorted(recording.command.items())
                 if len(samples.times)]
    arms = list(arms) if arms else commanded
    if not arms:
        raise ReplayError('the episode holds no position commands to Baxter')
    paths, grips = {}, {}
    for side in arms:
        if side not in commanded:
            raise ReplayError('the episode holds no position commands to the %s arm' % side)
        samples = recording.command[side]
        values = np.array(samples.values, float)
        for row in range(1, len(values)):  # a command naming some joints changes only those
            values[row] = np.where(np.isnan(values[row]), values[row - 1], values[row])
        paths[side] = samples._replace(values=values)
        go = recording.gripper_go.get(side)
        grips[side] = [] if go is None else [(float(t), float(v[0]))
                                             for t, v in zip(go.times, go.values)]
    return paths, grips


def check_speed(speed):
    """Raise ReplayError unless 0 < speed <= MAX_SPEED (a speed factor)."""
    if not 0.0 < speed <= MAX_SPEED:
        raise ReplayError('speed must be within 0 (exclusive) and %g, got %g' % (MAX_SPEED, speed))


class Replay:
    """Play an episode's command paths onto Baxter's arms at a speed factor.

    Args:
        paths, grips: from episode_script().
        limits: {Baxter side: 7 limits with lower, upper (rad), velocity (rad/s)}.
        speed: the speed factor, 0 < speed <= MAX_SPEED (episode seconds per second).
        period_s: the command period (s), the speed budget's burst.
        approach_speed_rad_s: joint speed to the start pose (capped by the velocity limits).
        puppet_moved_rad: a puppet joint moving further than this from where it was at the
            start stops the replay.
        guards: {Baxter side: world.zones.ZoneGuard} of the arms keep-out zones bind (None:
            none); a command whose motion is not proven clear waits, and stops the replay when
            it waits for ZONE_WAIT_S.
    Raises:
        ReplayError: the speed is out of range.
    """

    def __init__(self, paths, grips, limits, speed=1.0, period_s=0.01,
                 approach_speed_rad_s=APPROACH_SPEED_RAD_S, puppet_moved_rad=PUPPET_MOVED_RAD,
                 guards=None):
        check_speed(speed)
        self.paths, self.grips, self.limits, self.speed = paths, grips, limits, speed
        self._period_s, self._puppet_moved_rad = period_s, puppet_moved_rad
        self._approach_speeds = {side: [min(approach_speed_rad_s, lim.velocity)
                                        for lim in limits[side]] for side in paths}
        self.start_s = min(p.times[0] for p in paths.values())   # episode time of the start
        self.end_s = max(p.times[-1] for p in paths.values())
        self.robot = BaxterWatch(limits)
        self.phase, self.why = None, ''
        self._puppet, self._puppet_start = {}, {}
        self.guards = {side: guard for side, guard in (guards or {}).items() if side in paths}
        self._reach = {side: ArmReach(COMMAND_DELAY_S) for side in self.guards}
        self._budgets, self._stay, self._start_pose, self._sent = {}, {}, {}, {}
        self._reached_t = self._play_t = self._held_t = None
        self._episode_s = self.start_s

    # ---- inputs --------------------------------------------------------------------------

    def on_robot_pose(self, t, pose, velocities=None, age_s=0.0):
        """Take {side: 7 angles rad} (and velocities rad/s) of Baxter's arms, received at t and
        measured age_s earlier (by their stamp, counted within 0 .. MAX_POSE_AGE_S: the
        stamp may come from another host's clock)."""
        self.robot.on_robot_pose(t - min(max(age_s, 0.0), MAX_POSE_AGE_S), pose, velocities)

    def on_robot_enabled(self, t, enabled):
        """Take whether Baxter is enabled (not stopped, no error); disabled stops the replay."""
        if not enabled:
            self.stop(t, 'Baxter is disabled')

    def on_button(self, t, button):
        """Take the puppet's user button reading (0 none, 1..4); button 1 stops the replay."""
        if button == BUTTON_OPMODE:
            self.stop(t, 'button %d pressed' % BUTTON_OPMODE)

    def on_following(self, t, following):
        """Take whether the puppet drives a Baxter arm (teleop_state); that stops the replay."""
        if following:
            self.stop(t, 'the puppet started following: it would fight the replay')

    def on_puppet(self, t, side, angles):
        """Take a puppet arm's 7 angles (rad); moving it by more than puppet_moved_rad from
        where it was at the start stops the replay (non-finite readings are ignored)."""
        if not all_finite(angles):
            return
        self._puppet[side] = list(angles)
        if self.phase is None:
            return
        start = self._puppet_start.setdefault(side, list(angles))
        moved = max(abs(a - b) for a, b in zip(angles, start))
        if moved > self._puppet_moved_rad:
            self.stop(t, 'puppet arm %s moved %.2f rad' % (side, moved))

    def stop(self, t, why):
        """Stop at once (a stop request, or a stop rule): each arm stays where it is measured."""
        if self.phase not in (APPROACH, PLAY):
            return
        self.phase, self.why = STOPPED, why
        for side, sent in self._sent.items():
            now = self.robot.now(side, t)
            stay = now if now is not None else list(sent)
            if side in self.guards:   # no stay command leads out of where the arm can be
                stay = self._reach[side].inside(stay)
            self._stay[side] = stay

    # ---- steps ---------------------------------------------------------------------------

    def start(self, t):
        """Begin the approach to the start pose from where Baxter is; return the Step at t.

        Raises:
            ReplayError: Baxter's pose of a replayed arm is unknown.
        """
        for side, path in self.paths.items():
            here = self.robot.now(side, t)
            if here is None:
                raise ReplayError("Baxter's %s arm pose is unknown" % side)
            first = path.values[0]
            self._start_pose[side] = clamp(
                [h if np.isnan(f) else float(f) for f, h in zip(first, here)], self.limits[side])
            self._budgets[side] = SpeedBudget(here, self._period_s, t)
            self._sent[side] = list(here)
        self._puppet_start = dict(self._puppet)
        self.phase = APPROACH
        grips = [Grip(side, self._grip_at(side, self.start_s)) for side in sorted(self.grips)
                 if self._grip_at(side, self.start_s) is not None]
        step = self.step(t)
        return step if step.phase == STOPPED else step._replace(grips=grips + step.grips)

    def step(self, t):
        """Return the Step at time t (call at the command rate after start())."""
        if self.phase == APPROACH:
            return self._approach(t)
        if self.phase == PLAY:
            return self._play(t)
        if self.phase == STOPPED:
            return Step(STOPPED, {s: list(a) for s, a in self._stay.items()}, [])
        return Step(self.phase, {}, [])

    def progress(self):
        """Return (episode seconds played, the episode's duration s)."""
        return self._episode_s - self.start_s, self.end_s - self.start_s

    def _approach(self, t):
        commands = {side: self._budgets[side].move(self._start_pose[side],
                                                   self._approach_speeds[side], t)
                    for side in sorted(self.paths)}
        if not self._clear_of_zones(t, commands, ON_THE_WAY):
            return Step(self.phase, commands, []) if self.phase == APPROACH else self.step(t)
        if all(commands[s] == self._start_pose[s] for s in commands):
            self._reached_t = t if self._reached_t is None else self._reached_t
            measured = {s: self.robot.now(s, t) for s in commands}
            settled = all(m is not None and max(abs(a - b) for a, b in zip(
                m, self._start_pose[s])) <= APPROACH_TOLERANCE_RAD for s, m in measured.items())
            if settled or t - self._reached_t >= SETTLE_TIMEOUT_S:
                self.phase, self._play_t = PLAY, t
        return Step(APPROACH, commands, [])

    def _play(self, t):
        before = self._episode_s
        self._episode_s = min(self.start_s + (t - self._play_t) * self.speed, self.end_s)
        commands, arrived = {}, True
        for side, path in sorted(self.paths.items()):
            target = [float(np.interp(self._episode_s, path.times, column))
                      for column in path.values.T]
            target = clamp([fixed if np.isnan(a) else a  # a joint not yet commanded stays
                            for a, fixed in zip(target, self._start_pose[side])],
                           self.limits[side])
            commands[side] = self._budgets[side].move(
                target, [lim.velocity for lim in self.limits[side]], t)
            arrived = arrived and commands[side] == target
        if not self._clear_of_zones(t, commands, ''):   # the episode's clock waits
            self._episode_s = before
            self._play_t = t - (before - self.start_s) / self.speed
            return Step(PLAY, commands, []) if self.phase == PLAY else self.step(t)
        grips = [Grip(side, position) for side in sorted(self.grips)
                 for g_t, position in self.grips[side] if before < g_t <= self._episode_s]
        if self._episode_s >= self.end_s and arrived:
            self.phase = FINISHED
        return Step(PLAY, commands, grips)

    def _clear_of_zones(self, t, commands, where):
        """Return True when every guarded arm's motion to its command is proven clear of the
        zones; else cut each held arm's command (in commands, and its speed budget) back along
        its step to what is proven, return False, and stop (naming zone, link, arm and
        `where`) once some arm has been held for ZONE_WAIT_S. Takes commands as sent."""
        held = None
        for side in sorted(set(commands) & set(self.guards)):
            measured = self.robot.measured(side)
            box = self._reach[side].where(t, *measured)
            if box is None:
                self.stop(t, "Baxter's joint states of the %s arm are %.1f s old: its motion "
                          'cannot be kept out of the keep-out zones' % (side, t - measured[0]))
                return False
            command, hit = self.guards[side].limit_box(*box, self._sent[side], commands[side],
                                                       slide=False)
            if hit is not None:
                commands[side] = self._budgets[side].command = command
                held = held or (side, hit)
            self._reach[side].sent(t, command)
        self._sent.update((side, list(command)) for side, command in commands.items())
        if held is None:
            self._held_t = None
            return True
        self._held_t = t if self._held_t is None else self._held_t
        if t - self._held_t >= ZONE_WAIT_S:
            side, hit = held
            self.stop(t, ZONE_CUT % (hit.zone, hit.link, side) + where)
        return False

    def _grip_at(self, side, episode_s):
        """Return the last gripper position (%) commanded at or before episode_s, or None."""
        earlier = [position for g_t, position in self.grips[side] if g_t <= episode_s]
        return earlier[-1] if earlier else None
