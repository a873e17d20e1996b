"""Unit tests of robopuppet.puppet_sim.puppet_model: the simulated 2020 firmware and arm."""
import math

import pytest

from robopuppet import settings
from robopuppet.protocol import codec
from robopuppet.puppet_sim.puppet_arm import (COULOMB_FRICTION_NM, HAND_GRIP_S, HAND_YIELD_V,
                                              NOMINAL_VOLTAGE_V, STALL_TORQUE_NM)
from robopuppet.puppet_sim.puppet_model import POWER_ON_SETTINGS, REST_POSE_RAD, PuppetFirmware

ID = settings.CONFIG_ID
# Limits a host loads before it expects the puppet to move or hold (the power-on ones are
# velocity +-pi/4 rad/s and voltage 0 V).
LOADED = dict(velocity_min=-6.283, velocity_max=6.283, voltage_min=-7.2, voltage_max=7.2)


def run(firmware, start_s, seconds, step_s=0.01, grip=None):
    """Advance firmware from start_s for seconds; return (end time, all messages sent).

    grip: {joint: angle rad} the hand keeps holding (sent again every 0.1 s), or None."""
    out = []
    t = start_s
    while t < start_s + seconds - 1e-9:
        if grip and round(t / step_s) % round(0.1 / step_s) == 0:
            firmware.set_hand(grip)
        t += step_s
        out.extend(firmware.advance(t))
    return t, out


def states(messages):
    return [m for m in messages if isinstance(m, codec.JointState)]


def configure(firmware, joint, **values):
    for name, value in values.items():
        firmware.handle(codec.JointConfig(joint, ID[name], value))


def loaded(**values):
    """Return a firmware with LOADED limits (and values) on every joint."""
    firmware = PuppetFirmware()
    for joint in settings.JOINTS:
        configure(firmware, joint, **dict(LOADED, **values))
    return firmware


def test_heartbeat_1hz_and_state_sets_at_the_state_rate_in_order():
    firmware = PuppetFirmware(state_rate_hz=20.0)
    assert firmware.advance(0.0) == []  # power-on: nothing due yet
    _, out = run(firmware, 0.0, 3.05)
    assert sum(isinstance(m, codec.Heartbeat) for m in out) == 3  # at 1, 2 and 3 s
    sets = [out[i:i + 12] for i, m in enumerate(out)
            if isinstance(m, codec.JointState) and m.joint == 0]
    assert 59 <= len(sets) <= 61
    assert [type(m) for m in sets[1]] == [codec.JointState] * 7 + [codec.Gripper] * 4 + \
        [codec.Buttons]
    assert [m.joint for m in sets[1][:7]] == list(settings.JOINTS)


def test_a_late_advance_sends_every_state_set_due_meanwhile_each_of_its_own_time():
    # The device's clock does not wait for the simulator's process: called late (a loaded
    # host), the firmware still sends a set per state period, as the 2020 firmware does.
    firmware = loaded()
    firmware.advance(0.0)
    run(firmware, 0.0, 1.0)
    firmware.set_hand({3: REST_POSE_RAD[3] - 1.0})  # joint 3 (hall) moves: sets differ
    out = firmware.advance(1.35)  # a 0.35 s stall: the sets of 1.1, 1.2 and 1.3 s
    sets = [m for m in states(out) if m.joint == 3]
    assert len(sets) == 3 and len(set(m.angle_rad for m in sets)) == 3
    assert sum(isinstance(m, codec.Heartbeat) for m in out) == 0
    out = firmware.advance(3.0)  # a 1.65 s stall: only CATCH_UP_S (0.5 s) is caught up
    assert len(states(out)) == 6 * settings.NUM_JOINTS  # the sets of 2.5 .. 3.0 s
    assert sum(isinstance(m, codec.Heartbeat) for m in out) == 1  # the one at 3 s
    _, out = run(firmware, 3.0, 1.0)
    assert len(states(out)) == 10 * settings.NUM_JOINTS  # and on at the state rate


def test_rest_pose_quad_joints_uncalibrated_until_index_then_mechanical_angle():
    firmware = loaded()
    t, out = run(firmware, 0.0, 0.5)
    last = {m.joint: m for m in states(out)}
    for joint in settings.JOINTS:
        expected = codec.UNCALIBRATED if joint in settings.QUAD_JOINTS else codec.WORKING
        assert last[joint].status == expected
        assert REST_POSE_RAD[joint] != 0.0
    assert last[1].angle_rad == pytest.approx(REST_POSE_RAD[1], abs=0.05)
    # Sweep joint 0 through its index mark at 0 to -0.4.
    firmware.set_hand({0: -0.4})
    t, out = run(firmware, t, 1.0)
    last = {m.joint: m for m in states(out)}
    assert last[0].status == codec.WORKING
    assert last[0].angle_rad == pytest.approx(-0.4, abs=0.02)
    assert last[2].status == codec.UNCALIBRATED  # untouched quad joints stay uncalibrated


def test_home_and_sign_shape_the_reported_angle():
    firmware = PuppetFirmware()
    configure(firmware, 1, sign_angle=-1.0, home_angle=0.25)  # sign first, as hosts must
    t, out = run(firmware, 0.0, 0.5)
    joint1 = [m for m in states(out) if m.joint == 1][-1]
    # sign x wrap(raw - home x sign): the firmware subtracts home (the old model added it).
    mechanical = firmware.arm.angle_rad[1]
    assert joint1.angle_rad == pytest.approx(-mechanical - 0.25, abs=1e-3)


def test_home_is_stored_with_the_sign_in_force_when_it_arrives():
    firmware = PuppetFirmware()
    configure(firmware, 1, home_angle=0.25, sign_angle=-1.0)  # home first: stored as +0.25
    t, out = run(firmware, 0.0, 0.5)
    first = [m for m in states(out) if m.joint == 1][-1].angle_rad
    mechanical = firmware.arm.angle_rad[1]
    assert first == pytest.approx(-(mechanical - 0.25), abs=1e-3)
    configure(firmware, 1, home_angle=0.25, sign_angle=-1.0)  # the same load again
    t, out = run(firmware, t, 1.0)
    second = [m for m in states(out) if m.joint == 1][-1].angle_rad
    assert second == pytest.approx(-mechanical - 0.25, abs=1e-3)  # a reload moved it


def test_quadrature_home_applies_before_calibration_to_the_power_on_count():
    firmware = PuppetFirmware()
    configure(firmware, 0, home_angle=0.1)
    firmware.set_hand({0: REST_POSE_RAD[0] + 0.2})  # turn it, away from its index mark
    t, out = run(firmware, 0.0, 1.0)
    last = [m for m in states(out) if m.joint == 0][-1]
    assert last.status == codec.UNCALIBRATED
    assert last.angle_rad == pytest.approx(0.2 - 0.1, abs=2e-3)  # counted from power-on
    firmware.set_hand({0: -0.3})  # through the index mark at 0
    t, out = run(firmware, t, 2.0)
    last = [m for m in states(out) if m.joint == 0][-1]
    assert last.status == codec.WORKING
    assert last.angle_rad == pytest.approx(-0.3 - 0.1, abs=2e-3)


def test_disconnected_hall_encoder_reports_disconnected_and_zero():
    firmware = PuppetFirmware(hall_disconnected=[3])
    configure(firmware, 3, sign_angle=-1.0, home_angle=0.4)
    _, out = run(firmware, 0.0, 0.5)
    last = {m.joint: m for m in states(out)}
    assert last[3].status == codec.DISCONNECTED and last[3].angle_rad == 0.0
    assert last[1].status == last[5].status == codec.WORKING
    with pytest.raises(ValueError):
        PuppetFirmware(hall_disconnected=[2])


def test_power_on_settings_limit_speed_and_voltage_until_loaded():
    firmware = PuppetFirmware()
    assert firmware.config[2] == POWER_ON_SETTINGS
    assert POWER_ON_SETTINGS['velocity_max'] == pytest.approx(math.pi / 4)
    assert POWER_ON_SETTINGS['voltage_min'] == POWER_ON_SETTINGS['voltage_max'] == 0.0
    configure(firmware, 1, pid_kp=20.0)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.set_hand({1: REST_POSE_RAD[1] - 1.0})
    t, out = run(firmware, t, 0.5)
    angles = [m.angle_rad for m in states(out) if m.joint == 1]
    steps = [a - b for a, b in zip(angles, angles[1:])]
    assert max(steps) <= math.pi / 4 * 0.1 + 1e-3  # 10 Hz states, pi/4 rad/s
    firmware.handle(codec.Opmode(codec.HOLD))
    run(firmware, t, 0.5)
    assert firmware.voltage_v[1] == 0.0  # gain 20, but the voltage limits are still 0 V


def test_angle_clamp_and_rate_limit():
    firmware = loaded()
    configure(firmware, 3, angle_max=0.95, velocity_max=0.5, velocity_min=-0.5)
    t, _ = run(firmware, 0.0, 0.2)
    firmware.set_hand({3: 1.5})
    t, out = run(firmware, t, 0.4)
    angles = [m.angle_rad for m in states(out) if m.joint == 3]
    assert angles[-1] <= 0.95 + 1e-6
    steps = [b - a for a, b in zip(angles, angles[1:])]
    assert max(steps) <= 0.5 * 0.1 + 1e-6  # 10 Hz states, 0.5 rad/s


def test_limp_follows_the_hand_with_no_voltage():
    firmware = PuppetFirmware()
    firmware.set_hand({j: 0.3 for j in settings.JOINTS})
    _, out = run(firmware, 0.0, 1.5)
    last = {m.joint: m for m in states(out)}
    assert last[1].angle_rad == pytest.approx(0.3, abs=0.05)
    assert all(m.voltage_v == 0.0 for m in last.values())


def hold_released(kp, seconds=2.0):
    """Enter hold at rest, let go of the arm; return joint 1's angle drift and voltage."""
    firmware = loaded(pid_kp=kp, pid_ki=kp / 2, pid_kd=kp / 20)
    t, _ = run(firmware, 0.0, 0.3)
    for joint in settings.JOINTS:  # setpoints first: hold keeps the ones it has
        firmware.handle(codec.JointSetpoint(joint, firmware.angle_rad[joint]))
    firmware.handle(codec.Opmode(codec.HOLD))
    firmware.set_hand({j: math.nan for j in settings.JOINTS})
    _, out = run(firmware, t, seconds)
    last = [m for m in states(out) if m.joint == 1][-1]
    return abs(last.angle_rad - REST_POSE_RAD[1]), last.voltage_v


def test_pid_gains_matter_in_hold():
    sag_none, volts_none = hold_released(0.0)
    sag_soft, _ = hold_released(5.0)
    sag_stiff, volts_stiff = hold_released(40.0)
    assert sag_none > 0.5       # gravity pulls an unpowered arm down
    assert volts_none == 0.0
    assert sag_stiff < 0.07 < sag_soft < sag_none / 2
    assert volts_stiff < -1.0   # pushing up against gravity (joint 1 pitches down positive)


def test_setpoint_moves_a_released_joint_in_hold_and_is_clamped():
    firmware = loaded()
    configure(firmware, 3, pid_kp=20.0, pid_ki=10.0, pid_kd=1.0, angle_max=1.2)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.Opmode(codec.HOLD))
    firmware.set_hand({3: None})
    firmware.handle(codec.JointSetpoint(3, 3.0))
    assert firmware.setpoint_rad[3] == 1.2
    _, out = run(firmware, t, 3.0)
    assert [m for m in states(out) if m.joint == 3][-1].angle_rad == pytest.approx(1.2, abs=0.05)


def test_firm_hand_wins_against_hold():
    firmware = loaded()
    configure(firmware, 1, pid_kp=20.0, pid_ki=10.0)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.JointSetpoint(1, REST_POSE_RAD[1]))
    firmware.handle(codec.Opmode(codec.HOLD))
    _, out = run(firmware, t, 3.0, grip={1: -0.5})  # the operator holds on
    last = [m for m in states(out) if m.joint == 1][-1]
    assert last.angle_rad == pytest.approx(-0.5, abs=0.15)
    assert last.voltage_v == pytest.approx(7.2, abs=1e-3)  # the motor pushes back, saturated


def hand_against_hold(voltage_limit_v):
    """Hold joint 1 at rest with a saturating P gain while the hand pulls it to -0.5 rad;
    return (firmware, hand torque N m on joint 1, motor voltage V) after 3 s."""
    firmware = loaded(pid_kp=20.0)
    configure(firmware, 1, voltage_min=-voltage_limit_v, voltage_max=voltage_limit_v)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.JointSetpoint(1, REST_POSE_RAD[1]))
    firmware.handle(codec.Opmode(codec.HOLD))
    firmware.set_hand({2: math.nan})
    run(firmware, t, 3.0, grip={1: -0.5})
    return firmware, firmware.arm.hand_torque_nm[1], firmware.arm.motor_voltage_v[1]


@pytest.mark.parametrize('voltage_limit_v', [1.0, 2.0, 7.2])
def test_hand_torque_balances_the_servo_and_gravity(voltage_limit_v):
    firmware, hand_nm, motor_v = hand_against_hold(voltage_limit_v)
    assert motor_v == pytest.approx(voltage_limit_v, abs=1e-3)  # saturated, pushing back
    servo_nm = STALL_TORQUE_NM[1] * motor_v / NOMINAL_VOLTAGE_V
    # At rest: hand + gravity + servo = 0 up to the joint's static friction.
    assert abs(hand_nm + firmware.arm.gravity_nm[1] + servo_nm) <= COULOMB_FRICTION_NM[1] + 1e-6
    assert firmware.arm.hand_torque_nm[2] == 0.0  # let go: the hand exerts nothing


def test_hand_torque_grows_with_the_servo_voltage_it_meets():
    weak = hand_against_hold(1.0)[1]
    strong = hand_against_hold(2.0)[1]
    assert weak < 0.0 and strong < weak  # pulling toward -0.5 rad, harder against 2 V
    assert weak - strong == pytest.approx(STALL_TORQUE_NM[1] / NOMINAL_VOLTAGE_V, abs=0.13)


def held_away_resting(voltage_limit_v=7.2, away_rad=0.6):
    """Hold joints 1 and 3 away_rad from where the hand put them (shipped gains), the hand
    left alone from then on; return (firmware, time, the hand's pose)."""
    firmware = loaded(pid_kp=20.0, pid_ki=10.0, pid_kd=1.0, voltage_min=-voltage_limit_v,
                      voltage_max=voltage_limit_v)
    hand = list(REST_POSE_RAD)
    firmware.set_hand(dict(enumerate(hand)))
    t, _ = run(firmware, 0.0, 0.3)
    for joint in settings.JOINTS:
        firmware.handle(codec.JointSetpoint(joint, firmware.angle_rad[joint] + (
            away_rad if joint in (1, 3) else 0.0)))
    firmware.handle(codec.Opmode(codec.HOLD))
    return firmware, t, hand


def test_a_resting_hand_gives_way_to_the_motors_in_hold():
    firmware, t, hand = held_away_resting()
    t, _ = run(firmware, t, HAND_GRIP_S - 0.4)
    assert abs(firmware.arm.angle_rad[1] - hand[1]) < 0.15  # it still grips: held back
    assert abs(firmware.voltage_v[1]) > HAND_YIELD_V
    t, _ = run(firmware, t, 3.0)
    for joint in (1, 3):  # then it goes along: the joints reach their setpoints
        assert firmware.angle_rad[joint] == pytest.approx(firmware.setpoint_rad[joint],
                                                          abs=0.05)
        assert abs(firmware.voltage_v[joint]) < HAND_YIELD_V
        assert firmware.arm.hand_torque_nm[joint] == 0.0  # pushing nothing
    firmware.set_hand(dict(enumerate(hand)))  # the same targets again (another slider moved)
    assert firmware.arm.hand_torque_nm[1] == 0.0 and firmware.arm.hand_yielding[1]
    # Limp: the resting hand holds the puppet where it is (no drop under gravity).
    there = list(firmware.arm.angle_rad)
    firmware.handle(codec.Opmode(codec.LIMP))
    t, _ = run(firmware, t, 1.0)
    assert max(abs(a - b) for a, b in zip(firmware.arm.angle_rad, there)) < 0.06
    # A new input grips again: the hand moves the limp puppet.
    firmware.set_hand({1: hand[1]})
    run(firmware, t, 1.0)
    assert firmware.arm.angle_rad[1] == pytest.approx(hand[1], abs=0.06)


def test_a_resting_hand_does_not_give_way_to_feels_gentle_pull():
    firmware, t, hand = held_away_resting(voltage_limit_v=2.0)  # feel mode's default limit
    run(firmware, t, 3.0)
    assert abs(firmware.arm.angle_rad[1] - hand[1]) < 0.1
    assert abs(firmware.voltage_v[1]) == pytest.approx(2.0, abs=1e-3)
    assert firmware.arm.hand_torque_nm[1] != 0.0  # the nurse feels the pull


def test_bare_hold_keeps_setpoint_zero_and_drives_toward_it():
    firmware = loaded(pid_kp=20.0)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.Opmode(codec.HOLD))  # no setpoints: the 2020 host's GUI did this
    assert firmware.setpoint_rad == [0.0] * settings.NUM_JOINTS
    t, _ = run(firmware, t, 0.1)
    ticks = firmware.take_control_ticks()
    assert 4 <= len(ticks) <= 6  # 50 Hz, in hold only
    assert ticks[0].setpoint_rad == (0.0,) * settings.NUM_JOINTS
    assert ticks[0].voltage_v[1] == pytest.approx(-7.2)  # joint 1 at 0.5 rad pushed to 0
    assert firmware.take_control_ticks() == []


def test_limp_zeroes_setpoints_and_voltages_and_hold_keeps_setpoints():
    firmware = loaded(pid_kp=5.0)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.JointSetpoint(1, 0.4))
    firmware.handle(codec.Opmode(codec.HOLD))
    assert firmware.setpoint_rad[1] == pytest.approx(0.4)
    firmware.set_hand({1: 0.0})
    t, _ = run(firmware, t, 1.0)
    assert firmware.voltage_v[1] != 0.0
    firmware.handle(codec.Opmode(7))  # any byte but 0x01 is limp
    assert firmware.opmode == codec.LIMP
    assert firmware.voltage_v == [0.0] * settings.NUM_JOINTS
    assert firmware.setpoint_rad == [0.0] * settings.NUM_JOINTS
    firmware.handle(codec.JointSetpoint(2, 0.1))
    firmware.handle(codec.Opmode(codec.HOLD))
    assert firmware.setpoint_rad == [0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0]
    run(firmware, t, 0.5)
    assert firmware.take_control_ticks()
    assert firmware.take_control_ticks() == []


def test_unchecked_fields_never_crash_the_model():
    firmware = PuppetFirmware()
    firmware.configure(9, ID['pid_kp'], 1.0)      # joint out of range: ignored, counted
    firmware.set_setpoint(200, 0.5)
    assert firmware.ignored_frames == 2
    firmware.configure(2, 12, 5.0)                 # config id above 11: ignored
    assert firmware.config[2] == POWER_ON_SETTINGS
    firmware.configure(2, ID['home_angle'], math.nan)
    firmware.configure(4, ID['voltage_max'], math.inf)
    firmware.configure(4, ID['pid_kp'], math.nan)
    firmware.set_opmode(codec.HOLD)
    _, out = run(firmware, 0.0, 0.5)
    assert math.isnan([m for m in states(out) if m.joint == 2][-1].angle_rad)
    assert all(math.isfinite(a) for a in firmware.arm.angle_rad)


def test_operator_buttons_and_grippers():
    firmware = PuppetFirmware()
    _, out = run(firmware, 0.0, 0.15)
    assert [m.reading for m in out if isinstance(m, codec.Gripper)][:4] == [0.0, 0.0, 0.0, 1.0]
    firmware.set_button(2)
    firmware.set_grippers([0.5, 2.0, -1.0, 0.0])
    _, out = run(firmware, 0.15, 0.15)
    assert [m.button for m in out if isinstance(m, codec.Buttons)][-1] == 2
    assert [m.reading for m in out if isinstance(m, codec.Gripper)][-4:] == [0.5, 1.0, 0.0, 0.0]
    with pytest.raises(ValueError):
        firmware.set_button(5)
    with pytest.raises(ValueError):
        firmware.set_grippers([0.5, 0.5])
