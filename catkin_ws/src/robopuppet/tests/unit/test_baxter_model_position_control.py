"""Tests of robopuppet.baxter_sim.baxter_model's position control (modes 1 and 4): the model of
Baxter's joint position controller that arm_X's keep-out zones rely on (docs/baxter_sim.md, "How
the arms move"): per-joint speed caps, speed ratio, joints independent, monotone approach with no
overshoot, mode 1 going on to its last target and mode 4 holding on the command timeout,
joint limits."""
import random

import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim.baxter_joint_command import POSITION_MODE, RAW_POSITION_MODE
from robopuppet.baxter_sim.baxter_model import (DEFAULT_COMMAND_TIMEOUT_S, DEFAULT_SPEED_RATIO,
                                                BaxterModel)
from robopuppet.baxter_sim.baxter_refusals import CommandError

DESC = bd.load()
LEFT = bd.arm_joint_names('left')
LIMITS = {lim.name: lim for lim in bd.arm_limits('left')}
NEUTRAL = bd.neutral_pose('left')
# For each joint the end of its range farther from the neutral pose (>= 1.5 rad away).
FAR = {n: max((LIMITS[n].lower, LIMITS[n].upper), key=lambda end: abs(end - NEUTRAL[n]))
       for n in LEFT}
DT = 0.01


def enabled_model(ratio=None):
    model = BaxterModel(DESC, 0.0)
    model.set_enabled(True)
    if ratio is not None:
        model.set_speed_ratio('left', ratio)
    return model


def follow(model, mode, targets, start_s, end_s):
    """Send mode/targets every DT from start_s and step to end_s; return [(t, positions)]."""
    arm, trace, t = model.arms['left'], [], start_s
    while t < end_s - 1e-9:
        model.joint_command('left', mode, list(targets), list(targets.values()), t)
        t = round(t + DT, 9)
        model.step(t)
        trace.append((t, dict(arm.positions)))
    return trace


def steps(trace, name):
    """Return the joint's moves between successive samples of a trace (rad)."""
    return [b[1][name] - a[1][name] for a, b in zip(trace, trace[1:])]


@pytest.mark.parametrize('ratio', [None, 0.05, 0.5, 1.0])
def test_mode_1_moves_each_joint_at_the_speed_ratio_times_its_velocity_limit(ratio):
    model = enabled_model(ratio)
    expected = DEFAULT_SPEED_RATIO if ratio is None else ratio
    trace = follow(model, POSITION_MODE, FAR, 0.0, 0.3)   # far: every step is at the cap
    for name in LEFT:
        cap = expected * LIMITS[name].velocity * DT
        direction = 1.0 if FAR[name] > NEUTRAL[name] else -1.0
        assert trace[0][1][name] - NEUTRAL[name] == pytest.approx(direction * cap), name
        assert steps(trace, name) == pytest.approx([direction * cap] * (len(trace) - 1)), name
        assert model.arms['left'].velocities[name] == pytest.approx(direction * cap / DT)


def test_a_new_speed_ratio_sets_the_cap_of_every_step_after_it():
    model = enabled_model()
    trace = follow(model, POSITION_MODE, FAR, 0.0, 0.1)
    for ratio in (0.8, 0.1, 1.0):
        model.set_speed_ratio('left', ratio)
        trace = follow(model, POSITION_MODE, FAR, trace[-1][0], trace[-1][0] + 0.1)
        for name in LEFT:
            cap = ratio * LIMITS[name].velocity * DT
            assert [abs(s) for s in steps(trace, name)] == pytest.approx([cap] * 9), name


@pytest.mark.parametrize('ratio', [0.0, 0.3, 1.0])
def test_mode_4_moves_at_the_velocity_limit_whatever_the_speed_ratio(ratio):
    model = enabled_model(ratio)
    trace = follow(model, RAW_POSITION_MODE, FAR, 0.0, 0.3)
    for name in LEFT:
        cap = LIMITS[name].velocity * DT
        assert [abs(s) for s in steps(trace, name)] == pytest.approx([cap] * 29), name
    # No lag: a joint arrives when its distance at the velocity limit is covered, and stays.
    target = dict(model.arms['left'].positions, left_e1=model.arms['left'].positions['left_e1']
                  - 0.155)   # e1 at 1.5 rad/s: 0.015 rad a step, there after 11 steps
    trace = follow(model, RAW_POSITION_MODE, target, 0.3, 0.5)
    e1 = [p['left_e1'] for _, p in trace]
    assert e1[9] > target['left_e1'] + 0.004
    assert e1[10] == pytest.approx(target['left_e1'], abs=1e-12) and e1[-1] == e1[10]


def test_speed_ratio_0_stops_mode_1_at_once():
    model = enabled_model()
    trace = follow(model, POSITION_MODE, FAR, 0.0, 0.1)
    model.set_speed_ratio('left', 0.0)
    stopped = follow(model, POSITION_MODE, FAR, 0.1, 1.0)
    assert all(p == trace[-1][1] for _, p in stopped)
    assert set(model.arms['left'].velocities.values()) == {0.0}


def test_speed_ratio_outside_0_to_1_is_clipped_as_on_baxter():
    model = enabled_model()
    for ratio, kept in ((1.5, 1.0), (-0.2, 0.0), (0.7, 0.7), (1e300, 1.0)):
        model.set_speed_ratio('left', ratio)
        assert model.arms['left'].speed_ratio == kept
    with pytest.raises(CommandError):
        model.set_speed_ratio('left', float('nan'))
    assert model.arms['left'].speed_ratio == 1.0


@pytest.mark.parametrize('mode, seconds', [(POSITION_MODE, 0.8), (RAW_POSITION_MODE, 0.5)])
def test_joints_move_independently(mode, seconds):
    """A joint with a short way (s0: 0.1 rad) finishes early; the others go on at their own
    caps, exactly as each would when commanded alone (no joint slows to arrive with another)."""
    targets = dict(FAR, left_s0=0.1)
    together = follow(enabled_model(), mode, targets, 0.0, seconds)
    arrived = next(i for i, (_, p) in enumerate(together) if abs(p['left_s0'] - 0.1) < 1e-6)
    assert together[-1][0] - together[arrived][0] > 0.1
    cap = (DEFAULT_SPEED_RATIO if mode == POSITION_MODE else 1.0) * DT
    for name in LEFT:
        alone = follow(enabled_model(), mode, {name: targets[name]}, 0.0, seconds)
        assert [p[name] for _, p in alone] == [p[name] for _, p in together], name
        if name != 'left_s0':   # still on its way at its own cap after s0 arrived
            moves = steps(together[arrived:], name)
            assert [abs(m) for m in moves] == pytest.approx(
                [cap * LIMITS[name].velocity] * len(moves)), name


def timed_out(arm, t, last_command_s):
    """Return whether the arm holds at t: mode 4 with commands older than the timeout (mode 1
    has no timeout)."""
    return arm.mode == RAW_POSITION_MODE and t >= last_command_s + DEFAULT_COMMAND_TIMEOUT_S


def random_sequence_holds_the_hull(seed):
    """Run a seeded random command sequence, checking every joint after every move (up to a
    command's arrival, and each step). Return how many joint moves were checked."""
    rng = random.Random(seed)
    model = enabled_model(rng.choice([0.0, 0.05, 0.3, 1.0, rng.random()]))
    arm = model.arms['left']
    # A random start pose: mode 4 commands every 0.15 s (inside the timeout) for 4.5 s.
    start = {n: rng.uniform(LIMITS[n].lower, LIMITS[n].upper) for n in LEFT}
    t = 0.0
    while t < 4.5:
        model.joint_command('left', RAW_POSITION_MODE, LEFT, [start[n] for n in LEFT], t)
        last_command_s, t = t, t + 0.15
        model.step(t)
    assert arm.positions == pytest.approx(start, abs=1e-9)
    anchor, target = dict(arm.positions), dict(start)
    checked = 0

    def check(before, dt, mode, held):
        """Every joint moved from `before` over dt s in `mode` (held: all of dt past the
        timeout) within its hull, toward its target, within its cap."""
        nonlocal checked
        for name in LEFT:
            low, high = sorted((anchor[name], target[name]))
            position = arm.positions[name]
            assert low <= position <= high, (seed, name, low, position, high)
            assert abs(position - target[name]) <= abs(before[name] - target[name]), (seed, name)
            ratio = 1.0 if mode == RAW_POSITION_MODE else arm.speed_ratio
            cap = ratio * LIMITS[name].velocity * dt
            assert abs(position - before[name]) <= cap * (1 + 1e-9) + 1e-15, (seed, name)
            assert not held or position == before[name], (seed, name)   # timed out: holds
            checked += 1

    for _ in range(150):
        if rng.random() < 0.6:   # a command arrives between two steps, naming some joints
            names = rng.sample(LEFT, rng.randint(1, 7))
            values = [rng.uniform(LIMITS[n].lower - 1.0, LIMITS[n].upper + 1.0) for n in names]
            before, mode, dt = dict(arm.positions), arm.mode, rng.uniform(0.0, 0.02)
            held = timed_out(arm, t, last_command_s)
            t += dt
            model.joint_command('left', rng.choice([POSITION_MODE, RAW_POSITION_MODE]), names,
                                values, t)
            check(before, dt, mode, held)   # it moved toward the old targets until then
            for name, value in zip(names, values):   # where it was when its target came
                anchor[name] = arm.positions[name]
                target[name] = min(LIMITS[name].upper, max(LIMITS[name].lower, value))
            last_command_s = t
        if rng.random() < 0.1:
            model.set_speed_ratio('left', rng.choice([0.0, 1.0, rng.random()]))
        before, held = dict(arm.positions), timed_out(arm, t, last_command_s)
        dt = rng.choice([0.001, 0.01, 0.01, 0.03, DEFAULT_COMMAND_TIMEOUT_S, rng.uniform(0, 0.5)])
        t += dt
        model.step(t)
        check(before, dt, arm.mode, held)
    return checked


def test_every_joint_stays_between_where_its_target_came_and_the_target():
    """Seeded property test: random start poses, targets (also beyond the limits), subsets of
    joints, modes 1 and 4, speed ratios (0 too), step lengths (past the timeout too) and
    commands arriving mid-motion between steps. At every step every joint lies within the hull
    of its position when its current target came and that target, never moves away from the
    target, moves at most at its cap, and in mode 4 holds once commands are older than the
    timeout."""
    assert sum(random_sequence_holds_the_hull(seed) for seed in range(120)) > 100000


def test_mode_1_has_no_command_timeout_it_goes_on_to_its_last_target():
    """As a real Baxter, which finishes the move of tuck_arms.py -t after its last command
    (docs/baxter_sim.md, "How the arms move")."""
    model = enabled_model(1.0)
    model.joint_command('left', POSITION_MODE, list(FAR), list(FAR.values()), 0.0)
    arm, t, trace = model.arms['left'], 0.0, []
    while t < 5.0:   # one command only, then none: far past the timeout
        t = round(t + DT, 9)
        model.step(t)
        trace.append(dict(arm.positions))
    for name in LEFT:
        assert trace[-1][name] == FAR[name], name   # on the target, not creeping toward it
        assert trace[-100][name] == FAR[name], name  # and still for the last second
        assert arm.velocities[name] == 0.0
        moves = [abs(b[name] - a[name]) for a, b in zip(trace, trace[1:])]
        assert max(moves) <= LIMITS[name].velocity * DT * (1 + 1e-9), name


def test_mode_4_on_the_command_timeout_the_arm_stops_where_it_is_and_does_not_finish():
    mode = RAW_POSITION_MODE
    model = enabled_model(1.0)
    model.joint_command('left', mode, list(FAR), list(FAR.values()), 0.0)
    arm, t, trace = model.arms['left'], 0.0, []
    while t < 3.0:   # no further command: far longer than any joint needs to arrive
        t = round(t + DT, 9)
        model.step(t)
        trace.append(dict(arm.positions))
    at_timeout = trace[int(round(DEFAULT_COMMAND_TIMEOUT_S / DT)) - 1]
    for name in LEFT:
        assert abs(at_timeout[name] - NEUTRAL[name]) > 0.1, name         # it was moving ...
        assert abs(at_timeout[name] - FAR[name]) > 0.5, name             # ... far from there
        assert trace[-1][name] == at_timeout[name], name                 # and stopped there
        assert arm.velocities[name] == 0.0
        assert abs(at_timeout[name] - NEUTRAL[name]) == pytest.approx(   # at the velocity
            LIMITS[name].velocity * DEFAULT_COMMAND_TIMEOUT_S), name     # limit for the timeout
    # The hold lasts: a later step of any length moves nothing; a fresh command moves again.
    model.step(10.0)
    assert arm.positions == trace[-1]
    model.joint_command('left', mode, list(FAR), list(FAR.values()), 10.0)
    model.step(10.01)
    assert all(arm.positions[n] != trace[-1][n] for n in LEFT)


def test_commands_slower_than_the_timeout_move_in_bursts():
    """Commands every 0.25 s (timeout 0.2 s): the arm moves 0.2 s, holds 0.05 s, and so on."""
    model = enabled_model()
    arm, t, moved = model.arms['left'], 0.0, []
    for _ in range(4):
        model.joint_command('left', RAW_POSITION_MODE, ['left_s0'], [FAR['left_s0']], t)
        for _ in range(25):
            before = arm.positions['left_s0']
            t = round(t + DT, 9)
            model.step(t)
            moved.append(arm.positions['left_s0'] != before)
    assert moved == ([True] * 20 + [False] * 5) * 4


@pytest.mark.parametrize('mode', [POSITION_MODE, RAW_POSITION_MODE])
def test_targets_beyond_the_joint_limits_stop_at_the_limit(mode):
    model = enabled_model(1.0)
    for end, beyond in (('upper', 10.0), ('lower', -1e9)):
        trace = follow(model, mode, {n: beyond for n in LEFT}, 0.0 if end == 'upper' else 5.0,
                       5.0 if end == 'upper' else 10.0)
        for name in LEFT:
            assert all(LIMITS[name].lower <= p[name] <= LIMITS[name].upper for _, p in trace)
            assert trace[-1][1][name] == pytest.approx(getattr(LIMITS[name], end), abs=1e-9)
