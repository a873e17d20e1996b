"""Unit tests of the GUI's pure parts: ArmState buffers, the settings form checks, plot series."""
import math

import numpy as np
import pytest

from robopuppet import interface, settings
from robopuppet.config import config_store
from robopuppet.arm.joint_motion import mirror
from robopuppet.gui import settings_form, state, tracking
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
    arm.on_teleop(state.Teleop(interface.FOLLOWING, True, False, interface.HOLD, 0.2, '', '', '',
                               5.0))
    arm.on_button(3)
    arm.on_button(0)
    snap = arm.snapshot()
    assert snap.opmode == interface.HOLD and snap.teleop.follow_left
    assert (snap.button, snap.last_button) == (0, 3)


def test_feel_latches_angles_as_setpoints_like_hold():
    arm = state.ArmState()
    arm.on_opmode(interface.LIMP, 0.0)
    arm.on_angle(4, -0.3, 1.0)
    arm.on_opmode(interface.FEEL, 2.0)
    snap = arm.snapshot()
    assert snap.opmode == interface.FEEL and snap.joints[4].setpoint_rad == -0.3
    arm.on_opmode(interface.LIMP, 3.0)
    assert math.isnan(arm.snapshot().joints[4].setpoint_rad)


BAXTER_NAMES = ['head_pan'] + ['%s_%s' % (side, j) for side in ('left', 'right')
                               for j in ('s0', 's1', 'e0', 'e1', 'w0', 'w1', 'w2')]


def test_robot_joints_are_kept_per_arm_in_puppet_order_by_name():
    arm = state.ArmState()
    assert arm.snapshot().baxter is None
    names = list(reversed(BAXTER_NAMES))  # Baxter's order is its own: match by name
    positions = [float(BAXTER_NAMES.index(n)) for n in names]
    arm.on_robot_joints(names, positions, 7.0)
    baxter = arm.snapshot().baxter
    assert baxter.received_s == 7.0
    assert baxter.poses == {'left': tuple(float(i) for i in range(1, 8)),
                            'right': tuple(float(i) for i in range(8, 15))}
    arm.on_robot_joints(['left_s0'], [9.0], 8.0)  # an incomplete arm changes nothing
    assert arm.snapshot().baxter.poses['left'][0] == 1.0


PUPPET = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]
BAXTER = {'left': [0.15, 0.2, -0.3, 0.6, 0.5, 0.3, -0.7], 'right': [0.1, 0.25, 0.3, 0.4, 0.5, 0.6,
                                                                   0.9]}


@pytest.mark.parametrize('puppet_side, follow_left, follow_right, arm', [
    ('R', False, True, 'right'), ('R', True, False, 'left'), ('R', True, True, 'right'),
    ('R', False, False, 'right'), ('L', True, True, 'left'), ('L', False, True, 'right')])
def test_the_driven_arm_is_the_only_follower_else_the_own_side(puppet_side, follow_left,
                                                              follow_right, arm):
    assert tracking.driven_arm(puppet_side, follow_left, follow_right) == arm


def test_own_side_is_compared_as_is_and_the_other_side_mirrored():
    own = tracking.tracking('R', 'right', BAXTER, PUPPET)
    assert not own.mirrored and own.baxter_rad == BAXTER['right']
    assert own.error_rad == pytest.approx([0.0, -0.05, 0.0, 0.0, 0.0, 0.0, -0.2])
    other = tracking.tracking('R', 'left', BAXTER, PUPPET)
    assert other.mirrored and other.baxter_rad == mirror(BAXTER['left'])
    # joints 0, 2, 4, 6 of the left arm negated: puppet 0.3 vs 0.3 is no error at joint 2
    assert other.error_rad == pytest.approx([0.25, 0.0, 0.0, -0.2, 1.0, 0.3, 0.0])
    assert tracking.largest_error(other) == (4, pytest.approx(1.0))
    assert tracking.tracking('L', 'left', {'right': BAXTER['right']}, PUPPET) is None


@pytest.mark.parametrize('error, level', [(0.0, tracking.SMALL), (-0.049, tracking.SMALL),
                                          (0.05, tracking.MEDIUM), (-0.19, tracking.MEDIUM),
                                          (0.2, tracking.LARGE), (-1.0, tracking.LARGE),
                                          (math.nan, None)])
def test_error_levels(error, level):
    assert tracking.error_level(error) == level


def test_a_lag_is_an_error_that_stays_large():
    watch = tracking.LagWatch()
    assert not watch.update(10.0, True)
    assert not watch.update(10.5, True)
    assert watch.update(11.0, True)
    assert not watch.update(11.1, False)      # caught up: start over
    assert not watch.update(11.2, True) and not watch.update(12.1, True)
    assert watch.update(12.2, True)
    assert not watch.update(20.0, True)       # a gap (tab hidden) starts over too


def teleop(follow_left=False, follow_right=True, zone_left='', zone_right=''):
    return state.Teleop(interface.FOLLOWING, follow_left, follow_right, interface.FEEL, 0.1, '',
                        zone_left, zone_right, 1.0)


def test_the_line_names_the_zone_before_a_lag():
    line = tracking.status_line(teleop(zone_right='patient head'), {'right': (3, 0.5)}, True)
    assert line == ("keep-out zone 'patient head' holds back Baxter's right arm", tracking.ZONE)
    both = tracking.status_line(teleop(True, True, 'bed', 'patient head'), {}, True).text
    assert "'bed' holds back Baxter's left arm" in both and "'patient head'" in both
    assert tracking.status_line(teleop(True, True, 'bed', 'bed'), {}, True).text == \
        "keep-out zone 'bed' holds back Baxter's arms"
    lags = tracking.status_line(teleop(), {'right': (3, -0.456)}, True)
    assert lags == ('Baxter lags: right arm, joint 3 off by -0.46 rad', tracking.LAGS)
    assert tracking.status_line(teleop(), {}, True).level == tracking.TRACKS
    assert 'unknown' in tracking.status_line(teleop(), {}, False).text
    assert tracking.status_line(teleop(False, False), {}, True).level == tracking.IDLE
    assert tracking.status_line(None, {}, True).level == tracking.IDLE


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
