"""Unit tests of robopuppet.puppet_model: the simulated firmware and arm."""
import math

import pytest

from robopuppet import codec, settings
from robopuppet.puppet_model import PuppetFirmware, REST_POSE_RAD, QUAD_JOINTS

ID = settings.CONFIG_ID


def run(firmware, start_s, seconds, step_s=0.01):
    """Advance firmware from start_s for seconds; return (end time, all messages sent)."""
    out = []
    t = start_s
    while t < start_s + seconds - 1e-9:
        t += step_s
        out.extend(firmware.advance(t))
    return t, out


def states(messages):
    return [m for m in messages if isinstance(m, codec.JointState)]


def configure(firmware, joint, **values):
    for name, value in values.items():
        firmware.handle(codec.JointConfig(joint, ID[name], value))


def test_heartbeat_1hz_and_state_sets_at_the_state_rate_in_order():
    firmware = PuppetFirmware(state_rate_hz=20.0)
    _, out = run(firmware, 0.0, 3.0)
    assert sum(isinstance(m, codec.Heartbeat) for m in out) in (3, 4)
    sets = [out[i:i + 12] for i, m in enumerate(out)
            if isinstance(m, codec.JointState) and m.joint == 0]
    assert 59 <= len(sets) <= 61
    assert [type(m) for m in sets[1]] == [codec.JointState] * 7 + [codec.Gripper] * 4 + \
        [codec.Buttons]
    assert [m.joint for m in sets[1][:7]] == list(settings.JOINTS)


def test_rest_pose_quad_joints_uncalibrated_until_index_then_mechanical_angle():
    firmware = PuppetFirmware()
    t, out = run(firmware, 0.0, 0.5)
    last = {m.joint: m for m in states(out)}
    for joint in settings.JOINTS:
        expected = codec.UNCALIBRATED if joint in QUAD_JOINTS else codec.WORKING
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
    configure(firmware, 1, home_angle=0.25, sign_angle=-1.0)
    t, out = run(firmware, 0.0, 0.5)
    joint1 = [m for m in states(out) if m.joint == 1][-1]
    assert joint1.angle_rad == pytest.approx(0.25 - REST_POSE_RAD[1], abs=0.05)


def test_angle_clamp_and_rate_limit():
    firmware = PuppetFirmware()
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
    firmware = PuppetFirmware()
    for joint in settings.JOINTS:
        configure(firmware, joint, pid_kp=kp, pid_ki=kp / 2, pid_kd=kp / 20)
    t, _ = run(firmware, 0.0, 0.3)
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
    firmware = PuppetFirmware()
    configure(firmware, 3, pid_kp=20.0, pid_ki=10.0, pid_kd=1.0, angle_max=1.2)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.Opmode(codec.HOLD))
    firmware.set_hand({3: None})
    firmware.handle(codec.JointSetpoint(3, 3.0))
    assert firmware.setpoint_rad[3] == 1.2
    _, out = run(firmware, t, 3.0)
    assert [m for m in states(out) if m.joint == 3][-1].angle_rad == pytest.approx(1.2, abs=0.05)


def test_firm_hand_wins_against_hold():
    firmware = PuppetFirmware()
    configure(firmware, 1, pid_kp=20.0, pid_ki=10.0)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.Opmode(codec.HOLD))
    firmware.set_hand({1: -0.5})
    _, out = run(firmware, t, 3.0)
    last = [m for m in states(out) if m.joint == 1][-1]
    assert last.angle_rad == pytest.approx(-0.5, abs=0.15)
    assert last.voltage_v == pytest.approx(7.2, abs=1e-3)  # the motor pushes back, saturated


def test_limp_zeroes_voltage_and_hold_latches_current_angles():
    firmware = PuppetFirmware()
    configure(firmware, 1, pid_kp=5.0)
    t, _ = run(firmware, 0.0, 0.3)
    firmware.handle(codec.Opmode(codec.HOLD))
    assert firmware.setpoint_rad == firmware.angle_rad
    firmware.set_hand({1: 0.0})
    t, _ = run(firmware, t, 1.0)
    assert firmware.voltage_v[1] != 0.0
    firmware.handle(codec.Opmode(codec.LIMP))
    assert firmware.voltage_v == [0.0] * settings.NUM_JOINTS


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
