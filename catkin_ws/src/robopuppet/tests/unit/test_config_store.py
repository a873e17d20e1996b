"""Config store and config file: defaults, round trip, validation, repairs, atomic writes."""
import math
import os
import signal
import subprocess
import sys
import textwrap

import pytest

from robopuppet import atomic_file, settings
from robopuppet.config import config_file, config_store


def test_defaults_cover_every_joint_and_setting():
    config = config_store.defaults()
    assert sorted(config) == list(range(7))
    for values in config.values():
        assert list(values) == list(settings.NAMES)
        assert values['angle_min'] == pytest.approx(-1.571)
        assert values['voltage_max'] == pytest.approx(7.2)
        assert values['sign_motor'] == 1.0


def test_default_text_parses_back_to_defaults_without_problems():
    config, problems = config_store.parse(config_store.default_text())
    assert problems == []
    assert config == config_store.defaults()


@pytest.mark.parametrize('value', [0.1, -1.571, 7.2, 1e-7, 123456.7, -0.0, 3.14159265])
def test_format_value_round_trips_through_float32(value):
    stored = config_store.to_float32(value)
    assert config_store.to_float32(float(config_store.format_value(stored))) == stored


def test_round_trip_of_changed_values_keeps_comments_and_other_lines():
    text = textwrap.dedent("""\
        # my puppet, tuned 2026-11-01
        [joint_0]
        home_angle = 0.25   ; measured by hand
        angle_min = -1.2
        """)
    config, problems = config_store.parse(text)
    assert config[0]['home_angle'] == pytest.approx(0.25)
    assert any('angle_max: missing' in p for p in problems)
    config[0]['home_angle'] = config_store.to_float32(0.5)
    out = config_store.render(text, config)
    assert out.startswith('# my puppet, tuned 2026-11-01\n[joint_0]\nhome_angle = 0.5   ; measured by hand\n')
    assert 'angle_min = -1.2\n' in out
    reread, problems = config_store.parse(out)
    assert problems == []
    assert reread == config


def test_render_only_touches_the_named_entry():
    text = config_store.default_text().replace('pid_kp = 0', 'pid_kp = 0.000', 1)
    config, _ = config_store.parse(text)
    config[3]['pid_kd'] = 2.0
    out = config_store.render(text, config, only={(3, 'pid_kd')})
    assert 'pid_kp = 0.000' in out  # joint 0's spelling untouched
    changed = [line for line in out.splitlines() if line not in text.splitlines()]
    assert changed == ['pid_kd = 2']


@pytest.mark.parametrize('name, value, message', [
    ('angle_min', float('nan'), 'joint 4 angle_min = nan: not a finite'),
    ('pid_kp', float('inf'), 'joint 4 pid_kp = inf: not a finite'),
    ('pid_kp', 1e39, 'joint 4 pid_kp = 1e+39: not a finite'),
    ('sign_angle', 0.5, 'joint 4 sign_angle = 0.5: a sign must be'),
    ('sign_motor', 0.0, 'joint 4 sign_motor = 0.0: a sign must be'),
    ('angle_min', 2.0, 'joint 4 angle_min = 2.0: above angle_max = 1.571'),
    ('velocity_max', -7.0, 'joint 4 velocity_max = -7.0: below velocity_min = -6.283'),
    ('voltage_min', 7.0, 'joint 4 voltage_min = 7.0: above voltage_max = 6.5'),
    ('velocity_max', -1.0, 'joint 4 velocity_min..velocity_max = -6.283..-1: the range must '
     'hold 0'),
    ('velocity_min', 0.5, 'joint 4 velocity_min..velocity_max = 0.5..6.283: the range must '
     'hold 0'),
    ('no_such_setting', 1.0, "joint 4: unknown setting 'no_such_setting'"),
    ('pid_kp', 'abc', "joint 4 pid_kp = 'abc': not a number"),
])
def test_a_one_setting_request_refuses_bad_values_naming_joint_setting_and_value(
        name, value, message):
    values = config_store.defaults()[4]
    values['voltage_max'] = 6.5
    with pytest.raises(config_store.InvalidSetting) as error:
        config_store.check_request(values, 4, [name], [value])
    assert str(error.value).startswith(message), str(error.value)


@pytest.mark.parametrize('joint', [-1, 7, 9, 255, 1.5])
def test_a_request_for_a_joint_outside_0_to_6_is_refused(joint):
    with pytest.raises(config_store.InvalidSetting, match='valid joints are 0-6'):
        config_store.check_request(config_store.defaults()[0], joint, ['pid_kp'], [1.0])


def test_a_request_returns_all_settings_with_good_values_rounded_to_float32():
    values = config_store.defaults()[0]
    result = config_store.check_request(values, 0, ['sign_angle', 'angle_max', 'pid_kp'],
                                        [-1, 1.571, 0.1])
    assert result == dict(values, sign_angle=-1.0, pid_kp=config_store.to_float32(0.1))
    assert values == config_store.defaults()[0], 'the stored values are not changed in place'


@pytest.mark.parametrize('text, problem', [
    ('', 'not an ini file'),
    ('\x00\x01garbage that is no ini\n', 'not an ini file'),
    ('[joint_0]\npid_kp = 1.0\n', '[joint_1] missing section'),
    ('[joint_0]\npid_kp = fast\n', "pid_kp = 'fast': not a number"),
    ('[joint_0]\nsign_angle = 2\n', 'sign_angle = 2: invalid'),
    ('[joint_0]\npid_ki = nan\n', 'pid_ki = nan: invalid'),
    ('[joint_0]\nangle_min = 1\nangle_max = 0.5\n', 'angle_min = 1: above angle_max = 0.5'),
])
def test_parse_reports_and_repairs_malformed_text(text, problem):
    config, problems = config_store.parse(text)
    assert any(problem in p for p in problems), problems
    assert config[0]['sign_angle'] in (1.0, -1.0)
    for joint, values in config.items():
        for low, high in settings.RANGE_PAIRS:
            assert values[low] <= values[high]
        assert all(math.isfinite(v) for v in values.values())


def test_parse_keeps_good_entries_beside_broken_ones():
    config, _ = config_store.parse('[joint_2]\npid_kp = 3.5\npid_kd = oops\n')
    assert config[2]['pid_kp'] == 3.5
    assert config[2]['pid_kd'] == 0.0


def test_half_written_file_is_repaired_with_backup(tmp_path):
    path = tmp_path / 'arm_R.ini'
    full = config_store.default_text().replace('pid_kp = 0', 'pid_kp = 4', 1)
    torn = full[:full.index('[joint_2]') + 40]  # cut in the middle of joint 2
    path.write_text(torn)
    config, text, notes, problems, unwritable = config_file.load_or_create(str(path), '', 'stamp')
    assert unwritable == ''
    assert config[0]['pid_kp'] == 4.0
    assert any('[joint_6] missing section' in p for p in problems)
    assert all(p.startswith(str(path)) for p in problems)
    backup = tmp_path / 'arm_R.ini.bak-stamp'
    assert backup.read_text() == torn
    assert any(str(backup) in n for n in notes)
    assert config_store.parse(path.read_text()) == (config, [])


def test_missing_file_is_created_from_seed(tmp_path):
    seed = tmp_path / 'seed.ini'
    seed.write_text(config_store.default_text().replace('sign_motor = 1', 'sign_motor = -1'))
    path = tmp_path / 'home' / 'arm_L.ini'
    config, _, notes, problems, _ = config_file.load_or_create(str(path), str(seed), 'x')
    assert problems == []
    assert config[6]['sign_motor'] == -1.0
    assert path.read_text() == seed.read_text()
    assert notes == ['created %s from %s' % (path, seed)]


def test_missing_file_without_seed_gets_defaults(tmp_path):
    path = tmp_path / 'arm_L.ini'
    config, _, _, problems, _ = config_file.load_or_create(str(path), '', 'x')
    assert problems == [] and config == config_store.defaults()
    assert config_store.parse(path.read_text()) == (config, [])


def test_resolve_path_puts_relative_names_under_ros_home():
    assert config_file.resolve_path('arm_R.ini', '/h/.ros') == '/h/.ros/robopuppet/arm_R.ini'
    assert config_file.resolve_path('/etc/x.ini', '/h/.ros') == '/etc/x.ini'


def test_kill_during_writes_never_leaves_a_torn_file(tmp_path):
    """SIGKILL a process that rewrites the file as fast as it can: the file is always whole."""
    path = tmp_path / 'arm_R.ini'
    writer = textwrap.dedent("""\
        import sys
        from robopuppet import atomic_file
        from robopuppet.config import config_store
        config = config_store.defaults()
        i = 0
        while True:
            i += 1
            config[i % 7]['pid_kp'] = float(i % 9000)  # within the gain bound
            atomic_file.write_atomic(sys.argv[1], config_store.render('', config))
            if i == 20:
                print('writing', flush=True)
        """)
    for attempt in range(5):
        proc = subprocess.Popen([sys.executable, '-c', writer, str(path)],
                                stdout=subprocess.PIPE, env=os.environ)
        assert proc.stdout.readline() == b'writing\n'
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        proc.stdout.close()
        config, problems = config_store.parse(path.read_text())
        assert problems == [], 'attempt %d left a torn file' % attempt
        assert max(values['pid_kp'] for values in config.values()) >= 14
    # The next start tidies what the kills left: the file itself stays as it is.
    before = path.read_text()
    notes = config_file.load_or_create(str(path), '', 'x').notes
    assert path.read_text() == before
    assert sorted(os.listdir(tmp_path)) == ['arm_R.ini']
    assert all('interrupted write' in note for note in notes)


@pytest.mark.parametrize('value, text', [(10.0, '10'), (20.0, '20'), (0.0, '0'), (-1.0, '-1'),
                                         (0.1, '0.1'), (-1.571, '-1.571'), (7.2, '7.2')])
def test_format_value_is_plain_decimal(value, text):
    assert config_store.format_value(config_store.to_float32(value)) == text


def test_repeated_entries_are_reported_and_the_first_one_wins_everywhere():
    text = config_store.default_text().replace(
        '[joint_1]\n', '[joint_1]\npid_kp = 5\npid_kp = 9\n', 1) + '[joint_1]\npid_kd = 7\n'
    config, problems = config_store.parse(text)
    assert config[1]['pid_kp'] == 5.0 and config[1]['pid_kd'] == 0.0
    assert any('repeated option pid_kp in [joint_1]' in p for p in problems)
    assert any('repeated section [joint_1]' in p for p in problems)
    config[1]['pid_kp'] = 6.0
    config[1]['pid_kd'] = 3.0
    out = config_store.render(text, config, only={(1, 'pid_kp'), (1, 'pid_kd')})
    reread, _ = config_store.parse(out)
    assert reread[1]['pid_kp'] == 6.0 and reread[1]['pid_kd'] == 3.0, \
        'a saved change survives a restart'


def test_temporaries_of_an_interrupted_write_are_removed_at_start(tmp_path):
    path = tmp_path / 'arm_R.ini'
    path.write_text(config_store.default_text())
    (tmp_path / '.arm_R.ini.k3j2.tmp').write_text('[joint_0]\npid_')
    (tmp_path / '.arm_L.ini.k3j2.tmp').write_text('not ours')
    _, _, notes, problems, _ = config_file.load_or_create(str(path), '', 'x')
    assert problems == []
    assert sorted(os.listdir(tmp_path)) == ['.arm_L.ini.k3j2.tmp', 'arm_R.ini']
    assert notes == ['removed %s, left by an interrupted write' % (tmp_path / '.arm_R.ini.k3j2.tmp')]
