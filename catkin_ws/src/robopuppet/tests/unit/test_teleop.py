"""Teleop state machine: every state under every input, mirroring, clamping, approach, watchdog."""
import math

import pytest

from robopuppet import baxter_description, interface
from robopuppet.arm import joint_motion, opmode, teleop, timing
from robopuppet.interface import (BAXTER_SIDES, BUTTON_OPMODE, BUTTON_LEFT, BUTTON_RIGHT,
                                  CALIBRATING, FAULT, FEEL, FOLLOWING, HOLD, LIMP, NO_ROBOT,
                                  READY)

WORKING = [interface.WORKING] * 7
ONE_UNCALIBRATED = WORKING[:2] + [interface.UNCALIBRATED] + WORKING[3:]
LIMITS = {side: baxter_description.arm_limits(side) for side in BAXTER_SIDES}
NEUTRAL = {side: [baxter_description.NEUTRAL_POSE[s]
                  for s in baxter_description.ARM_JOINT_SUFFIXES] for side in BAXTER_SIDES}
STATE_TIMEOUT_S = timing.DEFAULT.timeout_s  # Teleop's default: the 2020 firmware's 10 Hz
HAND = [0.1, -0.5, 0.2, 0.8, -0.1, 1.2, 0.3]  # within Baxter's limits, near neutral


class Rig:
    """A Teleop for puppet R with a clock, fed like the arm node feeds it."""

    def __init__(self, side='R', **kwargs):
        self.tp = teleop.Teleop(side, LIMITS, **kwargs)
        self.t = 0.0
        self.angles = list(NEUTRAL['right'])
        self.statuses = WORKING

    def feed(self, statuses=None, angles=None, heartbeat=True):
        self.tp.on_joint_states(self.t, statuses or self.statuses, angles or self.angles)
        if heartbeat:
            self.tp.on_heartbeat(self.t)

    def robot(self, enabled=True, pose=None):
        self.tp.on_robot(enabled)
        self.tp.on_robot_pose(self.t, pose or NEUTRAL)

    def step(self, dt=0.01, feed=True):
        self.t += dt
        if feed:
            self.feed()
        return self.tp.step(self.t)

    def press(self, button):
        self.tp.on_button(button)
        result = self.step()
        self.tp.on_button(0)
        return result


def enter(state):
    """Return a Rig driven through real inputs into `state`."""
    rig = Rig()
    rig.robot(enabled=state != NO_ROBOT)
    rig.statuses = ONE_UNCALIBRATED if state == CALIBRATING else WORKING
    rig.step()
    if state == FOLLOWING:
        rig.press(BUTTON_RIGHT)
    if state == FAULT:
        rig.step(1.0, feed=False)
    assert rig.tp.state == state
    return rig


def apply(rig, name):
    """Apply one named input and step once."""
    if name == 'robot_lost':
        rig.robot(enabled=False)
    elif name == 'robot_ok':
        rig.robot(enabled=True)
    elif name == 'uncalibrated':
        rig.statuses = ONE_UNCALIBRATED
    elif name == 'calibrated':
        rig.statuses = WORKING
    elif name == 'silent':
        return rig.step(1.0, feed=False)
    elif name == 'press_follow':
        return rig.press(BUTTON_RIGHT)
    elif name == 'press_hold':
        return rig.press(BUTTON_OPMODE)
    return rig.step()


# Written out by hand from README.md's "Operating the puppet", independently of teleop.TRANSITIONS.
EXPECTED = {
    NO_ROBOT: dict(robot_lost=NO_ROBOT, robot_ok=READY, uncalibrated=NO_ROBOT,
                   calibrated=NO_ROBOT, silent=NO_ROBOT, press_follow=NO_ROBOT,
                   press_hold=NO_ROBOT),
    CALIBRATING: dict(robot_lost=NO_ROBOT, robot_ok=CALIBRATING, uncalibrated=CALIBRATING,
                      calibrated=READY, silent=FAULT, press_follow=CALIBRATING,
                      press_hold=CALIBRATING),
    READY: dict(robot_lost=NO_ROBOT, robot_ok=READY, uncalibrated=CALIBRATING, calibrated=READY,
                silent=FAULT, press_follow=FOLLOWING, press_hold=READY),
    FOLLOWING: dict(robot_lost=NO_ROBOT, robot_ok=FOLLOWING, uncalibrated=CALIBRATING,
                    calibrated=FOLLOWING, silent=FAULT, press_follow=READY,
                    press_hold=FOLLOWING),
    # From a fault, any input that brings fresh data ends it; a press then acts as usual.
    FAULT: dict(robot_lost=NO_ROBOT, robot_ok=READY, uncalibrated=CALIBRATING, calibrated=READY,
                silent=FAULT, press_follow=FOLLOWING, press_hold=READY),
}


@pytest.mark.parametrize('state, name', [(s, n) for s in EXPECTED for n in EXPECTED[s]])
def test_every_state_under_every_input(state, name):
    rig = enter(state)
    apply(rig, name)
    assert rig.tp.state == EXPECTED[state][name]
    following = rig.tp.state == FOLLOWING
    assert any(rig.tp.following.values()) == following
    commands = rig.step().commands
    assert bool(commands) == (rig.tp.state == FOLLOWING)


def test_calibrating_detail_names_the_joints_to_turn():
    rig = enter(CALIBRATING)
    assert rig.tp.detail == 'joint 2 Uncalibrated: turn each through its index mark'


def test_button_1_cycles_limp_hold_feel_only_when_calibrated_setpoints_first():
    rig = enter(READY)
    pose = {'left': [0.0] * 7, 'right': [0.3, -0.4, 0.5, 1.0, -0.2, 0.9, 0.1]}
    rig.robot(pose=pose)
    actions = rig.press(BUTTON_OPMODE).actions
    # Setpoints first: the firmware holds whatever setpoints it has when hold arrives.
    assert actions == [opmode.SetSetpoints(pose['right']), opmode.SetOpmode(HOLD)]
    assert rig.press(BUTTON_OPMODE).actions == [opmode.SetSetpoints(pose['right']),
                                                opmode.SetOpmode(FEEL)]
    assert rig.tp.opmode == FEEL
    assert rig.press(BUTTON_OPMODE).actions == [opmode.SetOpmode(LIMP)]
    assert rig.tp.opmode == LIMP
    calibrating = enter(CALIBRATING)
    assert calibrating.press(BUTTON_OPMODE).actions == []
    assert calibrating.tp.opmode == LIMP


def test_left_puppet_holds_to_left_arm():
    rig = Rig('L')
    rig.robot(pose={'left': [0.5] * 7, 'right': [-0.5] * 7})
    rig.step()
    assert rig.press(BUTTON_OPMODE).actions[0] == opmode.SetSetpoints([0.5] * 7)


def test_button_acts_once_per_press_however_long_it_is_held():
    rig = enter(READY)
    for _ in range(50):  # the serial node reports the held button with every state set
        rig.tp.on_button(BUTTON_RIGHT)
        rig.step()
    assert rig.tp.state == FOLLOWING
    rig.tp.on_button(0)
    rig.step()
    assert rig.tp.state == FOLLOWING
    rig.press(BUTTON_RIGHT)
    assert rig.tp.state == READY


def test_going_from_one_button_to_another_is_a_press():
    rig = enter(READY)
    rig.tp.on_button(BUTTON_RIGHT)
    rig.step()
    rig.tp.on_button(BUTTON_LEFT)
    rig.step()
    assert rig.tp.following == {'left': True, 'right': True}
    assert 'left and right arms' in rig.tp.detail


def run_until_tracking(rig, side, steps=2000):
    """Step until `side` tracks the puppet; return the command of the step after that."""
    for _ in range(steps):
        rig.step()
        if rig.tp.tracking[side]:
            return rig.step().commands[side]
    raise AssertionError('never reached the puppet')


def test_own_side_copies_and_other_side_mirrors():
    rig = enter(READY)
    rig.angles = list(HAND)
    rig.press(BUTTON_RIGHT)
    rig.press(BUTTON_LEFT)
    right = run_until_tracking(rig, 'right')
    left = run_until_tracking(rig, 'left')
    assert right == pytest.approx(HAND, abs=1e-9)
    assert left == pytest.approx([-HAND[0], HAND[1], -HAND[2], HAND[3], -HAND[4], HAND[5],
                                  -HAND[6]], abs=1e-9)


def test_commands_are_clamped_to_baxter_limits():
    rig = enter(READY)
    rig.angles = [3.0, 3.0, -3.2, -1.0, 3.2, -2.0, 3.1]
    rig.press(BUTTON_RIGHT)
    for _ in range(3000):
        command = rig.step().commands['right']
        for angle, limit in zip(command, LIMITS['right']):
            assert limit.lower <= angle <= limit.upper
    assert command == pytest.approx([lim.upper if a > 0 else lim.lower
                                     for a, lim in zip(rig.angles, LIMITS['right'])])


def test_approach_is_slow_then_tracking_follows_at_joint_speed():
    rig = enter(READY)
    start = NEUTRAL['right']
    rig.angles = [s + 1.0 for s in start]  # 1 rad away on every joint
    rig.angles[3] = 1.5
    previous = rig.press(BUTTON_RIGHT).commands['right']
    assert max(abs(p - s) for p, s in zip(previous, start)) <= 0.5 * 0.01 + 1e-12, \
        'following starts where the robot is'
    steps = 1
    while not rig.tp.tracking['right']:
        command = rig.step(0.01).commands['right']
        steps += 1
        assert max(abs(c - p) for c, p in zip(command, previous)) <= 0.5 * 0.01 + 1e-12
        previous = command
    assert steps == pytest.approx(1.0 / (0.5 * 0.01), rel=0.05)
    rig.angles = [a + 0.3 for a in rig.angles]  # a quick hand move, within limits
    command = rig.step(0.01).commands['right']
    speeds = [abs(c - p) / 0.01 for c, p in zip(command, previous)]
    assert max(speeds) > 0.5, 'tracking is faster than the approach'
    for speed, limit in zip(speeds, LIMITS['right']):
        assert speed <= limit.velocity + 1e-9


def test_non_finite_angles_are_ignored():
    rig = enter(READY)
    rig.angles = list(HAND)
    rig.press(BUTTON_RIGHT)
    run_until_tracking(rig, 'right')
    bad = list(HAND)
    bad[1], bad[4] = float('nan'), float('inf')
    rig.tp.on_joint_states(rig.t, WORKING, bad)
    command = rig.tp.step(rig.t + 0.01).commands['right']
    assert all(math.isfinite(a) for a in command)
    assert command == pytest.approx(HAND)
    assert rig.tp.puppet.ignored_angles == 2


def test_watchdog_stops_commands_when_joint_states_stop():
    rig = enter(READY)
    rig.press(BUTTON_RIGHT)
    assert rig.step().commands
    quiet_since = rig.t
    while True:
        step = rig.step(0.01, feed=False)
        if rig.tp.state == FAULT:
            break
    assert rig.t - quiet_since == pytest.approx(STATE_TIMEOUT_S, abs=0.011)
    assert 'joint states' in rig.tp.detail
    assert rig.tp.following == {'left': False, 'right': False}
    # Baxter is told to stay where it is measured, once, then nothing more.
    assert step.commands == {'right': pytest.approx(NEUTRAL['right'])}
    assert not rig.step(0.01, feed=False).commands


def test_watchdog_catches_a_missing_heartbeat_and_needs_a_new_press():
    rig = enter(READY)
    rig.press(BUTTON_RIGHT)
    last_beat = rig.t
    while rig.tp.state != FAULT:
        rig.t += 0.05
        rig.feed(heartbeat=False)
        rig.tp.step(rig.t)
    assert rig.t - last_beat == pytest.approx(interface.HEARTBEAT_TIMEOUT_S, abs=0.06)
    assert 'heartbeat' in rig.tp.detail
    for _ in range(20):
        assert not rig.step(0.05).commands  # data is fresh again, yet nothing follows
    assert rig.tp.state == READY
    rig.press(BUTTON_RIGHT)
    assert rig.step().commands


def test_fault_lets_a_holding_puppet_go_limp():
    rig = enter(READY)
    rig.press(BUTTON_OPMODE)
    assert rig.tp.opmode == HOLD
    assert rig.step(1.0, feed=False).actions == [opmode.SetOpmode(LIMP)]


def test_end_piece_closes_and_opens_the_following_grippers_only():
    rig = enter(READY)
    rig.press(BUTTON_RIGHT)
    rig.tp.on_end_piece(0.05)
    assert rig.step().actions == [teleop.Grip('right', True)]
    rig.tp.on_end_piece(0.5)  # between the thresholds: no change
    assert rig.step().actions == []
    rig.tp.on_end_piece(0.95)
    assert rig.step().actions == [teleop.Grip('right', False)]
    rig.press(BUTTON_RIGHT)
    rig.tp.on_end_piece(0.0)
    assert rig.step().actions == []


def test_mirror_negates_joints_0_2_4_6():
    assert joint_motion.mirror([1, 2, 3, 4, 5, 6, 7]) == [-1, 2, -3, 4, -5, 6, -7]


def test_an_arm_driven_by_the_other_puppet_is_not_taken():
    rig = enter(READY)
    rig.tp.on_other_puppet(rig.t, False, True)
    rig.step()
    rig.press(BUTTON_RIGHT)
    assert rig.tp.state == READY and not rig.tp.following['right']
    assert 'other puppet' in rig.tp.detail
    rig.press(BUTTON_LEFT)
    assert rig.tp.following == {'left': True, 'right': False}
    rig.tp.on_other_puppet(rig.t, False, False)
    rig.press(BUTTON_RIGHT)
    assert rig.tp.following == {'left': True, 'right': True}


def test_fresh_data_right_after_a_stream_command_is_carried_whole():
    """A move that fits one command period is not sliced by an unlucky stream command."""
    rig = enter(READY)
    rig.angles = list(HAND)
    rig.press(BUTTON_RIGHT)
    run_until_tracking(rig, 'right')
    rig.step(0.0095, feed=False)  # the steady-stream command, just before new data
    rig.angles[6] += 0.03          # w2 may move 4 rad/s x 10 ms = 0.04 rad per command
    command = rig.step(0.0005).commands['right']
    assert command[6] == pytest.approx(rig.angles[6])
    rig.angles[0] += 0.03          # s0 may move only 1.5 rad/s x 10 ms = 0.015 rad
    command = rig.step(0.0005).commands['right']
    assert command[0] == pytest.approx(rig.angles[0] - 0.015)


def test_both_puppets_claiming_an_arm_at_once_both_let_go():
    rig = enter(READY)
    rig.press(BUTTON_RIGHT)
    assert rig.step().commands
    rig.tp.on_other_puppet(rig.t, False, True)  # the other pressed 3 at about the same time
    assert rig.step().commands == {'right': pytest.approx(NEUTRAL['right'])}  # stay, once
    assert rig.tp.state == READY and 'both let go' in rig.tp.detail
    assert rig.step().commands == {}


def test_a_claim_that_is_not_renewed_expires():
    rig = enter(READY)
    rig.tp.on_other_puppet(rig.t, False, True)
    rig.press(BUTTON_RIGHT)
    assert not rig.tp.following['right']
    for _ in range(int(teleop.CLAIM_EXPIRY_S / 0.01) + 1):  # the other arm node died
        rig.step()
    rig.press(BUTTON_RIGHT)
    assert rig.tp.following['right']


def test_watchdog_works_before_the_first_heartbeat():
    tp = teleop.Teleop('R', LIMITS)  # fed joint states, never a heartbeat
    tp.on_robot(True)
    tp.on_robot_pose(0.0, NEUTRAL)
    t = 0.0
    while True:
        tp.on_joint_states(t, WORKING, NEUTRAL['right'])
        tp.step(t)
        if tp.state == FAULT:
            break
        t += 0.05
        assert t < 10, 'no fault without heartbeats'
    assert t == pytest.approx(interface.HEARTBEAT_TIMEOUT_S, abs=0.06)
    assert tp.heartbeat_age(t) == -1.0
    tp2 = teleop.Teleop('R', LIMITS)
    tp2.on_robot(True)
    tp2.on_robot_pose(0.0, NEUTRAL)
    tp2.on_joint_states(0.0, WORKING, NEUTRAL['right'])
    tp2.step(0.0)
    tp2.on_button(BUTTON_RIGHT)
    assert tp2.step(0.01).commands
    assert tp2.step(0.01 + STATE_TIMEOUT_S + 0.01).commands == {
        'right': pytest.approx(NEUTRAL['right'])}  # stay where Baxter is
    assert tp2.state == FAULT
    assert tp2.step(0.03 + STATE_TIMEOUT_S).commands == {}


def test_speed_stays_bounded_however_commands_are_spaced():
    rig = enter(READY)
    rig.press(BUTTON_RIGHT)
    run_until_tracking(rig, 'right')
    rig.angles = [lim.upper - 0.01 for lim in LIMITS['right']]  # far away on every joint
    start_t, start = rig.t, rig.step(0.001).commands['right']
    for k in range(200):  # stream commands and fresh data interleaved 1 ms / 9 ms apart
        command = rig.step(0.001 if k % 2 else 0.009).commands['right']
    elapsed = rig.t - start_t
    for a, b, lim in zip(command, start, LIMITS['right']):
        assert abs(a - b) <= lim.velocity * (elapsed + 0.01) + 1e-9


def test_nan_from_baxter_is_ignored():
    rig = enter(READY)
    rig.robot(pose={'left': NEUTRAL['left'], 'right': [math.nan] + NEUTRAL['right'][1:]})
    rig.press(BUTTON_RIGHT)
    command = rig.step().commands['right']
    assert all(math.isfinite(a) for a in command)
    assert command == pytest.approx(NEUTRAL['right'], abs=0.01)


def test_entering_hold_sends_the_setpoints_once_before_the_opmode():
    rig = enter(READY)
    actions = []
    rig.tp.on_button(BUTTON_OPMODE)
    for _ in range(100):
        actions += rig.step().actions
        rig.tp.on_button(0)
    assert actions == [opmode.SetSetpoints(NEUTRAL['right']), opmode.SetOpmode(HOLD)]


def test_a_joint_never_seen_valid_keeps_baxter_from_following():
    rig = Rig()
    rig.robot(pose={'left': NEUTRAL['left'], 'right': [0.0, 0.0, 0.0, 0.75, 0.0, 0.0, 0.0]})
    first = list(HAND)
    first[3] = math.nan  # e1 never valid: it must not become a 0.0 target
    rig.angles = first
    rig.step()
    assert rig.tp.state == CALIBRATING
    assert rig.tp.detail == 'joint 3 with no valid angle yet'
    assert not rig.press(BUTTON_RIGHT).commands and rig.tp.state == CALIBRATING
    rig.angles = list(HAND)
    rig.step()
    assert rig.tp.state == READY
    rig.angles = first  # NaN again later: e1 keeps its last valid angle
    rig.press(BUTTON_RIGHT)
    command = run_until_tracking(rig, 'right')
    assert command[3] == pytest.approx(HAND[3], abs=0.03)


def test_approach_speed_is_capped_by_the_velocity_limits():
    rig = Rig(approach_speed_rad_s=100.0)
    rig.robot()
    rig.step()
    rig.angles = [lim.upper - 0.05 for lim in LIMITS['right']]  # far from neutral
    previous = NEUTRAL['right']
    rig.press(BUTTON_RIGHT)
    for _ in range(20):
        command = rig.step().commands['right']
        for c, p, lim in zip(command, previous, LIMITS['right']):
            assert abs(c - p) <= lim.velocity * 0.01 * 2 + 1e-9  # budget: one period + dt
        previous = command


def test_a_robot_pose_out_of_its_limits_is_not_believed():
    rig = enter(READY)
    rig.robot(pose={'left': NEUTRAL['left'], 'right': [1e39] * 7})
    rig.robot(pose={'left': NEUTRAL['left'], 'right': [0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0]})
    assert rig.tp.robot.ignored_poses == 2
    actions = rig.press(BUTTON_OPMODE).actions
    assert actions[0] == opmode.SetSetpoints(NEUTRAL['right'])  # the last believable pose


def test_stopping_to_follow_tells_baxter_to_stay_where_it_is():
    for stop in ('press_follow', 'uncalibrated', 'silent'):
        rig = enter(FOLLOWING)
        rig.angles = list(HAND)
        run_until_tracking(rig, 'right')
        where = [a + 0.01 for a in HAND]  # Baxter lags behind its command
        rig.robot(pose={'left': NEUTRAL['left'], 'right': where})
        step = apply(rig, stop)
        assert rig.tp.state != FOLLOWING, stop
        assert step.commands == {'right': pytest.approx(where)}, stop
        assert not apply(rig, 'calibrated').commands, stop


def test_a_failed_controller_faults_and_needs_a_new_press():
    rig = enter(FOLLOWING)
    rig.tp.on_controller_failed('OverflowError: too big')
    step = rig.step()
    assert rig.tp.state == FAULT and 'OverflowError' in rig.tp.detail
    assert step.commands == {'right': pytest.approx(NEUTRAL['right'])}
    for _ in range(10):
        assert not rig.step().commands  # puppet data is fresh, yet nothing follows
    assert rig.tp.state == READY
    assert rig.press(BUTTON_RIGHT).commands


def test_a_stop_commands_where_the_moving_arm_is_now_not_where_it_was_measured():
    moving = [0.2, 0.0, 0.0, -0.3, 0.0, 0.0, 0.0]  # rad/s
    garbage = [math.nan, 99.0, 0.0, 0.0, 0.0, 0.0, 0.0]  # not finite, beyond the limit
    for speeds, age_s, expected_s in ((moving, 0.02, 0.02), (moving, 0.5, 0.05),
                                      (garbage, 0.02, 0.0)):
        rig = enter(FOLLOWING)
        rig.tp.on_robot_pose(rig.t, NEUTRAL, {'right': speeds})
        rig.t += age_s
        rig.feed(statuses=ONE_UNCALIBRATED)  # a joint lost its calibration: stop
        step = rig.tp.step(rig.t)
        expected = [a + (v if abs(v) < 1.0 else 0.0) * expected_s
                    for a, v in zip(NEUTRAL['right'], speeds)]
        assert step.commands == {'right': pytest.approx(expected)}, (speeds, age_s)


@pytest.mark.parametrize('side, button', [('right', BUTTON_RIGHT), ('left', BUTTON_LEFT)])
def test_no_stay_command_goes_to_a_baxter_that_is_absent_or_disabled(side, button):
    """Baxter goes absent or disabled while an arm follows: its pose may be stale, so the step
    that stops following commands nothing; a puppet fault with Baxter there commands the stay."""
    rig = enter(READY)
    rig.press(button)
    assert rig.tp.following[side] and rig.step().commands
    rig.robot(enabled=False)
    step = rig.step()
    assert rig.tp.state == NO_ROBOT and not rig.tp.following[side]
    assert step.commands == {}
    rig = enter(READY)
    rig.press(button)
    step = rig.step(1.0, feed=False)   # the puppet falls silent; Baxter is there
    assert rig.tp.state == FAULT
    assert step.commands == {side: pytest.approx(NEUTRAL[side])}


def test_after_a_fault_joint_states_alone_do_not_end_it_a_heartbeat_since_must_come_too():
    """The puppet's joint states stop (a fault) while its 1 Hz heartbeat is still recent; when
    they come back, the fault ends ("puppet data is back") only with a heartbeat after it."""
    rig = enter(FOLLOWING)
    rig.step(STATE_TIMEOUT_S + 0.1, feed=False)
    assert rig.tp.state == FAULT and 'no joint states' in rig.tp.detail
    for _ in range(10):   # joint states at 10 Hz again, the next heartbeat not yet
        rig.t += 0.1
        rig.feed(heartbeat=False)
        rig.tp.step(rig.t)
        assert rig.tp.state == FAULT and 'puppet data is back' not in rig.tp.detail
    rig.tp.on_heartbeat(rig.t)
    rig.step(feed=False)
    assert rig.tp.state == READY
