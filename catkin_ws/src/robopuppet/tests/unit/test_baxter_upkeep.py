"""Baxter's upkeep in arm_X: presence, enabling and gripper calibration (pure, time passed in)."""
import json

import pytest
from baxter_core_msgs.msg import EndEffectorCommand, EndEffectorState

from robopuppet.arm import baxter_upkeep
from robopuppet.arm.baxter_upkeep import BaxterUpkeep

GRIPPER_ID = 65538  # an electric gripper's id on Baxter


def present(t=0.0, enabled=True, stopped=False, error=False):
    """Return a BaxterUpkeep that got /robot/state and joint states at time t."""
    upkeep = BaxterUpkeep()
    upkeep.on_robot_state(t, enabled, stopped, error)
    upkeep.on_robot_joints(t)
    return upkeep


def test_baxter_is_ready_only_while_enabled_and_both_its_topics_are_fresh():
    assert present().ready(0.5)
    assert not present().ready(1.0)  # both older than a second: gone
    assert not BaxterUpkeep().ready(0.0)
    only_state = BaxterUpkeep()
    only_state.on_robot_state(0.0, True, False, False)
    assert not only_state.ready(0.1)  # no joint states: it cannot be followed
    stale_joints = present()
    stale_joints.on_robot_state(0.9, True, False, False)
    assert stale_joints.ready(0.95) and not stale_joints.ready(1.05)


@pytest.mark.parametrize('flags', [dict(enabled=False), dict(stopped=True), dict(error=True)])
def test_a_disabled_stopped_or_failed_baxter_is_not_ready(flags):
    assert not present(**flags).ready(0.1)


def test_enabling_is_asked_for_at_once_then_once_a_second_while_baxter_is_not_ready():
    upkeep = BaxterUpkeep()
    asked = [t / 100 for t in range(0, 350, 5) if upkeep.enable_due(t / 100)]
    assert asked == [0.0, 1.05, 2.1, 3.15]


def test_a_ready_baxter_is_not_asked_to_enable():
    upkeep = present(0.0)
    assert not upkeep.enable_due(0.5)
    assert upkeep.enable_due(1.5)  # gone since 1.0 s


def calibrations(upkeep, states, side='right'):
    """Feed gripper states (t, calibrated, holding); return the times a calibrate went out."""
    sent = []
    for t, calibrated, holding in states:
        command = upkeep.on_gripper_state(t, side, GRIPPER_ID, calibrated, holding)
        if command:
            assert command.command == baxter_upkeep.CMD_CALIBRATE and command.side == side
            sent.append(t)
    return sent


def test_an_uncalibrated_gripper_is_calibrated_and_asked_again_every_3_s_until_it_is():
    upkeep = BaxterUpkeep()
    states = [(t / 10, False, False) for t in range(0, 75)]
    assert calibrations(upkeep, states) == [0.0, 3.1, 6.2]
    assert calibrations(upkeep, [(7.5, True, False), (20.0, False, False)]) == []


def test_a_gripper_seen_calibrated_once_is_never_calibrated_again():
    upkeep = BaxterUpkeep()
    assert calibrations(upkeep, [(0.0, True, False)] + [(t, False, False) for t in range(1, 20)]
                        ) == []


def test_a_gripper_that_holds_what_the_puppet_closed_it_on_is_not_calibrated():
    upkeep = BaxterUpkeep()
    assert calibrations(upkeep, [(t / 10, False, True) for t in range(50)]) == []
    assert calibrations(upkeep, [(5.0, False, False)]) == [5.0]


def test_no_calibrate_without_a_gripper_and_each_side_on_its_own():
    upkeep = BaxterUpkeep()
    assert upkeep.on_gripper_state(0.0, 'left', 0, False, False) is None  # id 0: no gripper
    assert calibrations(upkeep, [(0.1, False, False)], side='left') == [0.1]
    assert calibrations(upkeep, [(0.2, False, False)], side='right') == [0.2]


def test_gripper_commands_carry_the_id_from_the_state_and_a_rising_sequence():
    upkeep = BaxterUpkeep()
    assert upkeep.grip('left', True).id == 0  # no state yet: Baxter ignores it
    upkeep.on_gripper_state(0.0, 'left', GRIPPER_ID, True, False)
    close, release = upkeep.grip('left', True), upkeep.grip('left', False)
    assert (close.id, close.command) == (GRIPPER_ID, EndEffectorCommand.CMD_GO)
    assert json.loads(close.args) == {'position': EndEffectorState.POSITION_CLOSED}
    assert json.loads(release.args) == {'position': EndEffectorState.POSITION_OPEN}
    assert release.sequence == close.sequence + 1


def test_the_gripper_api_names_are_baxters():
    assert baxter_upkeep.CMD_CALIBRATE == EndEffectorCommand.CMD_CALIBRATE
    assert baxter_upkeep.CMD_GO == EndEffectorCommand.CMD_GO
