"""Unit tests of feel mode's settings: the [feel] section of the ini file and the gentle gains
config_X lays over the stored joint settings (robopuppet.config.feel_profile, config_store)."""
import pytest

from robopuppet import settings
from robopuppet.config import config_file, config_store, feel_profile
from robopuppet.float32 import to_float32

DEFAULT_FEEL = {'gain_scale': 0.25, 'voltage_limit': 2.0}


def joint(**changes):
    return dict(config_store.defaults()[0], **changes)


def test_feel_gains_scale_kp_and_kd_zero_ki_and_clip_the_voltage():
    stored = joint(pid_kp=20.0, pid_ki=10.0, pid_kd=1.0, voltage_min=-7.2, voltage_max=7.2,
                   angle_min=-1.0, home_angle=0.5)
    active = feel_profile.feel_joint(stored, {'gain_scale': 0.25, 'voltage_limit': 2.0})
    assert (active['pid_kp'], active['pid_ki'], active['pid_kd']) == (5.0, 0.0, 0.25)
    assert (active['voltage_min'], active['voltage_max']) == (-2.0, 2.0)
    unchanged = set(settings.NAMES) - {'pid_kp', 'pid_ki', 'pid_kd', 'voltage_min', 'voltage_max'}
    assert {n: active[n] for n in unchanged} == {n: stored[n] for n in unchanged}
    assert stored['pid_kp'] == 20.0, 'the stored settings are not changed'


def test_a_stored_voltage_range_inside_the_limit_is_kept_and_one_outside_it_collapses():
    feel = {'gain_scale': 0.5, 'voltage_limit': 3.0}
    active = feel_profile.feel_joint(joint(voltage_min=-1.0, voltage_max=2.5), feel)
    assert (active['voltage_min'], active['voltage_max']) == (-1.0, 2.5)
    active = feel_profile.feel_joint(joint(voltage_min=4.0, voltage_max=6.0), feel)
    assert (active['voltage_min'], active['voltage_max']) == (3.0, 3.0)  # min <= max still
    active = feel_profile.feel_joint(joint(pid_kp=0.1, pid_kd=0.3), feel)
    assert (active['pid_kp'], active['pid_kd']) == (to_float32(0.05), to_float32(0.15))


def test_the_feel_profile_stays_within_what_the_config_node_would_store():
    stored = joint(pid_kp=settings.MAX_GAIN, pid_kd=settings.MAX_GAIN)
    active = feel_profile.feel_joint(stored, {'gain_scale': 1.0,
                                              'voltage_limit': settings.MOTOR_SUPPLY_V})
    assert config_store.check_request(stored, 0, list(active), list(active.values())) == active


def test_the_profiles():
    joints = [joint(pid_kp=float(j)) for j in settings.JOINTS]
    assert feel_profile.active_joints('', joints, DEFAULT_FEEL) == joints
    assert [v['pid_kp'] for v in feel_profile.active_joints('feel', joints, DEFAULT_FEEL)] == [
        j * 0.25 for j in settings.JOINTS]
    with pytest.raises(ValueError):
        feel_profile.active_joints('stiff', joints, DEFAULT_FEEL)


def test_a_file_without_a_feel_section_gets_the_defaults_and_no_problem():
    text = config_store.default_text()
    old = text[:text.index('# Feel mode')]  # a file from before feel mode
    assert '[feel]' not in old
    assert config_store.parse_feel(old) == (DEFAULT_FEEL, [])
    config, problems = config_store.parse(old)
    assert problems == []
    new = config_store.render(old, config)
    assert '[feel]\ngain_scale = 0.25\nvoltage_limit = 2\n' in new, new
    assert config_store.parse(new) == (config, [])
    assert new == config_store.render(old, config, only={(0, 'pid_kp')}), 'on the next save'


def test_feel_values_are_read_and_written_back_as_they_are():
    text = config_store.default_text().replace('gain_scale = 0.25', 'gain_scale = 0.5  ; firm')
    assert config_store.parse_feel(text) == ({'gain_scale': 0.5, 'voltage_limit': 2.0}, [])
    config = config_store.parse(text)[0]
    config[3]['pid_kp'] = 7.0
    new = config_store.render(text, config, only={(3, 'pid_kp')})
    assert 'gain_scale = 0.5  ; firm' in new
    assert config_store.render(text, config) == new


@pytest.mark.parametrize('line, words', [
    ('gain_scale = 0', 'gain_scale = 0: invalid (outside its bound (0, 1])'),
    ('gain_scale = 1.5', 'gain_scale = 1.5: invalid (outside its bound (0, 1])'),
    ('gain_scale = nan', 'gain_scale = nan: invalid (outside its bound (0, 1])'),
    ('gain_scale = soft', "gain_scale = soft: invalid (not a number)"),
    # Not above the motors' 7.2 V supply: a limit of 12 V would read as a bound and be none.
    ('voltage_limit = 12', 'voltage_limit = 12: invalid (outside its bound (0, 7.2] V)'),
    ('voltage_limit = 7.3', 'voltage_limit = 7.3: invalid (outside its bound (0, 7.2] V)'),
    ('voltage_limit = -2', 'voltage_limit = -2: invalid (outside its bound (0, 7.2] V)'),
])
def test_a_bad_feel_value_is_a_problem_the_default_and_repaired(line, words):
    name = line.split()[0]
    text = config_store.default_text()
    good = '%s = %s' % (name, {'gain_scale': '0.25', 'voltage_limit': '2'}[name])
    bad = text.replace(good, line)
    assert bad != text
    feel, problems = config_store.parse_feel(bad)
    assert feel == DEFAULT_FEEL
    assert len(problems) == 1 and '[feel] ' + words in problems[0], problems
    config, file_problems = config_store.parse(bad)
    assert file_problems == problems, 'the load repairs the file for it'
    assert config_store.render(bad, config) == text


def test_feel_lines_never_become_joint_settings_and_vice_versa():
    text = config_store.default_text().replace(
        'voltage_limit = 2', 'voltage_limit = 2\npid_kp = 1')
    config, problems = config_store.parse(text)
    assert problems == ['[feel] pid_kp: unknown option ignored']
    assert config == config_store.defaults()
    assert 'pid_kp = 1\n' not in config_store.render(text, config).split('[feel]')[1]
    text = config_store.default_text().replace('[joint_2]\n', '[joint_2]\ngain_scale = 0.9\n')
    assert config_store.parse(text)[1] == ['[joint_2] gain_scale: unknown option ignored']
    assert config_store.parse_feel(text)[0] == DEFAULT_FEEL


def test_the_file_is_repaired_for_a_bad_feel_value_and_left_alone_without_a_section(tmp_path):
    path = tmp_path / 'arm_L.ini'
    good = config_store.default_text()
    path.write_text(good.replace('voltage_limit = 2', 'voltage_limit = 20'))
    loaded = config_file.load_or_create(str(path), '', 'stamp')
    assert loaded.problems == ['%s: [feel] voltage_limit = 20: invalid (outside its bound '
                               '(0, 7.2] V), using default 2' % path]
    assert path.read_text() == loaded.text == good
    assert (tmp_path / 'arm_L.ini.bak-stamp').exists()
    old = good[:good.index('# Feel mode')]
    path.write_text(old)
    loaded = config_file.load_or_create(str(path), '', 'stamp2')
    assert (loaded.problems, loaded.notes, path.read_text()) == ([], [], old)
    assert config_store.parse_feel(loaded.text)[0] == DEFAULT_FEEL
