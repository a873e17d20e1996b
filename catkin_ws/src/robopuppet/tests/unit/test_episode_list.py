"""The episodes command: the episodes of a folder with start, duration, sides, cameras, size,
how they ended and what was exported, from the folder and the .yaml files alone."""
import datetime
import time

import pytest
import yaml

from robopuppet.episodes import episode_list


def write(folder, name, bag_bytes, suffix='.bag', **metadata):
    (folder / (name + suffix)).write_bytes(b'x' * bag_bytes)
    if metadata:
        (folder / (name + '.yaml')).write_text(yaml.safe_dump(dict(metadata, name=name)))


def test_the_list_says_each_episodes_start_duration_size_ending_and_exports(
        tmp_path, capsys, monkeypatch, request):
    monkeypatch.setenv('TZ', 'UTC')  # the start is shown in local time
    time.tzset()
    request.addfinalizer(lambda: (monkeypatch.undo(), time.tzset()))  # TZ back, then reread
    write(tmp_path, 'episode_20240101-120000_2', 3000000, start_time='2024-01-01T12:00:05.250Z',
          duration_s=20.04, sides=['R'], cameras=['room_camera', 'right_hand_camera'],
          ended_cleanly=True, notes='demo 1:\n reach and grip', task='pick up the cup')
    for suffix in ('.hdf5', '.png'):
        (tmp_path / ('episode_20240101-120000_2' + suffix)).write_bytes(b'')
    write(tmp_path, 'episode_20240101-110000', 1500000, start_time='2024-01-01T11:00:00.000Z',
          duration_s=4.0, sides=['L', 'R'], ended_cleanly=False,  # repaired, no cameras key
          task='lift the cup over the bed and hand it to the patient, handle first')
    write(tmp_path, 'episode_20240101-130000', 500000, suffix='.bag.active',
          start_time='2024-01-01T13:00:00.000Z', duration_s=0.0, sides=['R'], cameras=[],
          ended_cleanly=False)
    write(tmp_path, 'episode_20240101-140000', 100000, suffix='.bag.broken')
    (tmp_path / 'episode_20240101-120000_2.hdf5.123.part').write_bytes(b'')
    (tmp_path / '.recorder.lock').write_text('')
    with pytest.raises(SystemExit) as exit_info:
        episode_list.main([str(tmp_path)])
    assert exit_info.value.code == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].split() == ['episode', 'start', 'duration', 'sides', 'cameras', 'size',
                                'ended', 'exported', 'task', 'notes']
    assert lines[1].split() == ['episode_20240101-110000', '2024-01-01', '11:00:00', '4.0',
                                's', 'LR', '0', '1.5', 'MB', 'repaired', '-', 'lift', 'the',
                                'cup', 'over', 'the', 'bed', 'and', 'hand', 'it', 'to', 'the',
                                'pa...']
    assert lines[2].split() == ['episode_20240101-120000_2', '2024-01-01', '12:00:05', '20.0',
                                's', 'R', '2', '3.0', 'MB', 'clean', 'hdf5', 'png', 'pick',
                                'up', 'the', 'cup', 'demo', '1:', 'reach', 'and', 'grip']
    assert lines[3].split() == ['episode_20240101-130000', '2024-01-01', '13:00:00', '?', 'R',
                                '0', '0.5', 'MB', 'recording', '-', '-']
    assert lines[4].split() == ['episode_20240101-140000', '2024-01-01', '14:00:00', '?', '-',
                                '?', '0.1', 'MB', 'broken', '-', '-']
    assert lines[5] == '4 episodes, 5.1 MB, in %s' % tmp_path
    assert len({line.index(' 2024-01-01') for line in lines[1:5]}) == 1  # aligned columns
    assert lines[1].index('lift') == lines[2].index('pick up')  # the task column, and the
    assert lines[2].index('demo 1') == lines[1].index('lift') + 50 + 2  # notes after its 50


def test_a_missing_folder_is_said_and_an_empty_one_listed(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_info:
        episode_list.main([str(tmp_path / 'none')])
    assert exit_info.value.code == 2
    assert 'no such folder' in capsys.readouterr().err
    assert episode_list.table(episode_list.entries(str(tmp_path)), 'd')[-1] == (
        '0 episodes, 0.0 MB, in d')


def test_the_start_comes_from_the_metadata_else_from_the_name():
    assert episode_list._start({}, 'episode_20240102-030405_3') == datetime.datetime(
        2024, 1, 2, 3, 4, 5)
    assert episode_list._start({}, 'other') is None
