"""robopuppet.arm.leash and its use in arm_drive.ArmDrive: no command leads Baxter's measured
pose by more than leash_s of each joint's mode-1 travel, the speed rule still holds for the
commands sent, a following arm still reaches its target, and the zone cut comes after it."""
import numpy as np
import pytest

from robopuppet import baxter_description as bd, interface
from robopuppet.arm import arm_drive, leash
from robopuppet.arm.baxter_watch import BaxterWatch
from robopuppet.arm.zone_holds import ZoneHolds

LIMITS = {side: bd.arm_limits(side) for side in interface.BAXTER_SIDES}
RIGHT = LIMITS['right']
VELOCITY = np.array([lim.velocity for lim in RIGHT])
MODE1 = leash.MODE1_SPEED_RATIO * VELOCITY
START = [0.0, -0.5, 0.0, 1.0, 0.0, 0.5, 0.0]
FAR = [0.8, 0.3, 1.0, 2.0, -1.5, 1.5, 2.0]    # 0.8-2 rad from START on every joint
PERIOD_S, LAG_S = 0.01, 0.05                   # arm_X's command period; the stand-in's lag


class LaggingArm:
    """Baxter's arm in mode 1 as the stand-in models it: each joint a first-order lag (LAG_S)
    toward its command, at most at its mode-1 speed; held back (stuck) when told."""

    def __init__(self, pose):
        self.pose, self.velocity, self.stuck = np.array(pose, float), np.zeros(7), False

    def step(self, command, dt):
        rate = np.clip((np.array(command) - self.pose) / LAG_S, -MODE1, MODE1)
        self.velocity = np.zeros(7) if self.stuck else rate
        self.pose = self.pose + self.velocity * dt


def drive(leash_s, zones=None):
    """Return (ArmDrive of the right arm started at START, its BaxterWatch)."""
    robot = BaxterWatch(LIMITS)
    robot.on_robot_pose(0.0, {'right': START})
    drv = arm_drive.ArmDrive(LIMITS, robot, zones or ZoneHolds(None, robot), 0.5, 0.02,
                             PERIOD_S, leash_s)
    drv.start('right', 0.0)
    return drv, robot


def follow(drv, robot, target, seconds, arm=None, report=True, t0=0.0, jitter=None):
    """Command the right arm toward target (7 rad or a function of t) every PERIOD_S (jittered
    by up to `jitter` s) for `seconds`, Baxter being `arm` (a LaggingArm, 1 ms steps; default:
    standing at START), its pose reported 10 ms late while `report`; return (times, commands,
    the arm's poses at each command)."""
    arm = arm or LaggingArm(START)
    rng = np.random.default_rng(7)
    times, commands, poses, history = [], [], [], [(t0, arm.pose, arm.velocity)]
    command, t, next_t = list(arm.pose), t0, t0
    while t < t0 + seconds:
        t += 0.001
        arm.step(command, 0.001)
        history.append((t, arm.pose, arm.velocity))
        if t + 1e-9 < next_t:
            continue
        next_t = t + PERIOD_S + (rng.uniform(-jitter, jitter) if jitter else 0.0)
        if report:
            measured_t, pose, speeds = history[-min(11, len(history))]
            robot.on_robot_pose(measured_t, {'right': list(pose)}, {'right': list(speeds)})
        goal = target(t) if callable(target) else target
        command = drv.toward('right', t, goal)
        times.append(t), commands.append(command), poses.append(arm.pose)
    return np.array(times), np.array(commands), np.array(poses)


def assert_speed_rule(times, commands):
    """Over any T s between two commands each joint moved at most its limit x (T + 10 ms)."""
    for i in range(len(times) - 1):
        moved = np.abs(commands[i + 1:] - commands[i])
        allowed = (times[i + 1:] - times[i] + PERIOD_S)[:, None] * VELOCITY
        assert (moved <= allowed + 1e-9).all(), 'after command %d' % i


# ---- the pure rule ---------------------------------------------------------------------------

def test_each_joint_is_kept_within_its_own_share_of_mode_1_travel():
    reach = leash.leash_rad(RIGHT, 0.1)
    np.testing.assert_allclose(reach, 0.1 * 0.3 * VELOCITY)
    assert reach[0] == pytest.approx(0.045) and reach[6] == pytest.approx(0.12)  # s0, w2
    pose = [0.1] * 7
    up = leash.leashed([3.0] * 7, pose, RIGHT, 0.1)
    down = leash.leashed([-3.0] * 7, pose, RIGHT, 0.1)
    np.testing.assert_allclose(up, np.add(pose, reach))
    np.testing.assert_allclose(down, np.subtract(pose, reach))
    near = [0.1, 0.12, 0.06, 0.1, 0.2, 0.0, 0.15]   # within the leash: as it is
    assert leash.leashed(near, pose, RIGHT, 0.1) == near


@pytest.mark.parametrize('leash_s, pose', [(0.0, [0.1] * 7), (0.1, None)])
def test_no_leash_when_off_or_baxter_s_pose_is_unknown(leash_s, pose):
    assert leash.leashed([3.0] * 7, pose, RIGHT, leash_s) == [3.0] * 7


# ---- in ArmDrive -------------------------------------------------------------------------------

def test_a_command_never_leads_a_baxter_that_does_not_move_by_more_than_the_leash():
    drv, robot = drive(0.1)
    arm = LaggingArm(START)
    arm.stuck = True   # held (an obstacle, a stiff joint): its pose stays START
    times, commands, _ = follow(drv, robot, FAR, 2.0, arm)
    lead = np.abs(commands - START)
    assert (lead <= np.array(leash.leash_rad(RIGHT, 0.1)) + 1e-9).all()
    np.testing.assert_allclose(lead[-1], leash.leash_rad(RIGHT, 0.1))
    assert_speed_rule(times, commands)
    _, unleashed, _ = follow(*drive(0.0), FAR, 2.0, LaggingArm(START))   # without: far ahead
    assert np.abs(unleashed[-1] - START).max() > 1.0


def test_a_stale_pose_keeps_the_arm_within_the_leash_of_where_baxter_was_last_known():
    drv, robot = drive(0.1)
    arm = LaggingArm(START)
    t = follow(drv, robot, FAR, 0.5, arm)[0][-1]          # moving fast toward FAR
    last = robot.now('right', t + 1.0)                    # no pose comes any more
    times, commands, poses = follow(drv, robot, FAR, 2.0, arm, report=False, t0=t)
    assert np.abs(commands[-1] - last).max() > 0.04   # it went to the end of the leash ...
    settled = commands[times > t + 0.05]   # BaxterWatch.now extrapolates for 0.05 s at most
    assert (np.abs(settled - last) <= np.array(leash.leash_rad(RIGHT, 0.1)) + 1e-9).all()
    assert np.abs(poses[-1] - commands[-1]).max() < 1e-3   # ... and Baxter stopped there
    assert_speed_rule(times, commands)


@pytest.mark.parametrize('leash_s', [0.0, 0.05, 0.1])
def test_the_speed_rule_holds_for_the_commands_sent_with_a_moving_baxter(leash_s):
    drv, robot = drive(leash_s)
    swing = np.subtract(FAR, START)
    times, commands, _ = follow(drv, robot, lambda t: list(START + swing * np.sin(3.0 * t)),
                                4.0, jitter=0.004)
    assert_speed_rule(times, commands)


def test_a_command_pulled_back_by_a_jump_of_baxter_s_pose_moves_no_faster_than_the_budget():
    drv, robot = drive(0.1)
    arm = LaggingArm(START)
    arm.stuck = True
    times, commands, _ = follow(drv, robot, FAR, 0.5, arm)   # at the end of the leash
    back = list(np.subtract(START, 0.4))                      # Baxter now reports 0.4 rad back
    t = times[-1]
    robot.on_robot_pose(t, {'right': back})
    later = [drv.toward('right', t + PERIOD_S * k, FAR) for k in range(1, 121)]
    times = np.append(times, t + PERIOD_S * np.arange(1, 121))
    commands = np.vstack([commands, later])
    assert_speed_rule(times, commands)   # pulled back within the budget, not in one jump
    reach = np.array(leash.leash_rad(RIGHT, 0.1))
    assert (np.abs(commands[-1] - back) <= reach + 1e-9).all()   # back on the leash (1.2 s)


@pytest.mark.parametrize('leash_s', [0.05, 0.1])
def test_a_following_arm_still_reaches_its_target_about_as_soon(leash_s):
    arrivals = {}
    for ls in (0.0, leash_s):
        drv, robot = drive(ls)
        times, commands, poses = follow(drv, robot, FAR, 6.0, LaggingArm(START))
        near = np.abs(poses - FAR).max(axis=1) < 0.01
        assert near[-1] and drv.tracking['right']
        np.testing.assert_allclose(commands[-1], FAR, atol=1e-9)
        arrivals[ls] = times[np.argmax(near)]
    assert arrivals[leash_s] <= arrivals[0.0] + 0.1


def test_a_following_arm_tracks_a_fast_puppet_about_as_closely():
    errors = {}
    swing = np.subtract(FAR, START)
    for ls in (0.0, 0.1):
        drv, robot = drive(ls)
        times, _, poses = follow(drv, robot, lambda t: list(START + swing * np.sin(2.0 * t)),
                                 6.0, LaggingArm(START))
        wanted = START + swing * np.sin(2.0 * times)[:, None]
        errors[ls] = np.abs(poses - wanted).max(axis=1)[times > 2.0]
    assert np.median(errors[0.1]) <= np.median(errors[0.0]) * 1.05 + 0.005


def test_the_zone_cut_sees_the_step_to_the_leashed_command_and_its_cut_is_sent():
    class HalfStep(ZoneHolds):
        """A zone that lets only half of each step through, recording what it was shown."""

        def cut(self, side, t, before, command):
            self.shown.append((list(before), list(command)))
            return list(np.add(before, np.subtract(command, before) / 2.0))

    robot_zones = HalfStep(None, None)
    robot_zones.shown = []
    drv, robot = drive(0.1, robot_zones)
    robot_zones.robot = robot
    arm = LaggingArm(START)
    arm.stuck = True
    _, commands, _ = follow(drv, robot, FAR, 0.5, arm)
    reach = np.array(leash.leash_rad(RIGHT, 0.1))
    for k, (before, shown) in enumerate(robot_zones.shown):
        assert (np.abs(np.subtract(shown, START)) <= reach + 1e-9).all()   # leashed first
        np.testing.assert_allclose(before, commands[k - 1] if k else START)  # from the last sent
    ahead = np.sign(np.subtract(FAR, START)) * reach
    np.testing.assert_allclose(commands[-1], np.add(START, ahead), atol=1e-3)
