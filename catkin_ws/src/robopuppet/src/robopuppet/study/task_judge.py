"""Judge a study trial from MEASURED gripper poses and gripper states (docs/study.md, TASKS).

TrialJudge walks through a Trial's stages (study.tasks): a `hold` stage is met when each of its
goals is within tolerance (position, orientation when the goal has one, gripper state when it
names one) at once for the goals' hold_s without a break; a `grasp` stage when the gripper,
within tolerance of spot A, was open there and then closes (the object is then carried at the
tool point); a `release` stage when the carrying gripper opens within tolerance of spot B.
Opening it anywhere else drops the object: the trial fails at once. A trial not done by
tasks.TIMEOUT_S fails. Pure: time is an argument; numpy only.
"""
import numpy as np

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_ik import quaternion_matrix
from robopuppet.study import tasks


def tips_of(description, names, positions):
    """Return {arm: (xyz (3,) m, 3x3 rotation)} of each Baxter arm's tool point in base.

    Args:
        description: a baxter_description.Description.
        names, positions: a /robot/joint_states message's fields (rad); an arm whose 7 joints
            are not all there, or not finite, is left out.
    """
    angles = dict(zip(names, positions))
    tips = {}
    for side in bd.BAXTER_SIDES:
        joints = bd.arm_joint_names(side)
        if all(name in angles and np.isfinite(angles[name]) for name in joints):
            pose = description.transform(angles, bd.gripper_link(side))
            tips[side] = (pose[:3, 3].copy(), pose[:3, :3].copy())
    return tips


def within(goal, tip, closed):
    """Return whether a measured tip (xyz, rotation) and gripper state meet a goal."""
    if tip is None or np.linalg.norm(np.asarray(tip[0]) - goal.xyz) > goal.tolerance_m:
        return False
    if goal.quat is not None and goal.tolerance_rad is not None and \
            tasks.angle_between(tip[1], quaternion_matrix(goal.quat)) > goal.tolerance_rad:
        return False
    return goal.closed is None or closed == goal.closed


class TrialJudge:
    """Judge one trial from t0 (s) on.

    Args:
        trial: the tasks.Trial; t0: its start (s); timeout_s: when it fails undone (s after
            t0; tasks.TIMEOUT_S of its task by default).

    Attributes:
        done, success: whether it ended, and met every stage.
        end_t: when it ended (s), None before.
        detail: what to do now, or how it ended.
    """

    def __init__(self, trial, t0, timeout_s=None):
        self.trial, self.t0 = trial, float(t0)
        self.timeout_s = timeout_s or tasks.TIMEOUT_S[trial.task]
        self.stage = 0
        self.done = self.success = False
        self.end_t = None
        self._since = None          # a hold stage: when all its goals were first met together
        self._open_there = False    # a grasp stage: the gripper was open within tolerance
        self._carried = False
        self._object = None
        self._reached = ()
        self._t = self.t0
        first = trial.plan[0]
        if first.kind == 'grasp' or trial.task == 'bimanual':
            self._object = np.mean([g.xyz for g in first.goals], axis=0)
        self.detail = self._todo()

    def _todo(self, more=''):
        stage = self.trial.plan[self.stage]
        return 'step %d of %d: %s%s' % (self.stage + 1, len(self.trial.plan), stage.text, more)

    def goals(self, t=None):
        """Return the Goals to reach now (empty once done)."""
        return [] if self.done else list(self.trial.plan[self.stage].goals)

    def reached(self):
        """Return, for each of goals(), whether the last update met it."""
        return [] if self.done else list(self._reached)

    def carried(self):
        """Return whether the pick_place object is in the gripper."""
        return self._carried

    def objects(self):
        """Return [(name, xyz)] of the task's objects where they are now: the pick_place
        object (at the tool point while carried), the bimanual tray (between the grippers once
        both held their handles)."""
        return [] if self._object is None else [(self.trial.task, tuple(self._object))]

    def _finish(self, t, success, detail):
        self.done, self.success, self.end_t, self.detail = True, success, t, detail
        self._reached = ()

    def _next(self, t):
        self.stage += 1
        self._since = None
        self._open_there = False
        if self.stage == len(self.trial.plan):
            self._finish(t, True, 'done in %.1f s' % (t - self.t0))
        else:
            self.detail = self._todo()

    def update(self, t, tips, closed):
        """Judge the measured state at time t (s).

        Args:
            tips: {arm: (xyz, 3x3 rotation)} of the tool points (tips_of); a missing arm meets
                no goal.
            closed: {arm: bool} the grippers' measured states (True closed).
        """
        if self.done or t < self._t:
            return
        self._t = t
        stage = self.trial.plan[self.stage]
        self._reached = tuple(within(g, tips.get(g.arm), closed.get(g.arm)) for g in stage.goals)
        if stage.kind == 'hold':
            self._hold(t, stage)
        else:
            self._carry(t, stage, tips, closed)
        if self.trial.task == 'bimanual' and self.stage == 1 and not self.done:
            self._object = np.mean([tips[a][0] for a in tasks.ARMS['bimanual'] if a in tips]
                                   or [self._object], axis=0)
        if not self.done and t - self.t0 >= self.timeout_s:
            self._finish(t, False, 'timed out after %g s at step %d of %d'
                         % (self.timeout_s, self.stage + 1, len(self.trial.plan)))

    def _hold(self, t, stage):
        if not all(self._reached):
            self._since = None
            self.detail = self._todo()
            return
        if self._since is None:
            self._since = t
        held = t - self._since
        hold_s = max(g.hold_s for g in stage.goals)
        if held >= hold_s:
            self._next(t)
        else:
            self.detail = self._todo(': hold %.1f s more' % (hold_s - held))

    def _carry(self, t, stage, tips, closed):
        (goal,) = stage.goals
        tip, shut = tips.get(goal.arm), closed.get(goal.arm)
        near = tip is not None and np.linalg.norm(tip[0] - goal.xyz) <= goal.tolerance_m
        if stage.kind == 'grasp':
            if near and shut is False:
                self._open_there = True
                self.detail = self._todo()
            elif not near:
                self._open_there = False
            elif shut and self._open_there:
                self._carried = True
                self._object = np.array(tip[0])
                self._next(t)
            elif shut:
                self.detail = self._todo(': open the gripper there first')
            return
        if tip is not None:
            self._object = np.array(tip[0])
        if shut is False:
            self._carried = False
            if near:
                self._next(t)
            elif tip is None:
                self._finish(t, False, 'dropped away from spot B')
            else:
                gap = np.linalg.norm(tip[0] - goal.xyz)
                self._finish(t, False, 'dropped %.0f cm from spot B' % (gap * 100.0))
