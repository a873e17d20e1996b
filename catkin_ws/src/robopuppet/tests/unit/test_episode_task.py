"""Unit tests of `episodes set-task` (episodes.episode_task): the task rewritten whole or not at
all, the rest of the metadata kept; an episode being recorded, a bad task or .yaml refused."""
import os

import pytest
import yaml

from robopuppet.episodes import episode_list, episode_task, metadata, recording

META = {'format_version': 1, 'name': 'episode_a', 'duration_s': 4.5, 'sides': ['R'],
        'notes': 'demo 1', 'task': 'old task', 'ended_cleanly': True, 'sim': True,
        'topics': {'/robot/joint_states': 450}}


def episode(folder, name='episode_a', suffix=recording.BAG, meta=META):
    (folder / (name + suffix)).write_bytes(b'bag')
    if meta is not None:
        metadata.write_metadata(str(folder / (name + recording.META)), dict(meta, name=name))
    return str(folder / (name + recording.BAG))


def set_task(capsys, *argv):
    """Run `episodes set-task argv...`; return (exit code, stdout, stderr)."""
    with pytest.raises(SystemExit) as exit_info:
        episode_list.main(['set-task'] + list(argv))
    out, err = capsys.readouterr()
    return exit_info.value.code, out, err


def test_the_task_is_replaced_and_everything_else_kept(tmp_path, capsys):
    bag = episode(tmp_path)
    yaml_path = bag[:-len(recording.BAG)] + recording.META
    code, out, err = set_task(capsys, bag, '--task', '  pick up the cup: "gently"  ')
    assert (code, err) == (0, '') and yaml_path in out
    assert metadata.read_metadata(yaml_path) == dict(META, task='pick up the cup: "gently"')
    assert sorted(os.listdir(tmp_path)) == ['episode_a.bag', 'episode_a.yaml']  # no temp left
    assert set_task(capsys, yaml_path, '--task', '')[0] == 0  # '' clears it
    assert metadata.read_metadata(yaml_path)['task'] == ''


def test_episodes_are_found_by_name_in_the_default_folder_and_each_done_on_its_own(
        tmp_path, capsys, monkeypatch):
    folder = tmp_path / 'robopuppet' / 'episodes'
    folder.mkdir(parents=True)
    monkeypatch.setenv('ROS_HOME', str(tmp_path))
    episode(folder, 'episode_a')
    episode(folder, 'episode_b', meta=None)  # a bag without metadata gets its name and task
    episode(folder, 'episode_c', suffix=recording.ACTIVE)
    code, out, err = set_task(capsys, 'episode_a', 'episode_c', 'episode_missing',
                              'episode_b', '--task', 'hand it over')
    assert code == 1
    assert metadata.read_metadata(str(folder / 'episode_a.yaml'))['task'] == 'hand it over'
    assert metadata.read_metadata(str(folder / 'episode_b.yaml')) == {
        'name': 'episode_b', 'task': 'hand it over'}
    assert metadata.read_metadata(str(folder / 'episode_c.yaml'))['task'] == 'old task'
    assert 'episode_c: ' in err and 'still being recorded' in err
    assert 'episode_missing: ' in err and 'no such bag' in err
    assert len(out.splitlines()) == 2 and len(err.splitlines()) == 2


def test_an_episode_whose_recording_runs_beside_its_bag_is_refused(tmp_path, capsys):
    bag = episode(tmp_path)
    (tmp_path / 'episode_a.bag.active').write_bytes(b'')
    code, _, err = set_task(capsys, bag, '--task', 'new')
    assert code == 1 and 'episode_a is still being recorded (episode_a.bag.active exists)' in err
    assert metadata.read_metadata(str(tmp_path / 'episode_a.yaml'))['task'] == 'old task'


@pytest.mark.parametrize('task, why', [('two\nlines', 'one line'),
                                       ('x' * 501, 'at most 500 characters'),
                                       ('tab\there', 'printable')])
def test_a_bad_task_writes_nothing(tmp_path, capsys, task, why):
    bag = episode(tmp_path)
    before = (tmp_path / 'episode_a.yaml').read_bytes()
    code, _, err = set_task(capsys, bag, '--task', task)
    assert code == 2 and why in err
    assert (tmp_path / 'episode_a.yaml').read_bytes() == before


def test_an_unreadable_yaml_is_refused_and_kept(tmp_path, capsys):
    bag = episode(tmp_path, meta=None)
    (tmp_path / 'episode_a.yaml').write_text('{not: yaml: at all\n')
    code, _, err = set_task(capsys, bag, '--task', 'new')
    assert code == 1 and 'episode_a' in err
    assert (tmp_path / 'episode_a.yaml').read_text() == '{not: yaml: at all\n'


@pytest.mark.parametrize('fail', ['dump', 'fsync', 'replace'])
def test_a_failed_write_leaves_the_old_yaml_whole_and_no_temporary_file(
        tmp_path, capsys, monkeypatch, fail):
    bag = episode(tmp_path)
    before = (tmp_path / 'episode_a.yaml').read_bytes()

    def half_dump(data, stream=None, **_):
        if stream is not None:
            stream.write('format_version: 1\nname: epi')  # half a file, then the disk is full
        raise OSError(28, 'No space left on device')

    def broken(*_):
        raise OSError(28, 'No space left on device')
    target = {'dump': (metadata.yaml, 'safe_dump', half_dump), 'fsync': (os, 'fsync', broken),
              'replace': (os, 'replace', broken)}[fail]
    monkeypatch.setattr(*target)
    code, _, err = set_task(capsys, bag, '--task', 'new')
    monkeypatch.undo()
    assert code == 1 and 'No space left on device' in err
    assert (tmp_path / 'episode_a.yaml').read_bytes() == before
    assert yaml.safe_load(before)['task'] == 'old task'
    assert sorted(os.listdir(tmp_path)) == ['episode_a.bag', 'episode_a.yaml']


def test_set_task_is_a_function_too(tmp_path):
    bag = episode(tmp_path)
    assert episode_task.set_task(bag, 'new') == str(tmp_path / 'episode_a.yaml')
    with pytest.raises(metadata.EpisodeError, match='no such bag'):
        episode_task.set_task(str(tmp_path / 'episode_z'), 'new')
