"""Tests of the simulated participant in a closed loop with each device's own mapping.

The loop: the participant's actions go into the device's pure core (study.device_core with
key_jog's, pad_axes' controls; the marker's IK; the puppet's hand) as the device node would feed
them; a kinematic Baxter arm follows the device's target 0.1 s late at most 0.6 rad/s per joint,
and toggles following on each press of the side's follow button, as arm_X does.
"""
import collections

import numpy as np
import pytest
from evdev import ecodes as e

from robopuppet import baxter_description as bd, interface
from robopuppet.study import device_core, key_jog, pad_axes, participant
from robopuppet.study import participant_hands as ph
from robopuppet.study.cartesian import CartesianArm
from robopuppet.study.input_events import InputEvent

DESCRIPTION = bd.load()
RATE_HZ = 50.0
DELAY_S = 0.1
ARM_RAD_S = 0.6
# elbows bent, away from the stretched arm's singularity (the study's arms work there)
START = {'right': np.array([-0.3, -0.8, 1.0, 1.8, -0.5, 0.8, 0.0]),
         'left': np.array([0.3, -0.8, -1.0, 1.8, 0.5, 0.8, 0.0])}
SIDE = {'left': 'L', 'right': 'R'}


def controls(device, side):
    return {'keyboard': lambda: key_jog.KeyJog(side),
            'gamepad': lambda: pad_axes.Gamepad(side),
            'spacemouse': lambda: pad_axes.SpaceMouse(side)}.get(device, lambda: None)()


class Loop:
    """The participant, the device cores of the trial's arms, and the kinematic arms."""

    def __init__(self, device, arms=('right',), seed=1, start=None, sag=None):
        self.device, self.arms = device, arms
        self.person = participant.Participant(device, DESCRIPTION)
        self.person.begin(0.0, arms, seed)
        self.kin = {a: CartesianArm(a, DESCRIPTION) for a in arms}
        self.cores = {a: device_core.DeviceCore(SIDE[a], controls(device, SIDE[a]), self.kin[a])
                      for a in arms}
        self.measured = {a: np.array((start or START)[a], dtype=float) for a in arms}
        self.following = {a: False for a in arms}
        self.commands = {a: collections.deque() for a in arms}
        self.button = {a: 0 for a in arms}
        self.hand = {a: None for a in arms}
        self.closed = {a: False for a in arms}
        self.log, self.t = [], 0.0
        self.sag = np.zeros(7) if sag is None else np.asarray(sag)   # the puppet ends short

    def tip(self, arm):
        return self.kin[arm].tip(self.measured[arm])

    def take(self, action):
        if isinstance(action, ph.Event):
            for core in self.cores.values():   # every side reads the one device
                core.on_events([InputEvent(self.t, *action)])
            return
        arm = {'L': 'left', 'R': 'right'}[action.side]
        core = self.cores[arm]
        if isinstance(action, ph.MarkerPose):
            q = self.kin[arm].solve(action.xyz, action.quat, core.target())
            if q is not None:
                core.set_target(q)
        elif isinstance(action, ph.MarkerMenu):
            if action.entry == ph.MENU_FOLLOW:
                core.press_follow(self.t)
            else:
                core.set_closed(action.entry == ph.MENU_CLOSE)
        elif isinstance(action, ph.Hand):
            self.hand[arm] = np.array(action.angles)
        elif isinstance(action, ph.Press):
            core.press_follow(self.t)
        elif isinstance(action, ph.EndPiece):
            core.set_closed(action.closed)

    def run(self, targets, seconds):
        """Run for `seconds`; targets: [Target] or a function of t giving them."""
        end = self.t + seconds
        while self.t < end:
            shown = targets(self) if callable(targets) else targets
            actions = self.person.step(
                self.t, shown, dict(self.measured), dict(self.following),
                {a: interface.FOLLOWING if self.following[a] else interface.READY
                 for a in self.arms})
            self.log.extend((self.t, a) for a in actions)
            for action in actions:
                self.take(action)
            self.step_arms()
            self.t += 1.0 / RATE_HZ

    def step_arms(self):
        """Step every device core on the same states, then the arms (a press seen by both
        sides at once, as their nodes see it, before either arm controller answers)."""
        outs = {}
        for arm in self.arms:
            core = self.cores[arm]
            core.on_robot(self.measured[arm])
            core.on_teleop(self.following[arm])
            core.on_other_teleop(any(f for a, f in self.following.items() if a != arm))
            if self.device == 'puppet' and self.hand[arm] is not None and self.following[arm]:
                core.set_target(self.hand[arm] - self.sag)
            outs[arm] = core.step(self.t)
        for arm, out in outs.items():
            self.step_arm(arm, out)

    def step_arm(self, arm, out):
        if out.button and not self.button[arm]:
            self.following[arm] = not self.following[arm]
        self.button[arm] = out.button
        self.closed[arm] = out.grippers[interface.END_PIECE_GRIPPER] == device_core.PRESSED
        queue = self.commands[arm]
        if self.following[arm] and out.positions is not None:
            queue.append((self.t, np.array(out.positions)))
        while queue and queue[0][0] <= self.t - DELAY_S:
            command = queue.popleft()[1]
            step = np.clip(command - self.measured[arm], -ARM_RAD_S / RATE_HZ,
                           ARM_RAD_S / RATE_HZ)
            self.measured[arm] = self.measured[arm] + step


def target_from(arm, offset, tolerance_m=0.03, closed=None, turn=True):
    xyz, rotation = CartesianArm(arm, DESCRIPTION).tip(START[arm])
    quat = bd.matrix_quaternion(rotation) if turn else None
    return participant.Target(arm, tuple(xyz + np.array(offset)), quat, closed, tolerance_m)


def follow_presses(loop):
    kinds = {'keyboard': key_jog.FOLLOW_KEY['R'], 'gamepad': pad_axes.FOLLOW['R'],
             'spacemouse': pad_axes.SPACE_FOLLOW}
    code = kinds.get(loop.device)
    return [t for t, a in loop.log if (
        isinstance(a, ph.Event) and a.code == code and a.value == 1
        or isinstance(a, ph.MarkerMenu) and a.entry == ph.MENU_FOLLOW
        or isinstance(a, ph.Press))]


@pytest.mark.parametrize('device', interface.STUDY_DEVICES)
def test_each_device_brings_the_tip_onto_the_goal_and_follow_is_pressed_once(device):
    target = target_from('right', (0.12, -0.08, 0.06))
    loop = Loop(device)
    loop.run([target], 12.0)
    xyz, _ = loop.tip('right')
    assert np.linalg.norm(xyz - target.xyz) < target.tolerance_m
    assert loop.following['right']
    assert len(follow_presses(loop)) == 1
    # and it stays there: no drift while the goal is held
    loop.run([target], 2.0)
    assert np.linalg.norm(loop.tip('right')[0] - target.xyz) < target.tolerance_m


def test_the_puppet_hand_makes_up_for_an_arm_that_ends_short_of_it():
    target = target_from('right', (0.1, -0.1, -0.05))
    loop = Loop('puppet', sag=(0.05, 0.1, 0.0, -0.1, 0.0, 0.1, 0.0))
    loop.run([target], 10.0)
    assert np.linalg.norm(loop.tip('right')[0] - target.xyz) < target.tolerance_m


def test_an_arm_held_by_a_zone_lifts_away_goes_over_the_goal_then_down_aimed_higher():
    target = target_from('right', (0.1, 0.0, 0.0))
    person = participant.Participant('marker', DESCRIPTION)
    person.begin(0.0, ('right',), 5)
    args = ([target], {'right': START['right']}, {'right': True}, {'right': interface.FOLLOWING})
    person.step(1.0, *args)
    goal = person._goals['right']
    free = goal.reach.xyz1[2]
    person.step(6.0, *args, held={'right': True})   # reach over, arm still, off the goal: held
    held_at = person.tip('right', START['right'])[0]
    up = goal.reach.xyz1 - held_at
    assert up[2] > participant.RETREAT_M - 0.01 and np.hypot(up[0], up[1]) < 0.02
    person.step(12.0, *args)    # the lift over, the arm still off the goal: over the goal
    over = goal.reach.xyz1 - np.array(target.xyz)
    assert over[2] > participant.RETREAT_M - 0.01 and np.hypot(over[0], over[1]) < 0.02
    person.step(18.0, *args)    # then down to it, aimed higher (HELD_LIFT, with the aim's noise)
    lifted = goal.reach.xyz1
    assert lifted[2] - target.xyz[2] > 0.0 and free - target.xyz[2] < 0.02
    assert np.linalg.norm(lifted[:2] - np.array(target.xyz[:2])) < target.tolerance_m


def test_the_spacemouse_turns_the_gripper_to_the_goal_orientation():
    xyz, rotation = CartesianArm('right', DESCRIPTION).tip(START['right'])
    turned = bd.axis_angle_matrix((0.0, 0.0, 1.0), 0.4) @ rotation
    target = participant.Target('right', tuple(xyz + (0.05, 0.0, 0.0)),
                                bd.matrix_quaternion(turned), None, 0.03)
    loop = Loop('spacemouse')
    loop.run([target], 10.0)
    _, now = loop.tip('right')
    assert np.degrees(np.linalg.norm(participant.rotation_error(turned, now))) < 10.0


def test_no_motion_before_the_reaction_time():
    firsts = []
    for seed in range(20):
        loop = Loop('gamepad', seed=seed)
        loop.following['right'] = True
        loop.run([target_from('right', (0.1, 0.0, 0.0))], 0.8)
        firsts.append(min(t for t, a in loop.log if a.type == e.EV_ABS))
    assert min(firsts) >= participant.REACTION_MIN_S
    assert 0.22 < np.mean(firsts) < 0.38
    assert np.std(firsts) > 0.01   # the reaction time varies


def test_a_new_goal_waits_a_reaction_time_too():
    first, second = target_from('right', (0.1, 0.0, 0.0)), target_from('right', (0.1, -0.1, 0.0))
    loop = Loop('marker')
    loop.run([first], 6.0)
    switched = loop.t
    loop.run([second], 2.0)
    poses = [t for t, a in loop.log if isinstance(a, ph.MarkerPose) and t >= switched
             and np.linalg.norm(np.subtract(a.xyz, first.xyz)) > 0.005]
    assert poses and poses[0] - switched >= participant.REACTION_MIN_S


def test_the_same_seed_acts_the_same_and_another_seed_differs():
    target = target_from('right', (0.1, -0.05, 0.05))
    runs = []
    for seed in (3, 3, 4):
        loop = Loop('keyboard', seed=seed)
        loop.run([target], 6.0)
        runs.append([(round(t, 3), a) for t, a in loop.log])
    assert runs[0] == runs[1]
    assert runs[0] != runs[2]


@pytest.mark.parametrize('device', ['keyboard', 'gamepad', 'marker', 'puppet'])
def test_grasp_at_a_then_release_at_b_changes_the_grip_once_each(device):
    grasp = target_from('right', (0.1, 0.0, -0.05), closed=True)
    release = target_from('right', (0.1, -0.15, 0.0), closed=False)
    loop = Loop(device)
    grasped_at = []

    def shown(loop):
        if not grasped_at and loop.closed['right']:
            grasped_at.append(loop.tip('right')[0])
        return [release if grasped_at else grasp]
    loop.run(shown, 14.0)
    assert grasped_at and np.linalg.norm(grasped_at[0] - grasp.xyz) < grasp.tolerance_m
    assert not loop.closed['right']   # released at B
    assert np.linalg.norm(loop.tip('right')[0] - release.xyz) < release.tolerance_m
    grips = {'keyboard': key_jog.GRIP_KEY['R'], 'gamepad': pad_axes.GRIP['R']}.get(device)
    changes = [a for t, a in loop.log if t > 0.0 and (
        isinstance(a, ph.Event) and a.code == grips and a.value == 1
        or isinstance(a, (ph.MarkerMenu)) and a.entry != ph.MENU_FOLLOW
        or isinstance(a, ph.EndPiece))]
    assert len(changes) == 2


def test_a_closed_gripper_opens_before_a_grasp():
    loop = Loop('keyboard')
    loop.person.closed['right'] = True
    loop.cores['right'].on_events([InputEvent(0.0, e.EV_KEY, key_jog.GRIP_KEY['R'], 1)])
    loop.run([target_from('right', (0.08, 0.0, 0.0), closed=True)], 8.0)
    grips = [t for t, a in loop.log if isinstance(a, ph.Event)
             and a.code == key_jog.GRIP_KEY['R'] and a.value == 1]
    assert len(grips) == 2 and loop.closed['right']


def test_a_spacemouse_split_by_a_fault_is_brought_back_to_both_arms_following():
    left = target_from('left', (0.1, 0.05, 0.05), turn=False)
    right = target_from('right', (0.1, -0.05, 0.05), turn=False)
    loop = Loop('spacemouse', arms=('left', 'right'))
    loop.run([left, right], 2.0)
    assert loop.following == {'left': True, 'right': True}
    loop.following['left'] = False      # arm_L faulted: only the right arm follows
    loop.run([left, right], 3.0 * participant.FOLLOW_RETRY_S)
    assert loop.following == {'left': True, 'right': True}


def test_one_spacemouse_press_engages_both_arms_and_both_reach_mirrored_goals():
    left = target_from('left', (0.1, 0.05, 0.05), turn=False)
    right = target_from('right', (0.1, -0.05, 0.05), turn=False)
    loop = Loop('spacemouse', arms=('left', 'right'))
    loop.run([left, right], 10.0)
    assert loop.following == {'left': True, 'right': True}
    assert loop.person.presses == 1
    for goal in (left, right):
        assert np.linalg.norm(loop.tip(goal.arm)[0] - goal.xyz) < goal.tolerance_m


@pytest.mark.parametrize('device', interface.STUDY_DEVICES)
def test_between_trials_the_participant_lets_go_and_follows_again_next_trial(device):
    arms = ('left', 'right') if device == 'spacemouse' else ('right',)
    goals = [target_from(arm, (0.05, 0.0, 0.05), turn=False) for arm in arms]
    loop = Loop(device, arms=arms)
    loop.run(goals, 4.0)
    assert all(loop.following.values())
    for action in loop.person.rest(loop.t):
        loop.take(action)
    end = loop.t + 2.0 * participant.FOLLOW_RETRY_S
    while loop.t < end:   # the runner's DEVICE phase: the participant lets go
        for action in loop.person.let_go(loop.t, dict(loop.measured), dict(loop.following)):
            loop.take(action)
        loop.step_arms()
        loop.t += 1.0 / RATE_HZ
    assert not any(loop.following.values())
    assert loop.person.presses == (1 if device == 'spacemouse' else len(arms)) + 1
    loop.person.begin(loop.t, arms, 2)   # the next trial: follow is pressed again, and it takes
    loop.run(goals, 2.0)
    assert all(loop.following.values())


def test_rest_lets_go_of_every_key():
    loop = Loop('keyboard')
    loop.run([target_from('right', (0.2, -0.2, 0.1))], 1.5)
    for action in loop.person.rest(loop.t):
        loop.take(action)
    assert not any(loop.cores['right']._controls.velocity())


def test_study_state_goals_become_targets_and_identity_means_any_orientation():
    from geometry_msgs.msg import Point, Pose, Quaternion
    from robopuppet_msgs.msg import StudyState
    state = StudyState(targets=[Pose(Point(0.6, -0.3, 0.1), Quaternion(0, 0, 0, 1)),
                                Pose(Point(0.6, 0.3, 0.1), Quaternion(0, 1, 0, 0))],
                       target_arms=['right', 'left'], target_closed=[True, False],
                       target_tolerance=[0.03, 0.04])
    right, left = participant.targets_of(state)
    assert right == participant.Target('right', (0.6, -0.3, 0.1), None, True,
                                       pytest.approx(0.03))
    assert left.quat == (0, 1, 0, 0) and left.closed is False


def test_a_goal_out_of_reach_with_the_gripper_as_it_is_is_reached_with_it_down():
    # a keyboard trial's arm, wrist bent far (w1 1.95), next to a trace waypoint that this
    # orientation cannot reach: the participant turns the gripper back down instead of waiting
    q = np.array([0.83, -0.86, 0.01, 1.1, -0.12, 1.95, 0.68])
    goal = participant.Target('right', (0.832, -0.228, 0.112), None, None, 0.04)
    person = participant.Participant('keyboard', DESCRIPTION)
    person.begin(0.0, ('right',), 1)
    person.step(1.0, [goal], {'right': q}, {'right': True}, {'right': interface.FOLLOWING})
    reach = person._goals['right'].reach
    assert np.linalg.norm(person.tip('right', reach.q1)[0] - reach.xyz1) < 0.005
    assert np.abs(reach.q1 - q).max() > 0.3
