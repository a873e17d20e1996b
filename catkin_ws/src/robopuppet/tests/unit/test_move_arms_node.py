"""Unit tests of move_arms: its arguments, and its replay bringing the arms to the pose slowly,
shoulder up first, clear of a zone the straight way enters, ending there, and not stopped by a
study device that shows Baxter's pose."""
import math

import numpy as np
import pytest

from robopuppet import baxter_description
from robopuppet.arm import zone_topics
from robopuppet.episodes import move_arms_node as move_arms, replay
from robopuppet.interface import BAXTER_SIDES

LIMITS = {side: baxter_description.arm_limits(side) for side in BAXTER_SIDES}
PERIOD_S = 0.01


def test_angles_and_arms_are_parsed_and_bad_ones_refused():
    assert move_arms.parse_angles('0,-0.55, 0 0.75 0 1.26 0') == move_arms.NEUTRAL
    for bad in ('1,2,3', '1,2,3,4,5,6,7,8', '0,0,0,nan,0,0,0', '0,0,0,x,0,0,0', ''):
        with pytest.raises(ValueError, match='--angles'):
            move_arms.parse_angles(bad)
    assert move_arms.parse_arms('right left') == ('left', 'right')
    assert move_arms.parse_arms('right') == ('right',)
    for bad in ('', 'head', 'left,torso'):
        with pytest.raises(ValueError, match='--arms'):
            move_arms.parse_arms(bad)


HERE = {'left': [0.6, -0.2, -0.5, 1.4, 0.3, 0.4, -0.8],
        'right': [-0.6, 0.1, 0.5, 1.9, -0.3, 0.2, 0.9]}
# a pose over the patient whose straight way to neutral sweeps a finger through its body
OVER_PATIENT = [-0.13, -0.13, -0.42, 1.02, -0.19, 0.88, 0.61]


def play(core, here, t_end=30.0):
    """Step the core from start() with a Baxter that goes where it is commanded and a study
    device that shows Baxter's pose; return (the last Step, {side: [commands]})."""
    core.on_robot_pose(0.0, here)
    core.on_puppet(0.0, 'R', here['right'])
    step, t, sent = core.start(0.0), 0.0, {side: [list(a)] for side, a in here.items()}
    while step.phase in (replay.APPROACH, replay.PLAY) and t < t_end:
        for side, command in step.commands.items():
            sent[side].append(command)
        core.on_robot_pose(t, step.commands)
        core.on_puppet(t, 'R', step.commands['right'])
        t += PERIOD_S
        step = core.step(t)
    return step, sent


def test_the_arms_go_slowly_shoulder_up_first_to_neutral_and_it_finishes_there():
    paths, grips = move_arms.lifted_script(HERE, move_arms.NEUTRAL, LIMITS)
    core = replay.Replay(paths, grips, LIMITS, 1.0, PERIOD_S, puppet_moved_rad=math.inf)
    step, sent = play(core, HERE)
    assert step.phase == replay.FINISHED, core.why
    for side, commands in sent.items():
        commands = np.array(commands)
        assert commands[-1] == pytest.approx(move_arms.NEUTRAL)
        assert np.abs(np.diff(commands, axis=0)).max() <= (
            replay.APPROACH_SPEED_RAD_S * PERIOD_S * 1.01)       # slow, no jump
        shoulder = commands[:, move_arms.SHOULDER]
        top = int(np.argmin(shoulder))                           # s1: negative is up
        assert shoulder[top] == pytest.approx(
            min(HERE[side][1], move_arms.NEUTRAL[1]) - move_arms.LIFT_RAD)
        others = np.delete(commands, move_arms.SHOULDER, axis=1)
        assert others[top] == pytest.approx(np.delete(HERE[side], move_arms.SHOULDER))
        assert np.all(np.diff(shoulder[:top + 1]) <= 1e-12)     # up first, nothing else
        assert np.all(np.diff(shoulder[np.argmax(np.all(np.isclose(
            others, others[-1]), axis=1)):]) >= -1e-12)         # down last


def test_the_lifted_way_keeps_out_of_the_zone_the_straight_way_would_enter():
    guards, _ = zone_topics.load_guards(zone_topics.package_zones_file())
    straight_out, hit = guards['right'].limit(np.array(OVER_PATIENT), np.array(move_arms.NEUTRAL))
    assert hit is not None and hit.zone == 'patient body'
    here = {'right': OVER_PATIENT}
    paths, grips = move_arms.lifted_script(here, move_arms.NEUTRAL, LIMITS)
    core = replay.Replay(paths, grips, LIMITS, 1.0, PERIOD_S, puppet_moved_rad=math.inf,
                         guards={'right': guards['right']})
    step, sent = play(core, here)
    assert step.phase == replay.FINISHED, core.why
    assert sent['right'][-1] == pytest.approx(move_arms.NEUTRAL)


def test_a_puppet_that_starts_following_stops_it():
    paths, grips = move_arms.lifted_script({'right': [0.5] * 7}, move_arms.NEUTRAL, LIMITS)
    core = replay.Replay(paths, grips, LIMITS, 1.0, PERIOD_S, puppet_moved_rad=math.inf)
    core.on_robot_pose(0.0, {'right': [0.5] * 7})
    core.start(0.0)
    core.on_following(0.1, True)
    assert core.step(0.11).phase == replay.STOPPED and 'following' in core.why
