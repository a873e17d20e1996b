"""The export command on bad input and at scale: a bag with garbage over its middle, garbage
camera frames, a long episode's memory, a killed export's .part files.
"""
import os
import random
import resource
import signal
import subprocess
import sys
import time

import genpy
import h5py
import pytest
import rosbag
from sensor_msgs.msg import JointState

from test_export_files import LEFT, RIGHT, T0_S, run, write_episode
from test_export_images import add_frames

CHILD = 'from robopuppet.episodes import export_cli; export_cli.main()'


def test_garbage_over_a_bags_middle_costs_only_what_it_hit(tmp_path, capsys):
    damaged = write_episode(tmp_path, name='episode_20240102-030405', steps=600)
    intact = write_episode(tmp_path, name='episode_20240102-030500', steps=20)
    size = damaged.stat().st_size
    with open(str(damaged), 'r+b') as stream:
        stream.seek(size // 2 - 8192)
        stream.write(random.Random(32).randbytes(16384))
    code = run([str(damaged), str(intact), '--format', 'all', '--plot'])
    out, err = capsys.readouterr()
    for suffix in ('.hdf5', '.csv', '.png'):
        assert (tmp_path / ('episode_20240102-030500' + suffix)).stat().st_size > 0
    if code == 0:  # exported as far as readable, what was skipped said
        assert 'episode_20240102-030405: skipped' in out
        assert '1 of 2 episodes exported without what could not be read' in err
        with h5py.File(str(tmp_path / 'episode_20240102-030405.hdf5'), 'r') as root:
            assert root['/observations/qpos'].shape == (599 * 5 + 1, 16)
    else:
        assert code == 1 and 'episode_20240102-030405' in err and '1 of 2' in err
    assert not list(tmp_path.glob('*.part'))


def test_garbage_frames_are_skipped_and_counted(tmp_path, capsys):
    bag_path = write_episode(tmp_path)
    add_frames(bag_path, [('room_camera', 0.0, 'red'), ('room_camera', 0.3, b''),
                          ('room_camera', 0.5, os.urandom(3000)), ('room_camera', 0.8, 'blue')])
    assert run([str(bag_path), '--rate', '10', '--image-size', 'full']) == 0
    with h5py.File(str(tmp_path / 'episode_20240102-030405.hdf5'), 'r') as root:
        assert root['/observations/images/room_camera'].shape == (11, 24, 32, 3)
    assert 'room_camera: skipped frames that do not decode: 2' in capsys.readouterr().out


def long_episode(directory, minutes):
    """Write an episode of Baxter's joint states at 100 Hz for minutes; return its bag."""
    bag_path = directory / ('episode_%dmin.bag' % minutes)
    with rosbag.Bag(str(bag_path), 'w') as bag:
        for k in range(int(minutes * 6000)):
            angles = [0.001 * k + 0.01 * j for j in range(14)]
            bag.write('/robot/joint_states', JointState(
                name=LEFT + RIGHT, position=angles, velocity=[0.1] * 14, effort=[0.2] * 14),
                genpy.Time(T0_S) + genpy.Duration(0, k * 10**7))
    return bag_path


def peak_memory_mb(argv):
    """Run the export command in a child; return its peak resident memory (MB)."""
    child = subprocess.Popen([sys.executable, '-c', CHILD] + argv, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(child.pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    return usage.ru_maxrss / 1e3


@pytest.mark.slow
def test_memory_does_not_grow_with_the_episodes_length(tmp_path):
    short, long = long_episode(tmp_path, 1), long_episode(tmp_path, 4)
    peaks = [peak_memory_mb([str(bag), '--format', 'all']) for bag in (short, long)]
    assert peaks[1] - peaks[0] < 10.0, peaks  # the old exporter: about +100 MB
    with h5py.File(str(tmp_path / 'episode_4min.hdf5'), 'r') as root:
        assert root['/observations/qpos'].shape == (4 * 60 * 50, 16)


def start_export(argv, folder):
    """Start the export command in a child; return it once a .part file is being written."""
    child = subprocess.Popen([sys.executable, '-c', CHILD] + argv, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 20.0
    while not list(folder.glob('*.part')):
        assert child.poll() is None and time.monotonic() < deadline
        time.sleep(0.01)
    return child


def test_a_killed_export_leaves_no_part_file(tmp_path):
    bag_path = long_episode(tmp_path, 2)
    child = start_export([str(bag_path), '--format', 'all'], tmp_path)
    child.send_signal(signal.SIGTERM)
    assert child.wait(10) != 0
    assert not list(tmp_path.glob('*.part'))  # removed on SIGTERM
    child = start_export([str(bag_path), '--format', 'all'], tmp_path)
    child.kill()
    child.wait(10)
    parts = list(tmp_path.glob('*.part'))
    assert parts and not list(tmp_path.glob('*.hdf5'))  # never taken for an export
    assert run([str(bag_path), '--format', 'csv']) == 0  # the next run, another format
    assert not list(tmp_path.glob('*.part'))
    assert not (tmp_path / 'episode_2min.hdf5').exists()
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss > 0
