"""export --act-dir: episodes written as ACT's loader opens them (episode_0.hdf5, episode_1.hdf5
... in one folder, read as its EpisodicDataset reads them), the index continuing after the
highest one there, and the mapping from index to episode written beside them.
"""
import h5py
import numpy as np
import yaml

from robopuppet.episodes import export_act
from test_export_files import run, write_episode
from test_export_images import add_frames


def read_as_act(directory, index, cameras, step):
    """Read one step of episode_<index>.hdf5 the way ACT's EpisodicDataset does."""
    with h5py.File(str(directory / ('episode_%d.hdf5' % index)), 'r') as root:
        is_sim = root.attrs['sim']
        episode_len = root['/action'].shape[0]
        qpos = root['/observations/qpos'][step]
        qvel = root['/observations/qvel'][step]
        images = np.stack([root['/observations/images/%s' % c][step] for c in cameras])
        action = root['/action'][step:]
        return is_sim, episode_len, qpos, qvel, images, action, root.attrs['episode']


def test_episodes_get_indices_after_the_highest_and_the_mapping_is_written(tmp_path, capsys):
    recorded = tmp_path / 'episodes'
    recorded.mkdir()
    first = write_episode(recorded, name='episode_20240102-030405')
    second = write_episode(recorded, name='episode_20240102-030500')
    for bag in (first, second):
        add_frames(bag, [('room_camera', 0.0, 'red')])
    act = tmp_path / 'act'
    assert run([str(first), str(second), '--rate', '10', '--act-dir', str(act)]) == 0
    assert sorted(p.name for p in act.glob('*.hdf5')) == ['episode_0.hdf5', 'episode_1.hdf5']
    assert not (recorded / 'episode_20240102-030405.hdf5').exists()
    is_sim, length, qpos, qvel, images, action, name = read_as_act(act, 1, ['room_camera'], 3)
    assert is_sim and length == 11 and qpos.shape == qvel.shape == (16,)
    assert images.shape == (1, 240, 320, 3) and action.shape == (8, 16)
    assert name == 'episode_20240102-030500'
    index_file = act / export_act.INDEX_FILE
    assert yaml.safe_load(index_file.read_text()) == {0: 'episode_20240102-030405',
                                                      1: 'episode_20240102-030500'}
    assert 'ACT index 1' in capsys.readouterr().out
    # a folder that holds episode_0 .. episode_6 already (another tool's): the next is 7
    (act / 'episode_6.hdf5').write_bytes(b'')
    third = write_episode(recorded, name='episode_20240103-000000')
    assert run([str(third), '--rate', '10', '--no-images', '--act-dir', str(act)]) == 0
    assert (act / 'episode_7.hdf5').exists()
    mapping = yaml.safe_load(index_file.read_text())
    assert mapping[7] == 'episode_20240103-000000' and 6 not in mapping
    out = capsys.readouterr().out
    assert 'ACT index 7' in out
    assert 'has no episode_2.hdf5, episode_3.hdf5, episode_4.hdf5, episode_5.hdf5' in out
    # exported again: it keeps its index, no new file
    assert run([str(first), '--rate', '10', '--act-dir', str(act)]) == 0
    assert 'ACT index 0 (exported there before: written again)' in capsys.readouterr().out
    assert sorted(p.name for p in act.glob('*.hdf5')) == [
        'episode_0.hdf5', 'episode_1.hdf5', 'episode_6.hdf5', 'episode_7.hdf5']
    assert not list(act.glob('*.part'))


def test_episodes_of_other_lengths_are_named(tmp_path, capsys):
    act = tmp_path / 'act'
    for name, steps in (('episode_20240102-030405', 11), ('episode_20240102-030500', 6)):
        assert run([str(write_episode(tmp_path, name=name, steps=steps)), '--rate', '10',
                    '--act-dir', str(act)]) == 0
    assert ('episode_1 has 6 steps, others in %s have 11' % act) in capsys.readouterr().out


def test_the_next_index_is_chosen_from_the_files_there(tmp_path):
    assert export_act.choose_index(str(tmp_path), 'a') == (0, False)
    for index in (0, 1, 4):
        (tmp_path / export_act.file_name(index)).write_bytes(b'')
    (tmp_path / 'episode_x.hdf5').write_bytes(b'')
    (tmp_path / 'episode_20240101-000000.hdf5').write_bytes(b'')  # a recorded name
    assert export_act.indices(str(tmp_path)) == [0, 1, 4]
    assert export_act.choose_index(str(tmp_path), 'a') == (5, False)
    assert export_act.gaps(str(tmp_path)) == [2, 3]
    export_act.record(str(tmp_path), 5, 'a')
    (tmp_path / export_act.file_name(5)).write_bytes(b'')
    assert export_act.choose_index(str(tmp_path), 'a') == (5, True)
    assert export_act.read_index(str(tmp_path)) == {5: 'a'}
