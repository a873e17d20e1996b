"""Unit tests of where a Baxter arm can be until its next command takes effect (arm_reach)."""
import numpy as np

from robopuppet.arm import arm_reach

POSE = np.array([0.1, -0.5, 0.0, 1.0, 0.0, 0.8, 0.0])
DELAY = arm_reach.COMMAND_DELAY_S


def test_the_box_holds_the_pose_the_target_in_force_and_every_command_since():
    reach = arm_reach.ArmReach()
    old, in_force, newer = POSE - 0.3, POSE + 0.1, POSE - 0.05
    reach.sent(0.90, old)                # replaced before the measurement: not in the box
    reach.sent(1.00 - DELAY, in_force)   # the newest sent by t_m - delay: in force at t_m
    reach.sent(1.00, newer)              # sent since: on its way
    lo, hi = reach.where(1.01, 1.00, POSE)
    np.testing.assert_allclose(lo, POSE - 0.05)
    np.testing.assert_allclose(hi, POSE + 0.1)


def test_a_command_sent_within_the_delay_before_the_measurement_counts():
    reach = arm_reach.ArmReach()
    reach.sent(0.5, POSE)
    reach.sent(1.0 - DELAY / 2, POSE + 0.2)   # may not have reached Baxter by t_m
    reach.sent(1.0 - DELAY / 3, POSE + 0.1)
    lo, hi = reach.where(1.0, 1.0, POSE)
    np.testing.assert_allclose((lo, hi), (POSE, POSE + 0.2))


def test_without_commands_of_ours_the_measured_velocity_extends_the_pose():
    reach = arm_reach.ArmReach()
    speeds = np.array([0.5, -0.5, 0, 0, 0, 0, 1.0])
    lo, hi = reach.where(1.02, 1.0, POSE, speeds)   # 0.02 s old, plus the command's delay
    extra = speeds * (0.02 + DELAY)
    np.testing.assert_allclose(lo, np.minimum(POSE, POSE + extra))
    np.testing.assert_allclose(hi, np.maximum(POSE, POSE + extra))
    reach.sent(0.0, POSE + 1.0)   # long before the window, more than HISTORY_S before now:
    reach.sent(arm_reach.HISTORY_S + 0.5, POSE)   # forgotten
    lo, hi = reach.where(arm_reach.HISTORY_S + 0.6, arm_reach.HISTORY_S + 0.6, POSE)
    np.testing.assert_allclose((lo, hi), (POSE, POSE))


def test_inside_moves_a_pose_into_the_last_box():
    reach = arm_reach.ArmReach()
    assert reach.inside(list(POSE + 5)) == list(POSE + 5)   # no box yet: as it is
    reach.sent(1.0, POSE + 0.1)
    reach.where(1.0, 1.0, POSE)
    inside = reach.inside(POSE + np.array([0.5, -0.5, 0.05, 0, 0, 0, 0]))
    np.testing.assert_allclose(inside, POSE + np.array([0.1, 0.0, 0.05, 0, 0, 0, 0]))


def test_a_pose_older_than_the_commands_remembered_gives_no_box():
    reach = arm_reach.ArmReach()
    for k in range(300):   # 3 s of commands at 100 Hz: the first second is forgotten
        reach.sent(k * 0.01, POSE + k * 0.001)
    assert reach.where(3.0, 3.0 - arm_reach.HISTORY_S - 0.1, POSE) is None
    assert reach.where(3.0, 3.0 - arm_reach.HISTORY_S + 0.1, POSE) is not None
