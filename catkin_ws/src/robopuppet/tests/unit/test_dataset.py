"""Episodes read as demonstrations: Baxter's measured arms and grippers at 50 Hz, gaps cut."""
import numpy as np
import pytest

import assist_synthetic
from robopuppet.assist import dataset

SHOWN = assist_synthetic.demo(3)


def test_an_episode_reads_back_as_its_demonstration(tmp_path):
    path = assist_synthetic.write_episode(tmp_path, 'episode_1', SHOWN, 'carry')
    demo = dataset.read_episode(str(path), 'right', 'left')
    assert np.allclose(np.diff(demo.t), 0.02) and demo.t[0] == 0.0
    assert np.isclose(demo.t[-1], SHOWN.t[-1], atol=0.02)
    for side in ('left', 'right'):
        expected = np.array([np.interp(demo.t, SHOWN.t, getattr(SHOWN, side)[:, j])
                             for j in range(7)]).T
        assert np.allclose(getattr(demo, side), expected, atol=1e-6)
    expected_closed = np.interp(demo.t, SHOWN.t, SHOWN.left_closed.astype(float)) > 0.5
    assert (demo.left_closed == expected_closed).mean() > 0.98
    assert demo.left_closed.any() and not demo.left_closed.all()


def test_a_gap_in_the_joint_states_is_cut_not_interpolated(tmp_path):
    path = assist_synthetic.write_episode(tmp_path, 'episode_1', SHOWN, gap=(2.0, 2.5))
    demo = dataset.read_episode(str(path), 'right', 'left')
    assert not ((demo.t > 2.0) & (demo.t < 2.5)).any()
    jumps = np.flatnonzero(np.diff(demo.t) > 0.03)
    assert len(jumps) == 1 and demo.t[jumps[0]] <= 2.0 and demo.t[jumps[0] + 1] >= 2.5
    assert (demo.t >= 2.5).sum() > 100


def test_an_episode_without_the_followers_gripper_state_is_refused(tmp_path):
    path = assist_synthetic.write_episode(tmp_path, 'episode_1', SHOWN, grippers=False)
    with pytest.raises(dataset.DatasetError, match='left_gripper/state'):
        dataset.read_episode(str(path), 'right', 'left')


def test_an_episode_without_joint_states_is_refused(tmp_path):
    with pytest.raises(dataset.DatasetError, match='/robot/joint_states'):
        dataset.demo_of([])


def test_a_folder_is_read_filtered_by_task_with_a_line_per_episode(tmp_path):
    assist_synthetic.write_episode(tmp_path, 'episode_1', SHOWN, 'carry the tray')
    assist_synthetic.write_episode(tmp_path, 'episode_2', SHOWN, 'wipe')
    assist_synthetic.write_episode(tmp_path, 'episode_3', SHOWN, 'carry the tray')
    (tmp_path / 'episode_4.bag').write_text('not a bag')
    (tmp_path / 'episode_4.yaml').write_text('task: carry the tray\n')
    lines = []
    episodes, errors = dataset.read_episodes([str(tmp_path)], 'right', 'left',
                                             'carry the tray', lines.append)
    assert [e.name for e in episodes] == ['episode_1', 'episode_3']
    assert {e.task for e in episodes} == {'carry the tray'}
    assert len(errors) == 1 and 'episode_4' in errors[0]
    assert len(lines) == 4 and lines[0].startswith('[1/4] episode_1: ')
    assert "task 'wipe', not 'carry the tray': left out" in lines[1]
    assert lines[3].startswith('[4/4] skipped: ')
