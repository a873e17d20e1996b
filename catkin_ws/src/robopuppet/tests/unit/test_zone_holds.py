"""robopuppet.arm.zone_holds: following arms' commands cut at keep-out zones, and who holds whom."""
import pytest

from robopuppet import baxter_description
from robopuppet.arm import arm_reach
from robopuppet.arm.baxter_watch import BaxterWatch
from robopuppet.arm.zone_holds import POSE_TOO_OLD, ZONE_HELD, ZoneHolds
from robopuppet.world.zones import Hit

LIMITS = {side: baxter_description.arm_limits(side) for side in ('left', 'right')}
POSE = [0.0, -0.5, 0.0, 0.8, 0.0, 1.0, 0.0]
AHEAD = [0.2] + POSE[1:]


class Wall:
    """A stand-in for world.zones.ZoneGuard: records the boxes; while `blocking`, cuts every
    motion at its start with a hit of zone 'bed' at link right_hand."""

    def __init__(self):
        self.blocking, self.boxes = False, []

    def limit_box(self, lo, hi, before, command):
        self.boxes.append((list(lo), list(hi)))
        if self.blocking:
            return list(before), Hit('bed', 'right_hand')
        return list(command), None


def holds(measured_t=1.0):
    robot = BaxterWatch(LIMITS)
    robot.on_robot_pose(measured_t, {'left': POSE, 'right': POSE})
    wall = Wall()
    return ZoneHolds({'right': wall}, robot), wall


def test_an_arm_no_zone_binds_is_never_cut():
    zones, _ = holds()
    assert zones.cut('left', 1.0, POSE, [9.0] * 7) == [9.0] * 7
    assert zones.stay('left', 1.0, [9.0] * 7) == [9.0] * 7
    assert not zones.holding() and zones.detail() == ''


def test_the_guard_gets_the_box_from_the_measured_pose_to_the_command_and_its_cut_holds():
    zones, wall = holds()
    assert zones.cut('right', 1.01, POSE, AHEAD) == AHEAD
    lo, hi = wall.boxes[-1]
    assert (lo[0], hi[0]) == (0.0, 0.0)   # the box holds where the arm can be before the command
    wall.blocking = True
    assert zones.cut('right', 1.02, AHEAD, [0.4] + POSE[1:]) == AHEAD
    assert wall.boxes[-1][1][0] == pytest.approx(0.2)   # the previous command is in the box
    assert zones.holding() and zones.zone('right') == 'bed' and zones.zone('left') == ''
    assert zones.detail() == ZONE_HELD % ('bed', 'right_hand')


def test_a_command_that_goes_out_uncut_ends_the_hold():
    zones, wall = holds()
    wall.blocking = True
    zones.cut('right', 1.01, POSE, AHEAD)
    wall.blocking = False
    zones.cut('right', 1.02, POSE, AHEAD)
    assert not zones.holding() and zones.zone('right') == ''


def test_a_pose_older_than_the_commands_remembered_holds_the_arm_at_its_last_command():
    zones, wall = holds(measured_t=1.0)
    zones.cut('right', 1.01, POSE, AHEAD)
    zones.cut('right', 1.02, AHEAD, AHEAD)
    late_t = 1.0 + arm_reach.HISTORY_S + 1.0   # Baxter's pose stopped coming: 1.01 forgotten
    zones.cut('right', late_t, AHEAD, AHEAD)
    boxes = len(wall.boxes)
    assert zones.cut('right', late_t + 0.01, AHEAD, [0.5] + POSE[1:]) == AHEAD
    assert len(wall.boxes) == boxes   # nothing to prove a motion with: the guard is not asked
    assert zones.detail() == POSE_TOO_OLD.link and zones.zone('right') == ''


def test_the_hits_of_arms_that_stop_following_are_forgotten():
    zones, wall = holds()
    wall.blocking = True
    zones.cut('right', 1.01, POSE, AHEAD)
    zones.forget({'left': True, 'right': True})
    assert zones.zone('right') == 'bed'
    zones.forget({'left': True, 'right': False})
    assert not zones.holding()


def test_a_stay_command_is_moved_into_the_box_where_the_arm_can_be():
    zones, _ = holds()
    zones.cut('right', 1.01, POSE, AHEAD)
    zones.cut('right', 1.02, AHEAD, AHEAD)   # the arm can be between 0.0 and 0.2 on joint 0
    assert zones.stay('right', 1.02, [0.5] + POSE[1:])[0] == pytest.approx(0.2)
    assert zones.stay('right', 1.03, [-0.5] + POSE[1:])[0] == pytest.approx(0.0)
