"""Unit tests of robopuppet.episodes.tracking_watch: each rule at its boundaries, and the
simulated firmware under a resting and a gripping hand seen through the watch."""
import math

import pytest

from robopuppet import settings
from robopuppet.arm.joint_motion import SpeedBudget
from robopuppet.episodes import tracking_watch as tw
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_model import REST_POSE_RAD, PuppetFirmware

LIMITS = [(-7.2, 7.2)] * settings.NUM_JOINTS
SETPOINTS = [0.0] * settings.NUM_JOINTS
STATE_PERIOD_S = 0.1  # the firmware's 10 Hz state sets


def feed(watch, t0, seconds, error_rad, volts, joint=3):
    """Samples every STATE_PERIOD_S from t0 for `seconds` (inclusive), `joint` error_rad from
    its setpoint at volts, the others on theirs at 0 V; return [(t, Verdict or None)]."""
    out, k = [], 0
    while k * STATE_PERIOD_S <= seconds + 1e-9:
        t = t0 + k * STATE_PERIOD_S
        angles, voltages = list(SETPOINTS), [0.0] * settings.NUM_JOINTS
        angles[joint], voltages[joint] = error_rad, volts
        out.append((t, watch.on_sample(t, SETPOINTS, angles, voltages)))
        k += 1
    return out


@pytest.mark.parametrize('volts, limits, expected', [
    (7.2, (-7.2, 7.2), True), (7.15, (-7.2, 7.2), True), (7.14, (-7.2, 7.2), False),
    (-7.2, (-7.2, 7.2), True), (-7.1, (-7.2, 7.2), False),
    (3.0, (-3.0, 3.0), True),             # a lower limit (e.g. feel's 2 V, a careful tuning)
    (0.0, (0.0, 0.0), False),             # a limit of 0 V pushes nothing
    (None, (-7.2, 7.2), False), (math.nan, (-7.2, 7.2), False),
])
def test_saturated_means_at_the_devices_voltage_limit(volts, limits, expected):
    assert tw.saturated(volts, *limits) is expected


def test_voltage_limits_come_from_the_stored_settings_else_the_defaults():
    stored = {j: dict(settings.DEFAULTS, voltage_min=-2.0 - j, voltage_max=3.0)
              for j in settings.JOINTS}
    assert tw.voltage_limits(stored)[4] == (-6.0, 3.0)
    assert tw.voltage_limits(None) == [(-7.2, 7.2)] * settings.NUM_JOINTS


def test_a_joint_far_off_at_its_voltage_limit_for_the_follow_time_does_not_follow():
    watch = tw.TrackingWatch('R', LIMITS)
    out = feed(watch, 10.0, tw.FOLLOW_TIME_S, -0.9, 7.2)
    assert all(verdict is None for _, verdict in out[:-1])  # 0.9 s: not yet
    t, verdict = out[-1]
    assert t == pytest.approx(10.0 + tw.FOLLOW_TIME_S)
    assert verdict == tw.Verdict([3], 'puppet arm R does not follow: joint 3 0.90 rad from its '
                                 'setpoint for 1.0 s at 7.20 V (saturated)')


@pytest.mark.parametrize('error_rad, volts', [
    (tw.FOLLOW_ERROR_RAD, 7.2),          # at the error bound: not beyond it
    (1.0, 7.2 - tw.SATURATION_MARGIN_V - 0.01),  # far, but the motor is not saturated
])
def test_not_beyond_either_bound_is_no_verdict_in_the_follow_time(error_rad, volts):
    watch = tw.TrackingWatch('R', LIMITS)
    assert all(v is None for _, v in feed(watch, 0.0, tw.FOLLOW_TIME_S + 0.5, error_rad, volts))


def test_one_sample_that_follows_starts_the_time_again():
    watch = tw.TrackingWatch('R', LIMITS)
    feed(watch, 0.0, 0.9, 0.5, -7.2)
    assert watch.on_sample(1.0, SETPOINTS, [0.0] * 7, [0.0] * 7) is None  # caught up
    out = feed(watch, 1.1, tw.FOLLOW_TIME_S, 0.5, -7.2)
    assert [t for t, v in out if v] == [pytest.approx(1.1 + tw.FOLLOW_TIME_S)]


def test_every_joint_far_off_is_named_with_its_own_numbers():
    watch = tw.TrackingWatch('L', [(-7.2, 7.2)] * 6 + [(-3.0, 3.0)])
    verdict = None
    for k in range(12):
        t = k * STATE_PERIOD_S
        angles = [0.0, 0.5, 0.0, -0.4, 0.0, 0.0, 0.6 if k >= 5 else 0.0]
        verdict = verdict or watch.on_sample(t, SETPOINTS, angles,
                                             [0.0, -7.2, 0.0, 7.2, 0.0, 0.0, -3.0])
    assert verdict.joints == [1, 3, 6]
    assert verdict.why == ('puppet arm L does not follow: joint 1 0.50 rad from its setpoint '
                           'for 1.0 s at -7.20 V, joint 3 0.40 rad from its setpoint for 1.0 s '
                           'at 7.20 V, joint 6 0.60 rad from its setpoint for 0.5 s at -3.00 V '
                           '(saturated)')


def test_a_motor_saturated_for_the_saturation_time_is_stopped_however_close():
    watch = tw.TrackingWatch('R', LIMITS)
    out = feed(watch, 0.0, tw.SATURATION_MAX_S, 0.1, 7.2)   # close, but pushing hard
    assert all(v is None for _, v in out[:-1])
    t, verdict = out[-1]
    assert t == pytest.approx(tw.SATURATION_MAX_S)
    assert verdict == tw.Verdict([3], 'puppet arm R pushes at its voltage limit too long: '
                                 'joint 3 at 7.20 V for 2.0 s, 0.10 rad from its setpoint (to '
                                 'protect the motors)')


def test_without_voltages_only_the_end_is_watched():
    watch = tw.TrackingWatch('R', LIMITS)
    for k in range(50):
        assert watch.on_sample(k * 0.1, SETPOINTS, [1.0] * 7) is None
    assert not watch.reached(SETPOINTS, 0.0)
    assert 'joint 0 1.00 rad from it at an unknown voltage' in watch.not_reached(
        SETPOINTS, 4.0).why


def test_the_last_pose_is_reached_within_the_tolerance_by_a_sample_after_it_was_sent():
    watch = tw.TrackingWatch('R', LIMITS)
    assert not watch.reached(SETPOINTS, 0.0)  # no sample yet
    close = [tw.FINAL_TOLERANCE_RAD] * 7
    watch.on_sample(5.0, SETPOINTS, close, [1.0] * 7)
    assert watch.reached(SETPOINTS, 5.0) and not watch.reached(SETPOINTS, 5.01)
    assert watch.distance(SETPOINTS) == pytest.approx(tw.FINAL_TOLERANCE_RAD)
    off = list(close)
    off[2] = tw.FINAL_TOLERANCE_RAD + 0.001
    watch.on_sample(5.1, SETPOINTS, off, [0.0, 0.0, -2.5, 0.0, 0.0, 0.0, 0.0])
    assert not watch.reached(SETPOINTS, 5.0)
    assert watch.not_reached(SETPOINTS, 4.0) == tw.Verdict([2], (
        'puppet arm R did not reach the last recorded pose within 0.05 rad 4.0 s after the '
        'last setpoints: joint 2 0.05 rad from it at -2.50 V'))


# ---- the simulated firmware (the 2020 firmware's PID, the arm, the hand) through the watch --

SHIPPED = dict(velocity_min=-6.283, velocity_max=6.283, voltage_min=-7.2, voltage_max=7.2,
               pid_kp=20.0, pid_ki=10.0, pid_kd=1.0)
PLAY_SPEED_RAD_S = 1.5  # puppet_playback.PLAY_SPEED_RAD_S: the playback's fastest setpoint


def play_into_the_simulator(hand, move_rad, pose=(0.0,) * 7, seconds=6.0):
    """Hold the simulated puppet at pose, then move every joint's setpoint by move_rad (within
    +-1.5 rad) at the playback's top speed; hand: 'resting' (put there, then left alone), or
    'gripping' (holding on there throughout: the target sent every 0.1 s).

    Returns:
        (the first watch verdicts [(t, Verdict)], time the setpoints arrived, time the last
        pose was reached or None); it stops at the first verdict or once reached.
    """
    firmware = PuppetFirmware(pose_rad=tuple(pose))
    for joint in settings.JOINTS:
        for name, value in SHIPPED.items():
            firmware.handle(codec.JointConfig(joint, settings.CONFIG_ID[name], value))
    grip = dict(enumerate(pose))
    firmware.set_hand(grip)
    t = 0.0
    while t < 1.5 - 1e-9:  # the hand puts it there
        t += 0.02
        if hand == 'gripping' and round(t / 0.02) % 5 == 0:
            firmware.set_hand(grip)
        firmware.advance(t)
    start = list(firmware.angle_rad)
    for joint in settings.JOINTS:
        firmware.handle(codec.JointSetpoint(joint, start[joint]))
    firmware.handle(codec.Opmode(codec.HOLD))
    watch, budget = tw.TrackingWatch('R', LIMITS), SpeedBudget(start, 0.02, t)
    goal = [min(1.5, max(-1.5, a + move_rad)) for a in start]
    verdicts, arrived_t, reached_t = [], None, None
    end = t + seconds
    while t < end - 1e-9:
        t += 0.02
        setpoints = budget.move(goal, [PLAY_SPEED_RAD_S] * 7, t)
        if arrived_t is None and setpoints == goal:
            arrived_t = t
        if hand == 'gripping' and round(t / 0.02) % 5 == 0:
            firmware.set_hand(grip)
        for joint in settings.JOINTS:
            firmware.handle(codec.JointSetpoint(joint, setpoints[joint]))
        states = [m for m in firmware.advance(t) if isinstance(m, codec.JointState)]
        if states:
            verdict = watch.on_sample(t, setpoints, [m.angle_rad for m in states],
                                      [m.voltage_v for m in states])
            if verdict:
                verdicts.append((t, verdict))
            if arrived_t is not None and watch.reached(goal, arrived_t):
                reached_t = t
            if verdicts or reached_t is not None:
                break
    return verdicts, arrived_t, reached_t


@pytest.mark.parametrize('pose', [(0.0,) * 7, REST_POSE_RAD, (-0.2, -1.0, -0.3, 1.0, -0.3, 0.9,
                                                                0.25)])
@pytest.mark.parametrize('move_rad', [-1.1, -0.5, 0.5, 1.1])
def test_the_simulated_puppet_under_a_resting_hand_follows_within_the_rules(move_rad, pose):
    verdicts, arrived_t, reached_t = play_into_the_simulator('resting', move_rad, pose)
    assert verdicts == []
    assert reached_t is not None and reached_t - arrived_t < tw.FINAL_TIMEOUT_S


def test_the_simulated_puppet_held_firmly_breaks_the_follow_rule_in_its_time():
    verdicts, _, reached_t = play_into_the_simulator('gripping', -1.1)
    assert reached_t is None
    t, verdict = verdicts[0]
    assert verdict.joints == list(settings.JOINTS)   # every joint held
    assert 'does not follow' in verdict.why and '7.20 V' in verdict.why
    # Far beyond FOLLOW_ERROR_RAD (the setpoints left at 1.5 rad/s): the time it took is the
    # rule's, after the P term alone (kp 20 V/rad) saturated at 0.36 rad.
    assert t - 1.5 == pytest.approx(0.36 / PLAY_SPEED_RAD_S + tw.FOLLOW_TIME_S, abs=0.25)
