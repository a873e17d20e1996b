"""Plausibility bounds of the joint settings: what the hardware can take."""
import math
import os

import pytest

from robopuppet import settings
from robopuppet.config import config_store
from robopuppet.gui import settings_form
from robopuppet.protocol.device_settings import DeviceSettings

CONFIG_DIR = os.path.join(os.path.dirname(__file__), '..', '..', 'config')


def test_every_setting_has_a_bound_that_holds_its_default_and_says_where_it_comes_from():
    for setting in settings.SETTINGS:
        assert setting.low < setting.high
        assert setting.low <= setting.default <= setting.high, setting.name
        assert setting.bound_source.strip(), setting.name


@pytest.mark.parametrize('name', ['arm_L.ini', 'arm_R.ini'])
def test_the_shipped_files_are_within_the_bounds(name):
    with open(os.path.join(CONFIG_DIR, name)) as ini:
        _, problems = config_store.parse(ini.read())
    assert problems == []


@pytest.mark.parametrize('name, value, bound', [
    ('voltage_max', 1e20, '[-7.2, 7.2] V (the 7.2 V motor supply)'),
    ('voltage_min', -7.5, '[-7.2, 7.2] V'),
    ('pid_kp', 3.4e38, '[0, 10000] V/rad'),
    ('pid_kp', -1.0, '[0, 10000] V/rad'),
    ('pid_ki', 1e5, '[0, 10000] V/(rad*s)'),
    ('pid_kd', -0.5, '[0, 10000] V/(rad/s)'),
    ('angle_max', 3.2, '[-3.1415927, 3.1415927] rad'),
    ('angle_min', -4.0, '[-3.1415927, 3.1415927] rad'),
    ('home_angle', 7.0, '[-6.2831855, 6.2831855] rad'),
    ('velocity_max', 13.0, '[-12.566371, 12.566371] rad/s'),
    ('velocity_min', -100.0, '[-12.566371, 12.566371] rad/s'),
])
def test_a_value_outside_its_bound_is_refused_naming_joint_setting_value_and_bound(
        name, value, bound):
    with pytest.raises(config_store.InvalidSetting) as error:
        config_store.check_request(config_store.defaults()[5], 5, [name], [value])
    message = str(error.value)
    assert message.startswith('joint 5 %s = %r: outside its bound' % (name, value)), message
    assert bound in message


@pytest.mark.parametrize('name, value', [
    ('angle_max', math.pi), ('angle_min', -math.pi), ('home_angle', -2 * math.pi),
    ('voltage_max', 7.2), ('voltage_min', -7.2), ('pid_kp', 1e4), ('pid_kd', 0.0),
    ('velocity_max', 4 * math.pi), ('sign_motor', -1.0),
])
def test_a_value_on_its_bound_is_accepted(name, value):
    stored = config_store.check_request(config_store.defaults()[0], 0, [name], [value])
    assert stored[name] == config_store.to_float32(value)


def test_an_out_of_bound_value_in_the_file_is_repaired_like_a_damaged_entry():
    text = config_store.default_text().replace('voltage_max = 7.2', 'voltage_max = 1e20', 1)
    text = text.replace('pid_kp = 0', 'pid_kp = 3.4e38', 1)
    config, problems = config_store.parse(text)
    assert config == config_store.defaults()
    assert any(p.startswith('[joint_0] voltage_max = 1e20: invalid (outside its bound')
               and p.endswith('using default 7.2') for p in problems), problems
    assert any(p.startswith('[joint_0] pid_kp = 3.4e38: invalid') for p in problems), problems
    repaired = config_store.render(text, config)
    assert config_store.parse(repaired) == (config, []) and '1e20' not in repaired


def test_the_gui_refuses_what_the_config_node_refuses():
    texts = {name: config_store.format_value(value) for name, value in settings.DEFAULTS.items()}
    texts.update(voltage_max='1e20', pid_kp='3.4e38')
    with pytest.raises(settings_form.EntryError) as error:
        settings_form.parse_form(2, texts)
    # The same problems as config_X's, each shown beside its field (without 'joint 2 ').
    fields = error.value.by_field()
    assert set(fields) == {'voltage_max', 'pid_kp'}
    assert 'outside its bound' in fields['voltage_max'][0]
    assert 'outside its bound' in fields['pid_kp'][0]



@pytest.mark.parametrize('changes, why', [
    ({'angle_min': 1.5, 'angle_max': 0.5}, 'angle_min = 1.5: above angle_max = 0.5'),
    ({'velocity_min': 0.5}, 'velocity_min..velocity_max = 0.5..6.283: the range must hold 0 ('),
])
def test_a_broken_range_reads_the_same_from_the_config_node_the_file_and_the_serial_node(
        changes, why):
    stored = config_store.defaults()
    with pytest.raises(config_store.InvalidSetting) as error:
        config_store.check_request(stored[2], 2, list(changes), list(changes.values()))
    assert str(error.value).startswith('joint 2 ' + why)
    broken = {**stored, 2: dict(stored[2], **changes)}
    _, problems = config_store.parse(config_store.render('', broken))
    assert len(problems) == 1 and problems[0].startswith('[joint_2] ' + why)
    warnings = []
    DeviceSettings(None, None, None, warnings.append, 'active').on_stored(1, broken.items())
    assert ('joint 2 ' + why) in warnings[0]
