"""The export command on synthetic episodes (a small rosbag and its yaml in tmp_path): the HDF5
opens with h5py in ALOHA's layout, the CSV reads back the same numbers, bad episodes fail alone.
"""
import csv

import genpy
import h5py
import numpy as np
import pytest
import rosbag
import yaml
from baxter_core_msgs.msg import EndEffectorCommand, EndEffectorState, JointCommand
from robopuppet_msgs.msg import TeleopState
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32, String

from robopuppet.episodes import export, export_cli, export_files

T0_S = 1700000000  # whole seconds of ROS time; message k at T0_S + 0.1 k s, exact in ns
RIGHT = ['right_s0', 'right_s1', 'right_e0', 'right_e1', 'right_w0', 'right_w1', 'right_w2']
LEFT = [n.replace('right', 'left') for n in RIGHT]


def write_episode(directory, name='episode_20240102-030405', sim=True, steps=11):
    """Write an episode of steps x 0.1 s: joint j of either arm at 0.01 j + 0.1 k rad at step k
    (k = 0..steps-1), the right arm commanded 0.05 rad ahead from step 1, its gripper at
    (10 k) % and a 'go' to 20 % at step 5. Return the bag path."""
    bag_path = directory / (name + '.bag')
    with rosbag.Bag(str(bag_path), 'w') as bag:
        for k in range(steps):
            t = genpy.Time(T0_S + k // 10, k % 10 * 100000000)
            angles = [0.01 * j + 0.1 * k for j in range(7)]
            bag.write('/robot/joint_states', JointState(
                name=LEFT + RIGHT, position=angles * 2, velocity=[1.0] * 14,
                effort=[0.5] * 14), t)
            bag.write('/robot/end_effector/right_gripper/state',
                      EndEffectorState(position=10.0 * k, force=0.0), t)
            bag.write('/puppet/arm_R/joint_states', JointState(
                name=['joint_%d' % j for j in range(7)], position=angles), t)
            bag.write('/puppet/arm_R/gripper_3', Float32(data=1.0 if k < 5 else 0.0), t)
            bag.write('/puppet/arm_R/opmode', String(data='limp'), t)
            if k >= 1:
                bag.write('/robot/limb/right/joint_command', JointCommand(
                    mode=JointCommand.POSITION_MODE, names=RIGHT,
                    command=[a + 0.05 for a in angles]), t)
            if k == 5:
                bag.write('/robot/end_effector/right_gripper/command', EndEffectorCommand(
                    command='go', args='{"position": 20.0}'), t)
        bag.write('/puppet/arm_R/teleop_state', TeleopState(state='following', follow_right=True),
                  genpy.Time(T0_S))
    metadata = {'format_version': 1, 'name': name, 'sim': sim, 'sides': ['R'],
                'duration_s': 0.1 * (steps - 1), 'ended_cleanly': True}
    (directory / (name + '.yaml')).write_text(yaml.safe_dump(metadata))
    return bag_path


def run(argv):
    with pytest.raises(SystemExit) as exit_info:
        export_cli.main(argv)
    return exit_info.value.code


def test_the_hdf5_opens_with_h5py_in_alohas_layout(tmp_path):
    bag_path = write_episode(tmp_path)
    assert run([str(bag_path), '--rate', '20']) == 0
    with h5py.File(str(tmp_path / 'episode_20240102-030405.hdf5'), 'r') as root:
        assert root.attrs['sim'] == True  # noqa: E712  (h5py gives numpy.bool_)
        assert root.attrs['rate_hz'] == 20.0
        assert root.attrs['fps'] == 20.0  # the name LeRobot's ALOHA datasets give the rate
        assert list(root.attrs['columns']) == export.COLUMNS
        for name in ('/observations/qpos', '/observations/qvel', '/observations/effort',
                     '/action'):
            assert root[name].shape == (21, 16) and root[name].dtype == np.float32
        qpos, action = root['/observations/qpos'][()], root['/action'][()]
        qvel = root['/observations/qvel'][()]
    # step 0.05 s: right_e0 (j=2) measured 0.02 + 2 k_half ... at grid index 3 (0.15 s): 0.17
    assert qpos[3, 10] == pytest.approx(0.17, abs=1e-6)
    assert qpos[3, 2] == pytest.approx(0.17, abs=1e-6)  # left_e0 the same
    assert qvel[3, 10] == 1.0
    # commanded right_e0: held from the step-1 command (0.12 + 0.05) at 0.15 s; before it,
    # at 0.05 s, the measured 0.07
    assert action[3, 10] == pytest.approx(0.17, abs=1e-6)
    assert action[1, 10] == pytest.approx(0.07, abs=1e-6)
    # gripper: (10 k) % -> opening 0.15 at 0.15 s; its 'go' to 20 % held from 0.5 s
    assert qpos[3, 15] == pytest.approx(0.15, abs=1e-6)
    assert action[9, 15] == pytest.approx(0.45, abs=1e-6)
    assert action[10, 15] == pytest.approx(0.2, abs=1e-6)


def test_the_csv_reads_back_the_same_numbers(tmp_path):
    bag_path = write_episode(tmp_path, sim=False, steps=4)
    assert run([str(bag_path), '--format', 'csv', '--rate', '10', '--out',
                str(tmp_path / 'out')]) == 0
    with open(str(tmp_path / 'out' / 'episode_20240102-030405.csv')) as stream:
        rows = list(csv.reader(stream))
    assert rows[0] == export.CSV_HEADER
    table = np.array([[float(v) for v in row] for row in rows[1:]])
    assert table[:, 0].tolist() == [0.0, 0.1, 0.2, 0.3]
    expected_arm = np.array([[0.01 * j + 0.1 * k for j in range(7)] for k in range(4)])
    assert np.array_equal(table[:, 1:8], expected_arm)  # exact: repr round-trips floats
    assert np.array_equal(table[:, 9:16], expected_arm)
    assert table[:, 16].tolist() == [0.0, 10.0, 20.0, 30.0]  # percent, as joint_recorder
    assert table[:, 8].tolist() == [0.0] * 4
    recording = export.collect(export_files.read_messages(str(bag_path),
                                                          export.episode_topics()))
    arrays = export.aloha_arrays(recording, 10.0)
    assert np.array_equal(table[:, 1:8], arrays['qpos'][:, :7])


def test_a_bad_episode_fails_alone_with_a_clear_message(tmp_path, capsys):
    good = write_episode(tmp_path)
    (tmp_path / 'episode_20240102-030500.bag.active').write_bytes(b'')
    (tmp_path / 'episode_20240102-030600.bag').write_bytes(b'not a bag')
    assert run([str(tmp_path / 'episode_20240102-030500'), str(tmp_path / 'missing.bag'),
                str(tmp_path / 'episode_20240102-030600.bag'), str(good),
                '--format', 'all', '--plot']) == 1
    err = capsys.readouterr().err
    assert 'rosbag reindex' in err and 'no such bag' in err and 'cannot read the bag' in err
    assert '3 of 4 episodes failed' in err
    for suffix in ('.hdf5', '.csv', '.png'):
        assert (tmp_path / ('episode_20240102-030405' + suffix)).stat().st_size > 0
    assert not list(tmp_path.glob('*.part'))
    png = (tmp_path / 'episode_20240102-030405.png').read_bytes()
    assert png.startswith(b'\x89PNG')


def test_a_bare_name_is_found_in_ros_home(tmp_path, monkeypatch):
    episodes = tmp_path / 'robopuppet' / 'episodes'
    episodes.mkdir(parents=True)
    write_episode(episodes, name='episode_20240101-000000', steps=2)
    monkeypatch.setenv('ROS_HOME', str(tmp_path))
    monkeypatch.chdir(tmp_path)
    assert run(['episode_20240101-000000']) == 0
    assert (episodes / 'episode_20240101-000000.hdf5').exists()
    assert not (episodes / 'episode_20240101-000000.csv').exists()
