"""The train_assist command on synthetic episodes (bags in tmp_path): a model written and its
table printed, clear errors for what cannot train."""
import numpy as np
import pytest

import assist_synthetic
from robopuppet.assist import model_file, train_cli


def write_episodes(directory, count, task='synthetic task', first_seed=0):
    return [str(assist_synthetic.write_episode(directory, 'episode_%02d' % (first_seed + k),
                                               assist_synthetic.demo(first_seed + k), task,
                                               rate_hz=50.0))
            for k in range(count)]


def run(argv):
    lines = []
    code = train_cli.run(train_cli.parse_args(argv), lines.append)
    return code, '\n'.join(lines)


def test_a_folder_trains_evaluates_and_writes_the_better_model(tmp_path):
    folder = tmp_path / 'episodes'
    folder.mkdir()
    write_episodes(folder, 6)
    out, plot = str(tmp_path / 'model.npz'), str(tmp_path / 'plot.png')
    code, text = run([str(folder), '--out', out, '--plot', plot, '--holdout', '0.34'])
    assert code == 0, text
    assert '[6/6] episode_05' in text
    assert 'held-out evaluation (4 training, 2 held-out episodes; follower left, leader right)' \
        in text
    assert "task 'synthetic task' is not one assist.tasks knows" in text
    header = model_file.read_header(out)
    assert 'kept %s: lowest held-out error p99' % header['method'] in text
    rows = [line.split() for line in text.splitlines() if line.startswith(('  gmr ', '  lwr '))]
    assert sorted(r[0] for r in rows) == ['gmr', 'lwr']
    best = min(rows, key=lambda r: float(r[3]))
    assert header['method'] == best[0]
    assert len(header['training_episodes']) == 4 and len(header['heldout_episodes']) == 2
    assert set(header['heldout']) == {'gmr', 'lwr'} and header['task'] == 'synthetic task'
    predictor = model_file.load(out)
    shown = assist_synthetic.demo(50)
    positions, _, _ = predictor.predict_demo(shown)
    assert np.percentile(np.abs(positions - shown.left).max(axis=1), 99) < 0.15
    assert open(plot, 'rb').read(4) == b'\x89PNG'


def test_one_method_is_trained_when_asked(tmp_path):
    paths = write_episodes(tmp_path, 4)
    code, text = run(paths + ['--out', str(tmp_path / 'm.npz'), '--method', 'lwr'])
    assert code == 0 and model_file.read_header(str(tmp_path / 'm.npz'))['method'] == 'lwr'
    assert 'gmr' not in text


def test_episodes_of_several_tasks_need_a_task(tmp_path):
    paths = write_episodes(tmp_path, 3, 'one') + write_episodes(tmp_path, 3, 'two', 3)
    code, text = run(paths + ['--out', str(tmp_path / 'm.npz'), '--method', 'lwr'])
    assert code == 1 and "2 tasks: choose one with --task ('one': 3; 'two': 3)" in text
    code, text = run(paths + ['--out', str(tmp_path / 'm.npz'), '--method', 'lwr',
                              '--task', 'two'])
    assert code == 0 and model_file.read_header(str(tmp_path / 'm.npz'))['task'] == 'two'


@pytest.mark.parametrize('count, expected', [(0, 'no episodes to train on'),
                                             (2, 'leave 1 to train on')])
def test_too_few_episodes_is_an_error_and_writes_nothing(tmp_path, count, expected):
    folder = tmp_path / 'episodes'
    folder.mkdir()
    write_episodes(folder, count)
    code, text = run([str(folder), '--out', str(tmp_path / 'm.npz')])
    assert code == 1 and expected in text.splitlines()[-1]
    assert text.splitlines()[-1].startswith('error: ')
    assert not (tmp_path / 'm.npz').exists()


def test_a_bad_holdout_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as stop:
        train_cli.parse_args(['x', '--out', 'm.npz', '--holdout', '1.5'])
    assert stop.value.code == 2 and '--holdout' in capsys.readouterr().err
