"""Unit tests of the GUI's pure parts: ArmState buffers, the settings form checks, plot series."""
import math

import numpy as np
import pytest

from robopuppet import interface, settings
from robopuppet.config import config_store
from robopuppet.gui import settings_form, state
from robopuppet.gui.live_plot import Series


def test_drain_returns_new_points_once_in_order():
    arm = state.ArmState()
    arm.on_angle(2, 0.1, 10.0)
    arm.on_angle(2, 0.2, 10.1)
    arm.on_voltage(2, 3.0, 10.1)
    points = arm.drain()
    assert points[('angle', 2)] == [(10.0, 0.1), (10.1, 0.2)]
    assert points[('voltage', 2)] == [(10.1, 3.0)]
    assert ('angle', 3) not in points
    assert arm.drain() == {}
    assert arm.snapshot().joints[2].angle_rad == 0.2


def test_buffers_are_bounded_and_keep_the_newest():
    arm = state.ArmState(capacity=5)
    for i in range(100):
        arm.on_angle(0, float(i), float(i))
    assert arm.drain()[('angle', 0)] == [(float(i), float(i)) for i in range(95, 100)]


def test_hold_latches_angles_as_setpoints_and_limp_ends_them():
    arm = state.ArmState()
    arm.on_angle(1, 0.5, 1.0)
    arm.on_opmode(interface.HOLD, 2.0)
    assert arm.snapshot().joints[1].setpoint_rad == 0.5
    arm.on_setpoint(1, 0.7, 3.0)
    arm.on_opmode(interface.HOLD, 3.5)  # repeated: no new latch
    assert arm.snapshot().joints[1].setpoint_rad == 0.7
    arm.on_opmode(interface.LIMP, 4.0)
    assert math.isnan(arm.snapshot().joints[1].setpoint_rad)
    setpoints = arm.drain()[('setpoint', 1)]
    assert setpoints[:2] == [(2.0, 0.5), (3.0, 0.7)]
    assert setpoints[2][0] == 4.0 and math.isnan(setpoints[2][1])


def test_hold_keeps_setpoints_sent_before_it_since_the_last_limp():
    arm = state.ArmState()
    arm.on_opmode(interface.LIMP, 0.0)
    arm.on_angle(2, 0.5, 1.0)
    arm.on_angle(3, -0.4, 1.0)
    arm.on_setpoint(2, 1.2, 1.5)  # arm_X sends Baxter's pose, then hold
    arm.on_opmode(interface.HOLD, 2.0)
    joints = arm.snapshot().joints
    assert joints[2].setpoint_rad == 1.2 and joints[3].setpoint_rad == -0.4
    arm.on_opmode(interface.LIMP, 3.0)
    arm.on_opmode(interface.HOLD, 4.0)  # no setpoint since that limp: the angle again
    assert arm.snapshot().joints[2].setpoint_rad == 0.5


def test_bad_input_is_refused_and_changes_nothing():
    arm = state.ArmState()
    arm.on_opmode(interface.LIMP, 0.0)
    with pytest.raises(ValueError):
        arm.on_opmode('floppy', 1.0)
    with pytest.raises(ValueError):
        arm.on_angle(7, 0.0, 1.0)
    with pytest.raises(ValueError):
        arm.on_gripper(4, 0.5)
    snap = arm.snapshot()
    assert snap.opmode == interface.LIMP
    assert all(math.isnan(j.angle_rad) for j in snap.joints)


def test_teleop_opmode_updates_the_opmode_and_buttons_remember_the_last_press():
    arm = state.ArmState()
    arm.on_teleop(state.Teleop(interface.FOLLOWING, True, False, interface.HOLD, 0.2, '', 5.0))
    arm.on_button(3)
    arm.on_button(0)
    snap = arm.snapshot()
    assert snap.opmode == interface.HOLD and snap.teleop.follow_left
    assert (snap.button, snap.last_button) == (0, 3)


def test_heartbeat_age():
    arm = state.ArmState()
    assert state.heartbeat_age(arm.snapshot(), 5.0) is None
    arm.on_heartbeat(3.0)
    assert state.heartbeat_age(arm.snapshot(), 5.5) == pytest.approx(2.5)


def form(**changes):
    texts = {name: config_store.format_value(value) for name, value in settings.DEFAULTS.items()}
    texts.update(changes)
    return texts


def test_form_accepts_the_defaults_and_rounds_to_float32():
    values = settings_form.parse_form(0, form(pid_kp=' 0.1 '))
    assert values['pid_kp'] == config_store.to_float32(0.1)
    assert values['angle_min'] == config_store.to_float32(-1.571)


@pytest.mark.parametrize('field, text, words', [
    ('pid_kp', 'abc', 'not a number'),
    ('pid_ki', '', 'not a number'),
    ('home_angle', 'nan', 'finite'),
    ('velocity_max', '1e50', 'finite'),
    ('sign_motor', '0.5', 'sign'),
    ('angle_min', '2', 'above angle_max'),
])
def test_form_refuses_bad_entries_naming_the_setting(field, text, words):
    with pytest.raises(settings_form.EntryError) as error:
        settings_form.parse_form(3, form(**{field: text}))
    assert field in str(error.value) and words in str(error.value)


@pytest.mark.parametrize('value, text', [(10.0, '10'), (0.0, '0'), (-1.0, '-1'),
                                         (config_store.to_float32(1.571), '1.571'),
                                         (config_store.to_float32(-7.2), '-7.2'),
                                         (config_store.to_float32(1e-5), '1e-05')])
def test_field_text_is_plain_and_reads_back_exactly(value, text):
    assert settings_form.field_text(value) == text
    assert config_store.to_float32(float(text)) == value


def test_setpoint_entry():
    stored = {'angle_min': -1.0, 'angle_max': 1.0}
    assert settings_form.parse_setpoint(' 0.5', stored) == 0.5
    assert settings_form.parse_setpoint('3', None) == 3.0
    for text in ('x', 'inf', '1.5'):
        with pytest.raises(settings_form.EntryError):
            settings_form.parse_setpoint(text, stored)


def test_series_keeps_the_window_and_one_point_before_it():
    series = Series(window_s=2.0, capacity=100)
    series.extend([(t / 10, t) for t in range(50)])  # 0.0 .. 4.9 s
    times, values = series.relative(4.9)
    assert times[-1] == 0.0 and values[-1] == 49
    assert times[0] < -2.0 <= times[1]
    series.extend([])
    assert len(series.values) == len(values)


def test_series_capacity_and_steps():
    series = Series(window_s=100.0, capacity=3)
    series.extend([(1.0, 10.0), (2.0, 20.0), (3.0, 30.0), (4.0, 40.0)])
    assert list(series.values) == [20.0, 30.0, 40.0]
    times, values = series.steps(5.0)
    assert np.allclose(times, [-3, -2, -2, -1, -1, 0])
    assert list(values) == [20.0, 20.0, 30.0, 30.0, 40.0, 40.0]
