"""Tests of robopuppet.baxter_sim.baxter_contact in the model: an arm driven into a table stops
at contact (every capsule outside the table at every step, by a brute-force check), blocked
joints press with a bounded torque that grows with the command's distance past contact, a
motion away or along the table is free, and no obstacles leave the model as it was."""
import os

import numpy as np
import pytest

from robopuppet import baxter_description as bd
from robopuppet.baxter_sim import baxter_contact
from robopuppet.baxter_sim.baxter_joint_command import (POSITION_MODE, RAW_POSITION_MODE,
                                                        TORQUE_MODE, VELOCITY_MODE)
from robopuppet.baxter_sim.baxter_model import BaxterModel
from robopuppet.world import obstacles
from robopuppet.world.arm_capsules import ArmCapsules

TABLE_FILE = os.path.join(os.path.dirname(__file__), '..', 'integration', 'fixtures',
                          'table.yaml')
TABLE = obstacles.load_obstacles(TABLE_FILE)
URDF = open(bd.URDF_PATH).read()
DESC = bd.Description(URDF)
RIGHT = bd.arm_joint_names('right')
S1 = 'right_s1'          # s1 positive lowers the arm onto the table
S1_EFFORT_N_M = 100.0    # the URDF's (Rethink's) effort limit of s1
DT = 0.01


def brute_force_clearance(capsules, angles, table, samples=400):
    """Least clearance (m) of the arm's capsules from a box without rotation, sampling points
    along each segment: at least the true clearance, never less."""
    centre = np.array(table.xyz)
    half = np.array(table.size) / 2.0
    segments = capsules.segments(np.array([angles]))[0]            # (C, 3, 2)
    s = np.linspace(0.0, 1.0, samples)
    points = segments[:, :, :1] + (segments[:, :, 1:] - segments[:, :, :1]) * s   # (C, 3, S)
    local = np.abs(points - centre[:, None]) - half[:, None]
    outside = np.linalg.norm(np.maximum(local, 0.0), axis=1)
    inside = np.minimum(local.max(axis=1), 0.0)
    return ((outside + inside).min(axis=1) - capsules.radii).min()


def table_model():
    model = BaxterModel(DESC, 0.0, contacts=baxter_contact.arm_contacts(DESC, URDF, TABLE))
    model.set_enabled(True)
    return model


def drive(model, start_s, duration_s, mode, targets, check=None):
    """Send the right arm `targets` {joint: value} every step for duration_s; return the time."""
    t = start_s
    for _ in range(int(round(duration_s / DT))):
        model.joint_command('right', mode, list(targets), list(targets.values()), t)
        t = round(t + DT, 9)
        model.step(t)
        if check:
            check(model)
    return t


def effort(model, name):
    names, _, _, efforts = model.joint_state()
    return efforts[names.index(name)]


def angles(model):
    return [model.arms['right'].positions[n] for n in RIGHT]


@pytest.mark.parametrize('mode', [POSITION_MODE, RAW_POSITION_MODE])
def test_an_arm_driven_into_the_table_stops_at_contact_and_presses(mode):
    model = table_model()
    capsules = ArmCapsules(DESC, URDF, 'right')
    clearances = []
    t = drive(model, 0.0, 1.5, mode, {S1: 0.6},
              lambda m: clearances.append(brute_force_clearance(capsules, angles(m), TABLE[0])))
    assert min(clearances) > 0.0                  # never inside, at any step
    assert clearances[-1] < 0.005   # ... but it got there: the guard stops 2-4 mm short
    stopped = model.arms['right'].positions[S1]
    assert stopped < 0.6 - 0.5
    drive(model, t, 0.2, mode, {S1: 0.6})
    assert model.arms['right'].positions[S1] == stopped    # held at contact
    assert model.arms['right'].velocities[S1] == 0.0
    assert effort(model, S1) == S1_EFFORT_N_M               # far past contact: saturated
    # The other joints were not commanded: they do not press.
    assert all(effort(model, n) == 0.0 for n in RIGHT if n != S1)


def test_the_press_grows_with_the_command_past_contact_and_is_bounded():
    model = table_model()
    t = drive(model, 0.0, 1.5, RAW_POSITION_MODE, {S1: 0.6})
    contact = model.arms['right'].positions[S1]
    pressed = []
    for past in (0.01, 0.05, 0.1, 0.2, 0.3, 1.0):
        t = drive(model, t, 0.05, RAW_POSITION_MODE, {S1: contact + past})
        assert model.arms['right'].positions[S1] == contact
        pressed.append(effort(model, S1))
    assert all(0.0 < a < b for a, b in zip(pressed, pressed[1:4]))
    assert pressed[0] == pytest.approx(0.01 / baxter_contact.SATURATION_RAD * S1_EFFORT_N_M,
                                       rel=0.05)
    assert pressed[4:] == [S1_EFFORT_N_M, S1_EFFORT_N_M]


def test_a_command_away_from_the_table_moves_freely_and_the_press_ends():
    model = table_model()
    t = drive(model, 0.0, 1.5, RAW_POSITION_MODE, {S1: 0.6})
    contact = model.arms['right'].positions[S1]
    t = drive(model, t, 0.01, RAW_POSITION_MODE, {S1: contact - 0.3})
    assert effort(model, S1) == 0.0
    assert model.arms['right'].positions[S1] == pytest.approx(contact - 1.5 * DT)  # full speed
    drive(model, t, 0.5, RAW_POSITION_MODE, {S1: contact - 0.3})
    assert model.arms['right'].positions[S1] == pytest.approx(contact - 0.3)


def test_joints_whose_motion_stays_clear_move_on_while_others_are_blocked():
    # At contact on the table top, s0 turns the arm about a vertical axis, along the table.
    model = table_model()
    t = drive(model, 0.0, 1.5, RAW_POSITION_MODE, {S1: 0.6})
    contact = model.arms['right'].positions[S1]
    drive(model, t, 0.5, RAW_POSITION_MODE, {'right_s0': 0.2, S1: 0.6})
    assert model.arms['right'].positions['right_s0'] == pytest.approx(0.2)
    assert model.arms['right'].positions[S1] == pytest.approx(contact, abs=0.01)
    assert effort(model, 'right_s0') == 0.0 and effort(model, S1) == S1_EFFORT_N_M


@pytest.mark.parametrize('mode, value, pressed', [
    (TORQUE_MODE, 40.0, 40.0),                 # the commanded torque, as in free motion
    (VELOCITY_MODE, 0.75, 0.75 / 1.5 * 100.0),   # the torque that speed stands for
])
def test_speed_and_torque_modes_stop_at_contact_too(mode, value, pressed):
    model = table_model()
    t = drive(model, 0.0, 1.5, mode, {S1: value})
    stopped = model.arms['right'].positions[S1]
    drive(model, t, 0.1, mode, {S1: value})
    assert model.arms['right'].positions[S1] == stopped < 0.0
    assert effort(model, S1) == pytest.approx(pressed)


def test_the_left_arm_and_free_motion_report_no_press():
    model = table_model()
    drive(model, 0.0, 0.1, RAW_POSITION_MODE, {S1: -0.6})     # up, away from the table
    names, _, _, efforts = model.joint_state()
    assert efforts == [0.0] * len(names)


def test_without_obstacles_the_model_is_unchanged():
    assert baxter_contact.arm_contacts(DESC, URDF, []) == {}
    free, plain = BaxterModel(DESC, 0.0, contacts={}), BaxterModel(DESC, 0.0)
    for model in (free, plain):
        model.set_enabled(True)
        drive(model, 0.0, 4.0, POSITION_MODE, {S1: 0.6, 'right_e1': 0.1})
    assert free.joint_state() == plain.joint_state()
    assert plain.arms['right'].positions[S1] == pytest.approx(0.6)   # through the table
