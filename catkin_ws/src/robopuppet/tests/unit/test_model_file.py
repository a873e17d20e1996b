"""The assist's model file: a round trip, atomic writes, and clear errors for bad files."""
import json
import os

import numpy as np
import pytest

import assist_synthetic
from robopuppet.assist import learners, model_file

DEMOS = [assist_synthetic.demo(seed) for seed in range(4)]


@pytest.fixture(scope='module')
def predictor():
    return learners.train(DEMOS, 'lwr', 'right', 'left', 'wipe', seed=0)


def test_a_saved_model_loads_and_predicts_the_same(tmp_path, predictor):
    path = str(tmp_path / 'model.npz')
    model_file.save(path, predictor, {'training_episodes': ['a', 'b']})
    loaded = model_file.load(path)
    assert (loaded.method, loaded.leader, loaded.follower, loaded.task) == \
        ('lwr', 'right', 'left', 'wipe')
    assert model_file.read_header(path)['training_episodes'] == ['a', 'b']
    for k in range(0, 300, 50):
        assert loaded.step(DEMOS[0].t[k], DEMOS[0].right[k]) == \
            predictor.step(DEMOS[0].t[k], DEMOS[0].right[k])
    assert os.listdir(str(tmp_path)) == ['model.npz']


def test_a_save_that_fails_leaves_the_old_model(tmp_path, predictor, monkeypatch):
    path = str(tmp_path / 'model.npz')
    model_file.save(path, predictor)
    before = open(path, 'rb').read()

    def broken(*_args):
        raise OSError('disk full')
    monkeypatch.setattr(os, 'fsync', broken)
    with pytest.raises(OSError, match='disk full'):
        model_file.save(path, predictor, {'task': 'other'})
    assert open(path, 'rb').read() == before
    assert os.listdir(str(tmp_path)) == ['model.npz']


def test_a_missing_file_says_so(tmp_path):
    with pytest.raises(model_file.ModelError, match='no such model file.*train_assist'):
        model_file.load(str(tmp_path / 'none.npz'))


def test_a_truncated_file_is_refused(tmp_path, predictor):
    path = str(tmp_path / 'model.npz')
    model_file.save(path, predictor)
    data = open(path, 'rb').read()
    with open(path, 'wb') as out:
        out.write(data[:len(data) // 2])
    with pytest.raises(model_file.ModelError, match='not an assist model file, or truncated'):
        model_file.load(path)


@pytest.mark.parametrize('arrays, expected', [
    ({'weights': np.zeros(3)}, 'no header'),
    ({'header': np.array(json.dumps({'format': 'other'}))}, 'not an assist model file'),
    ({'header': np.array(json.dumps({'format': model_file.FORMAT, 'format_version': 99}))},
     'version 99.*train the model again'),
    ({'header': np.array([{'format': model_file.FORMAT}], dtype=object)},
     'not an assist model file'),
    ({'header': np.array(json.dumps({'format': model_file.FORMAT, 'format_version': 1,
                                     'method': 'gmr', 'leader': 'right', 'follower': 'left',
                                     'task': '', 'score_ref': 0, 'score_threshold': 1}))},
     'damaged'),
])
def test_a_foreign_or_other_version_file_is_refused(tmp_path, arrays, expected):
    path = str(tmp_path / 'model.npz')
    np.savez(path, **arrays)
    with pytest.raises(model_file.ModelError, match=expected):
        model_file.load(path)


def test_a_text_file_is_not_a_model(tmp_path):
    path = tmp_path / 'model.npz'
    path.write_text('hello')
    with pytest.raises(model_file.ModelError, match='not an assist model'):
        model_file.load(str(path))
