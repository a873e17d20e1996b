"""Config file hardening: a repair is clean once; an unwritable file or a full disk leaves the
settings readable, the file as it was and nothing half-written beside it."""
import errno
import os
import random
import shutil
import sys
import textwrap

import pytest

from robopuppet.config import config_file, config_store

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..',
                                'integration'))
from tmpfs_testing import tmpfs  # noqa: E402  (shared with the config rostests)

DAMAGED = textwrap.dedent("""\
    # my puppet, tuned by hand
    stray = 1
    [joint_0]
    home_angle = 0.25   ; measured by hand
    pid_kp = 12
    pid_kp = 99
    colour = blue
    [joint_1]
    # joint 1 keeps its own comment
    pid_kd = 0.5
    angle_max = 1.2
    [bogus]
    # a comment of an unknown section
    pid_kp = 5
    [joint_0]
    pid_ki = 3
    [joint_2]
    voltage_max = 1e20
    pid_kp = 3.4e38
    [joint_3]
    angle_min = -1.0
    pid_
    \x00\x01 garbage
    [joint_4
    """)


def test_a_repair_is_clean_once_and_keeps_the_comments_of_intact_entries():
    config, problems = config_store.parse(DAMAGED)
    assert len(problems) >= 9, problems
    repaired = config_store.render(DAMAGED, config)
    assert config_store.parse(repaired) == (config, []), 'the repaired text needs no repair'
    assert config_store.render(repaired, config) == repaired, 'a second repair changes nothing'
    for kept in ('# my puppet, tuned by hand', 'home_angle = 0.25   ; measured by hand',
                 '# joint 1 keeps its own comment', 'pid_kd = 0.5', 'angle_max = 1.2',
                 'angle_min = -1'):
        assert kept in repaired.splitlines(), kept
    for dropped in ('stray', 'pid_kp = 99', 'colour', '[bogus]', 'unknown section', 'pid_ki = 3',
                    'pid_\n', 'garbage', '[joint_4\n', '1e20', '3.4e38'):
        assert dropped not in repaired, dropped
    assert config[0]['pid_kp'] == 12.0 and config[0]['pid_ki'] == 0.0
    assert config[2]['voltage_max'] == config_store.to_float32(7.2)
    assert repaired.count('[joint_0]') == 1 and '[joint_6]' in repaired


def _damage(rng, text):
    """Return text damaged the ways a crash, a careless edit or a bad disk damage a file."""
    lines = text.splitlines(True)
    for _ in range(rng.randint(1, 4)):
        how = rng.choice(('cut', 'bytes', 'repeat', 'drop', 'swap', 'section', 'value'))
        index = rng.randrange(len(lines)) if lines else 0
        if how == 'cut':
            lines = lines[:index] + ([lines[index][:rng.randrange(len(lines[index]) + 1)]]
                                     if lines else [])
        elif how == 'bytes':
            lines.insert(index, ''.join(chr(rng.randrange(256)) for _ in range(rng.randint(1, 30))))
        elif how == 'repeat' and lines:
            lines.insert(rng.randrange(len(lines) + 1), lines[index])
        elif how == 'drop' and lines:
            del lines[index]
        elif how == 'swap' and len(lines) > 1:
            other = rng.randrange(len(lines))
            lines[index], lines[other] = lines[other], lines[index]
        elif how == 'section':
            lines.insert(index, rng.choice(('[joint_%d]\n' % rng.randrange(9), '[x]\n', '[\n')))
        elif how == 'value' and lines:
            lines[index] = lines[index].split('=')[0] + '= ' + rng.choice(
                ('1e20', '-3', 'nan', '', '0x1', '7.3', '3.2', '1e4', '-1e-3', '2')) + '\n'
    return ''.join(lines)


def test_fuzz_every_damaged_text_is_clean_after_one_repair():
    rng = random.Random(14)
    shipped = open(os.path.join(os.path.dirname(__file__), '..', '..', 'config',
                                'arm_L.ini')).read()
    for trial in range(1000):
        text = _damage(rng, rng.choice((shipped, config_store.default_text())))
        config, _ = config_store.parse(text)
        repaired = config_store.render(text, config)
        assert config_store.parse(repaired) == (config, []), 'trial %d: %r' % (trial, text)


def test_starting_twice_on_a_damaged_file_backs_it_up_once(tmp_path):
    path = tmp_path / 'arm_R.ini'
    path.write_text(DAMAGED)
    first = config_file.load_or_create(str(path), '', '20261122-101500')
    repaired = path.read_text()
    second = config_file.load_or_create(str(path), '', '20261122-101501')
    config, _, notes, problems = second[:4]  # (by index: the test predates Loaded's names)
    assert problems == [], 'the second start finds nothing to repair'
    assert notes == [] and config == first[0]
    assert path.read_text() == repaired
    assert sorted(os.listdir(tmp_path)) == ['arm_R.ini', 'arm_R.ini.bak-20261122-101500']
    assert (tmp_path / 'arm_R.ini.bak-20261122-101500').read_text() == DAMAGED


def test_a_backup_never_overwrites_an_older_one(tmp_path):
    path = tmp_path / 'arm_R.ini'
    path.write_text('one')
    assert config_file.backup(str(path), 's') == str(path) + '.bak-s'
    path.write_text('two')
    assert config_file.backup(str(path), 's') == str(path) + '.bak-s-2'
    assert (tmp_path / 'arm_R.ini.bak-s').read_text() == 'one'
    assert (tmp_path / 'arm_R.ini.bak-s-2').read_text() == 'two'


def _fail_with(code):
    def fail(*_args, **_kwargs):
        raise OSError(code, os.strerror(code))
    return fail


@pytest.mark.parametrize('code', [errno.EROFS, errno.ENOSPC])
def test_a_repair_that_cannot_be_written_leaves_file_settings_and_directory_as_they_were(
        tmp_path, monkeypatch, code):
    path = tmp_path / 'arm_R.ini'
    path.write_text(DAMAGED)
    monkeypatch.setattr(os, 'replace', _fail_with(code))
    loaded = config_file.load_or_create(str(path), '', 'stamp')
    assert os.strerror(code) in loaded.unwritable and str(path) in loaded.unwritable
    assert loaded.config == config_store.parse(DAMAGED)[0], 'runs from what it could read'
    assert path.read_text() == DAMAGED
    assert os.listdir(tmp_path) == ['arm_R.ini'], 'no backup or temporary is left behind'


def test_a_backup_that_fails_half_way_leaves_no_partial_copy(tmp_path, monkeypatch):
    path = tmp_path / 'arm_R.ini'
    path.write_text(DAMAGED)
    monkeypatch.setattr(shutil, 'copyfileobj', _fail_with(errno.ENOSPC))
    loaded = config_file.load_or_create(str(path), '', 'stamp')
    assert 'No space left' in loaded.unwritable
    assert path.read_text() == DAMAGED and os.listdir(tmp_path) == ['arm_R.ini']


def test_a_file_that_cannot_be_created_runs_from_the_seed(tmp_path):
    seed = tmp_path / 'seed.ini'
    seed.write_text(config_store.default_text().replace('pid_kp = 0', 'pid_kp = 4'))
    (tmp_path / 'not_a_dir').write_text('')
    path = tmp_path / 'not_a_dir' / 'arm_L.ini'  # works as root too: the parent is a file
    loaded = config_file.load_or_create(str(path), str(seed), 'x')
    assert loaded.unwritable.startswith('cannot create %s' % path)
    assert loaded.config[6]['pid_kp'] == 4.0 and loaded.problems == []
    assert sorted(os.listdir(tmp_path)) == ['not_a_dir', 'seed.ini']


def test_a_file_that_cannot_be_read_runs_from_the_defaults_and_is_never_written(tmp_path):
    path = tmp_path / 'arm_L.ini'
    path.mkdir()  # unreadable as a file, for root too
    loaded = config_file.load_or_create(str(path), '', 'x')
    assert loaded.unwritable.startswith('cannot read %s' % path)
    assert loaded.config == config_store.defaults()
    assert os.listdir(path) == [] and os.listdir(tmp_path) == ['arm_L.ini']


def test_a_real_full_disk_leaves_no_empty_backup(tmp_path):
    with tmpfs(64, {'arm_R.ini': DAMAGED}, full=True) as disk:
        loaded = config_file.load_or_create(os.path.join(disk, 'arm_R.ini'), '', 'stamp')
        assert 'No space left' in loaded.unwritable
        assert sorted(os.listdir(disk)) == ['arm_R.ini', 'filler']
        assert open(os.path.join(disk, 'arm_R.ini')).read() == DAMAGED
        assert loaded.config[0]['pid_kp'] == 12.0


def test_a_real_read_only_directory_is_read_and_left_alone(tmp_path):
    seed = tmp_path / 'seed.ini'
    seed.write_text(config_store.default_text())
    with tmpfs(64, {'arm_R.ini': DAMAGED}, read_only=True) as disk:
        loaded = config_file.load_or_create(os.path.join(disk, 'arm_R.ini'), str(seed), 's')
        assert 'Read-only file system' in loaded.unwritable
        assert loaded.config[1]['pid_kd'] == 0.5
        assert os.listdir(disk) == ['arm_R.ini']
        created = config_file.load_or_create(os.path.join(disk, 'sub', 'arm_L.ini'), str(seed), 's')
        assert created.unwritable.startswith('cannot create')
        assert created.config == config_store.defaults()
