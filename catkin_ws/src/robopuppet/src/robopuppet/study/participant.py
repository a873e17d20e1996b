"""The simulated participant: a model operator who drives a study device toward each goal (pure).

Like a person: a reaction time after each new goal (0.3 s, seeded noise), a minimum-jerk reach
(assist.demonstration.minimum_jerk) toward a slightly noisy aim point, corrections when it sees
the arm off the goal, the follow control pressed once at a trial's start for each arm that does
not follow (and again between trials, to let go), the gripper changed once when a goal wants
another grip state (opened before a grasp, closed or opened on arrival), and, held back by a
keep-out zone, a lift away and a way in from above. What the hands do on each device:
participant_hands.py. Time is an argument; the noise comes from one generator seeded per trial.
"""
import collections
import math

import numpy as np

from robopuppet import interface
from robopuppet.assist import arm_path
from robopuppet.assist.demonstration import minimum_jerk
from robopuppet.baxter_sim.baxter_ik import quaternion_matrix, rotation_error
from robopuppet.baxter_description import axis_angle_matrix
from robopuppet.study import participant_hands as hands_of, tasks
from robopuppet.study.cartesian import CartesianArm

Target = collections.namedtuple('Target', 'arm xyz quat closed tolerance_m')
Target.__doc__ = """One goal as the study state shows it: arm 'left'|'right', xyz (m, base), quat
(x, y, z, w) or None (any), closed (the grip wanted: True, False or None for any), tolerance_m."""

REACTION_S, REACTION_SD_S, REACTION_MIN_S = 0.3, 0.05, 0.15
AIM_SD = 0.15           # the aim point's error, per axis, as a share of the goal's tolerance
ARRIVED = 0.6           # the tip within this share of the tolerance counts as on the goal
ARRIVED_RAD = 0.15      # and, for a goal with an orientation, within this angle of it
GRIP_PAUSE_S = 0.3      # on the goal this long before the grip changes
SETTLE_S = 0.6          # a reach that ended this long ago without arriving is made again,
STILL_M_S, STILL_DT_S = 0.02, 0.3   # once the tip moved slower than this over this long
STILL_WAIT_S = 3.0      # (or this long after the reach ended)
FOLLOW_RETRY_S = 3.0    # a follow press that did not take is made again after this long
CALIBRATE_RETRY_S = 30.0
HELD_LIFT = 0.4         # a zone held the arm: aim this share of the tolerance higher, and
RETREAT_M, RETREATS = 0.08, 3   # lift this far, over the goal, down to it (so often per goal)
STUCK_PLANS = 3         # after this many reaches of one goal, IK from other seeds
MAX_OFFSET_RAD = 0.2    # the most a hand leads Baxter to make up for where it ends
FOLLOW_STATES = (interface.READY, interface.FOLLOWING)


def targets_of(state):
    """Return a StudyState's goals as [Target]; an identity or zero orientation means any
    orientation (StudyState has no field for 'any')."""
    out = []
    for pose, arm, closed, tolerance in zip(state.targets, state.target_arms,
                                            state.target_closed, state.target_tolerance):
        o, p = pose.orientation, pose.position
        quat = (o.x, o.y, o.z, o.w)
        if np.allclose(quat, (0.0, 0.0, 0.0, 1.0)) or np.allclose(quat, 0.0):
            quat = None
        out.append(Target(arm, (p.x, p.y, p.z), quat, bool(closed), float(tolerance)))
    return out


class Reach:
    """A minimum-jerk path of the tip (and of the joints) from t0 over duration_s."""

    def __init__(self, t0, duration_s, start, goal, q_start=None, q_goal=None):
        self.t0, self.duration_s = t0, duration_s
        (self.xyz0, self.rot0), (self.xyz1, self.rot1) = start, goal
        self._turn = rotation_error(self.rot1, self.rot0)
        self.q0, self.q1 = q_start, q_goal

    @property
    def end(self):
        return self.t0 + self.duration_s

    def at(self, t):
        """Return (xyz, velocity, rotation, angular velocity, joints) of the path at t."""
        s = min(max((t - self.t0) / self.duration_s, 0.0), 1.0)
        share = minimum_jerk(s)
        speed = 30.0 * s * s * (1.0 - s) ** 2 / self.duration_s   # d share / dt
        xyz = self.xyz0 + share * (self.xyz1 - self.xyz0)
        angle = np.linalg.norm(self._turn)
        rotation = (self.rot0 if angle < 1e-9 else
                    axis_angle_matrix(self._turn / angle, share * angle) @ self.rot0)
        joints = None if self.q1 is None else self.q0 + share * (self.q1 - self.q0)
        return xyz, speed * (self.xyz1 - self.xyz0), rotation, speed * self._turn, joints


class ArmGoal:
    """One arm's pursuit of one goal: when it may start, its reach, its grip steps."""

    def __init__(self, target, go_t):
        self.target, self.go_t = target, go_t
        self.reach, self.on_since, self.opened = None, None, False
        self.tip, self.moved_t = None, go_t   # (t, xyz) a while ago; when it last moved
        # Baxter's arm off the hand's pose (puppet); reaches made; whether a zone held the arm
        # (ever; since the last retreat); the retreats made; the via points ahead (xyz)
        self.offset, self.plans, self.held, self.held_now, self.retreats, self.via = (
            0.0, 0, False, False, 0, [])


class Participant:
    """A model operator of one study device.

    Args:
        device: one of interface.STUDY_DEVICES.
        description: a baxter_description.Description (the arms' kinematics).
        speeds: {'jog_speed': rad/s, 'max_speed': m/s, 'max_turn': rad/s} of the device.
    The grip state it believes in starts open, as a freshly started device's does; a device
    whose grip is set, not toggled (marker, puppet), is set open at each trial's start.
    """

    def __init__(self, device, description, speeds=None):
        self.device = device
        self.speeds = dict(hands_of.SPEEDS, **(speeds or {}))
        self._arms = {arm: CartesianArm(arm, description, arm_path.joint_bounds(arm) if
                                        device == 'puppet' else None)   # what a puppet shows
                      for arm in interface.BAXTER_SIDES}
        self.closed = {arm: False for arm in interface.BAXTER_SIDES}
        self._let_go_t = -math.inf
        self.begin(0.0, (), 0)

    def begin(self, t, arms, seed):
        """Start a trial at t with Baxter arms `arms`, noise seeded by seed."""
        self.rng = np.random.default_rng(seed)
        self.hands = hands_of.make_hands(self.device, self.rng, **self.speeds)
        self.arms, self.start_t = tuple(arms), t
        self.go_t = t + self._reaction()
        self._goals, self._pressed_t, self._calibrate_t = {}, {}, {}
        self.presses, self._grip_set = 0, False
        if not self.hands.toggles:
            self.closed = {arm: False for arm in interface.BAXTER_SIDES}

    def _reaction(self):
        return max(REACTION_MIN_S, REACTION_S + REACTION_SD_S * self.rng.standard_normal())

    def tip(self, arm, angles):
        """Return (xyz, 3x3 rotation) of the arm's gripper tool point at angles."""
        return self._arms[arm].tip(angles)

    def on_goal(self, target, tip):
        """Return True when the tip (xyz, rotation) is on the target, as this device can tell."""
        xyz, rotation = tip
        if np.linalg.norm(xyz - np.asarray(target.xyz)) > ARRIVED * target.tolerance_m:
            return False
        return (target.quat is None or not self.hands.turns or np.linalg.norm(
            rotation_error(quaternion_matrix(target.quat), rotation)) <= ARRIVED_RAD)

    def step(self, t, targets, angles, following, states, held=None):
        """Return the device actions of time t.

        Args:
            targets: [Target] the study shows now (the first of each arm counts).
            angles: {arm: 7 rad} Baxter's measured angles.
            following: {arm: bool} whether each arm follows this device.
            states: {arm: teleop state} of the arm controller that drives each arm.
            held: {arm: bool} whether a keep-out zone holds the arm back (the zones lie
                below: the next reach aims at the goal's upper part).
        """
        out = self.hands.due(t) + self._engage(t, angles, following, states)
        if not (self.hands.toggles or self._grip_set):
            self._grip_set = True   # a grip that is set, not toggled: open, as believed
            out += self.hands.grip(self.arms, False, t)
        wants, grips = {}, {}
        for arm in self.arms:
            target = next((g for g in targets if g.arm == arm), None)
            if target is None or arm not in angles or not following.get(arm):
                continue
            goal = self._goals.get(arm)
            if goal is None or goal.target != target:
                goal = self._goals[arm] = ArmGoal(target, max(t, self.go_t) + (
                    self._reaction() if goal is not None else 0.0))
            if t < goal.go_t:
                continue
            goal.held_now = goal.held_now or bool((held or {}).get(arm))
            goal.held = goal.held or goal.held_now
            wants[arm], grip = self._pursue(t, goal, angles[arm])
            if grip is not None:
                grips[arm] = grip
        out += self._grip(t, grips)
        return out + (self.hands.drive(t, wants) if wants else [])

    def _engage(self, t, angles, following, states):
        """Press follow (once; again only if it did not take) for arms that do not follow."""
        out, press = [], []
        for arm in self.arms:
            if following.get(arm) or arm not in angles:
                continue
            if states.get(arm) == interface.CALIBRATING:
                out += self.calibrate(t, [arm], angles, states)
            elif (states.get(arm) in FOLLOW_STATES and t >= self.go_t
                  and t >= self._pressed_t.get(arm, -math.inf) + FOLLOW_RETRY_S):
                press.append(arm)
        if press:   # shared, with an arm following: the press stops it; the next starts all
            for arm in (self.arms if self.hands.shared else press):
                self._pressed_t[arm] = t
            self.presses += 1 if self.hands.shared else len(press)
            out += self.hands.follow(press, t, angles)
        return out

    def _pursue(self, t, goal, angles):
        """Return (Want, the grip to set or None) of one arm on its goal at t."""
        target, tip = goal.target, self.tip(goal.target.arm, angles)
        on_goal = self.on_goal(target, tip)
        goal.on_since = (goal.on_since if goal.on_since is not None else t) if on_goal else None
        if goal.tip is None or t - goal.tip[0] >= STILL_DT_S:   # look at the arm's speed
            if goal.tip is None or np.linalg.norm(tip[0] - goal.tip[1]) > STILL_M_S * (
                    t - goal.tip[0]):
                goal.moved_t = t
            goal.tip = (t, tip[0])
        if goal.reach is None or (not on_goal and t > goal.reach.end + SETTLE_S and (
                t - goal.moved_t > STILL_DT_S or t > goal.reach.end + STILL_WAIT_S)):
            hand = None if goal.reach is None or self.device != 'puppet' else goal.reach.q1
            if hand is not None:   # where Baxter's arm ended off the hand's pose
                goal.offset = np.clip(hand - angles, -MAX_OFFSET_RAD, MAX_OFFSET_RAD)
            goal.plans += 1   # stuck (a zone holds the arm): try another arm configuration
            seeds = self._arms[target.arm].seeds
            seed = None if goal.plans <= STUCK_PLANS else seeds[goal.plans % len(seeds)]
            if goal.held_now and goal.retreats < RETREATS:   # held: up, over the goal, down
                goal.held_now, goal.retreats = False, goal.retreats + 1
                goal.via = [tip[0] + (0.0, 0.0, RETREAT_M),
                            np.asarray(target.xyz) + (0.0, 0.0, RETREAT_M)]
            toward = target
            if goal.via:
                toward, seed = target._replace(xyz=tuple(goal.via.pop(0)), quat=None), None
            goal.reach = self._plan(t, toward, tip, angles, hand, goal.offset if seed is None
                                    else 0.0, seed, goal.held)
        xyz, velocity, rotation, turn, joints = goal.reach.at(t)
        hold = on_goal and t >= goal.reach.end
        want = hands_of.Want(xyz, velocity, rotation, turn, tip[0], tip[1], joints,
                             goal.reach.q1, np.asarray(angles, dtype=float), hold)
        grip = None
        if target.closed and self.closed[target.arm] and not goal.opened:
            goal.opened, grip = True, False   # open before the grasp
        elif (target.closed is not None and target.closed != self.closed[target.arm]
              and on_goal and t - goal.on_since >= GRIP_PAUSE_S):
            grip = target.closed
        return want, grip

    def _plan(self, t, target, tip, angles, hand=None, offset=0.0, seed=None, held=False):
        """Return a Reach from the measured tip to a noisy aim at the target; joints from
        the hand's pose (or the measured angles) to the goal's plus the offset seen."""
        aim = np.asarray(target.xyz) + AIM_SD * target.tolerance_m * self.rng.standard_normal(3)
        aim[2] += HELD_LIFT * target.tolerance_m * held
        rotation = tip[1] if target.quat is None else quaternion_matrix(target.quat)
        q0, q1 = np.asarray(angles, dtype=float), None
        if self.hands.joint_space:
            arm = self._arms[target.arm]
            q1 = arm.solve_near(aim, rotation, q0 if seed is None else seed)
            if q1 is None and target.quat is None:   # any orientation: the gripper down, then
                q1 = arm.solve_near(aim, tasks.neutral_rotation(target.arm), q0)
        if self.hands.joint_space:   # nothing reaches it: stay (try again after SETTLE_S)
            q1 = q0 if q1 is None else self._arms[target.arm].clip(q1 + offset)
            q0 = q0 if hand is None else np.asarray(hand, dtype=float)
        duration = hands_of.reach_time(
            self.device, np.linalg.norm(aim - tip[0]),
            np.linalg.norm(rotation_error(rotation, tip[1])) if self.hands.turns else 0.0,
            0.0 if q1 is None else np.abs(q1 - q0).max(), self.speeds)
        duration *= 1.0 + 0.1 * self.rng.standard_normal()
        return Reach(t, max(duration, 0.3), tip, (aim, rotation), q0, q1)

    def _grip(self, t, grips):
        """Return the actions that set the grips wanted now (a shared control: all at once)."""
        out = []
        for closed in sorted(set(grips.values())):
            arms = (list(self.arms) if self.hands.shared
                    else [a for a, c in grips.items() if c == closed])
            self.closed.update(dict.fromkeys(arms, closed))
            out += self.hands.grip(arms, closed, t)
            if self.hands.shared:
                break   # one button toggles every side
        return out

    def rest(self, t):
        """Return the actions that let go of the device (between trials)."""
        return self.hands.rest(t)

    def calibrate(self, t, arms, angles, states):
        """Return the actions that get a new device working for each of the arms whose
        controller calibrates (the simulated puppet: the turn through its index marks, ending
        at Baxter's pose); again after CALIBRATE_RETRY_S."""
        out = []
        for arm in arms:
            if (states.get(arm) == interface.CALIBRATING and arm in angles
                    and t >= self._calibrate_t.get(arm, -math.inf) + CALIBRATE_RETRY_S):
                self._calibrate_t[arm] = t
                out += self.hands.calibrate(arm, angles[arm])
        return out

    def let_go(self, t, angles, following):
        """Return the actions that stop the arms following between trials, so that the runner
        can bring them to their start: a follow press, again after FOLLOW_RETRY_S while an arm
        still follows (a shared control's press acts on every side)."""
        held = [arm for arm in interface.BAXTER_SIDES if following.get(arm) and arm in angles]
        out = self.hands.due(t)
        if held and t >= self._let_go_t + FOLLOW_RETRY_S:
            self._let_go_t = t
            self.presses += 1
            out += self.hands.follow(held, t, angles)
        return out
