"""Unit tests of episode_files' bags and their repair, which episode_folder's lock guards (one
recorder per episodes folder): a live recorder's files are never repaired, a dead one's and a
.bag without its index are."""
import os
import signal
import subprocess
import sys
import textwrap

import pytest
import rosbag
import yaml
from std_msgs.msg import Float32

from robopuppet.episodes import episode_files, episode_folder, metadata, recording
from test_session import raw

# A recorder in its own process: takes the folder's lock, then (with 'write') records an episode
# the way the recorder does, flushing every 0.1 s; says 'locked' and each flush on stdout.
HOLDER = textwrap.dedent('''
    import sys, time
    from std_msgs.msg import Float32
    from robopuppet.episodes import episode_files, episode_folder, metadata
    sys.path.insert(0, %r)
    from test_session import raw
    lock = episode_folder.FolderLock(sys.argv[1], '/holder')
    print('locked', flush=True)
    if sys.argv[2] == 'write':
        metadata.write_metadata(sys.argv[1] + '/episode_live.yaml',
                                {'name': 'episode_live', 'ended_cleanly': False})
        writer = episode_files.BagWriter(sys.argv[1], 'episode_live')
    k = 0
    while True:
        if sys.argv[2] == 'write':
            writer.write('/x', raw(Float32(k), '/x'), 1000.0 + 0.01 * k)
            writer.flush()
            print('flushed', k, flush=True)
            k += 1
        time.sleep(0.1)
''') % os.path.dirname(os.path.abspath(__file__))


@pytest.fixture
def holder(tmp_path):
    """Start holder(what) in tmp_path ('idle' or 'write'); kill every one at the end."""
    procs = []

    def start(what='idle'):
        proc = subprocess.Popen([sys.executable, '-c', HOLDER, str(tmp_path), what],
                                stdout=subprocess.PIPE, text=True)
        procs.append(proc)
        assert proc.stdout.readline() == 'locked\n', 'the holder did not take the lock'
        return proc
    yield start
    for proc in procs:
        proc.kill()
        proc.wait(5)


def flushes(proc, count):
    """Wait for count more flushes of a writing holder."""
    for _ in range(count):
        assert proc.stdout.readline().startswith('flushed'), 'the holder died'


def test_a_second_recorder_is_refused_naming_the_folder_and_the_holder(tmp_path, holder):
    proc = holder()
    with pytest.raises(episode_folder.FolderBusy) as refused:
        episode_folder.FolderLock(str(tmp_path), '/second')
    assert str(tmp_path) in str(refused.value)
    assert 'pid %d /holder' % proc.pid in str(refused.value)
    assert refused.value.holder == 'pid %d /holder' % proc.pid
    assert sorted(os.listdir(str(tmp_path))) == [recording.LOCK_FILE]  # nothing else made


def test_a_killed_holder_leaves_no_lock_behind(tmp_path, holder):
    proc = holder()
    proc.send_signal(signal.SIGKILL)  # as kill -9; recorder.launch respawns 1 s later
    proc.wait(5)
    lock = episode_folder.FolderLock(str(tmp_path), '/respawned')
    assert lock.held()
    with open(lock.path) as source:
        assert source.read() == 'pid %d /respawned\n' % os.getpid()


def test_a_live_recorders_active_bag_is_never_repaired(tmp_path, holder):
    earlier = episode_folder.FolderLock(str(tmp_path), '/earlier')
    earlier.release()
    proc = holder('write')
    flushes(proc, 2)
    active = tmp_path / ('episode_live' + recording.ACTIVE)
    meta = (tmp_path / 'episode_live.yaml').read_bytes()
    size = active.stat().st_size
    with pytest.raises(episode_folder.FolderBusy):  # what a second recorder's start meets first
        episode_folder.FolderLock(str(tmp_path), '/second')
    with pytest.raises(RuntimeError):  # repairing without the lock is refused
        episode_files.recover(earlier)
    flushes(proc, 3)
    assert active.stat().st_size > size  # the live episode goes on as it was
    assert (tmp_path / 'episode_live.yaml').read_bytes() == meta
    assert not (tmp_path / 'episode_live.bag').exists()

    proc.send_signal(signal.SIGKILL)  # now it is a leftover: the next holder repairs it
    proc.wait(5)
    lock = episode_folder.FolderLock(str(tmp_path), '/respawned')
    [(path, repaired, error)] = episode_files.recover(lock)
    assert (path, repaired, error) == (str(active), str(tmp_path / 'episode_live.bag'), '')
    with rosbag.Bag(repaired) as bag:  # whole: opens without a reindex
        assert bag.get_message_count() >= 5
    assert yaml.safe_load(open(str(tmp_path / 'episode_live.yaml')))['ended_cleanly'] is False


def unindexed(directory, name, count):
    """Leave name.bag as an older recorder could: messages flushed, no index."""
    writer = episode_files.BagWriter(directory, name)
    for k in range(count):
        writer.write('/x', raw_float(k), 1000.0 + 0.1 * k)
    writer.flush()
    writer.abandon()
    os.replace(writer.active_path, writer.path)
    metadata.write_metadata(os.path.join(directory, name + recording.META),
                            {'name': name, 'ended_cleanly': True, 'duration_s': 4.47})
    return writer.path


def raw_float(value):
    return raw(Float32(value), '/x')


def test_a_bag_without_its_index_is_repaired_and_one_beyond_repair_renamed(tmp_path):
    directory = str(tmp_path)
    broken = unindexed(directory, 'episode_old', 20)
    whole = episode_files.BagWriter(directory, 'episode_whole')
    whole.write('/x', raw_float(1.0), 1000.0)
    whole.close()
    garbage = tmp_path / 'episode_garbage.bag'
    garbage.write_bytes(episode_folder.BAG_VERSION_LINE + b'\x00' * 100)
    with pytest.raises(rosbag.ROSBagUnindexedException):
        rosbag.Bag(broken)
    assert [episode_folder.is_whole(p) for p in (broken, whole.path, str(garbage))] == [
        False, True, False]
    whole_mtime = os.stat(whole.path).st_mtime_ns

    results = episode_files.recover(episode_folder.FolderLock(directory, '/test'))
    assert [(os.path.basename(p), os.path.basename(r)) for p, r, _ in results] == [
        ('episode_garbage.bag', ''), ('episode_old.bag', 'episode_old.bag')]
    assert 'renamed episode_garbage.bag.broken' in results[0][2] and results[1][2] == ''
    assert (tmp_path / 'episode_garbage.bag.broken').exists() and not garbage.exists()
    with rosbag.Bag(broken) as bag:
        assert [m.data for _, m, _ in bag.read_messages()] == [float(k) for k in range(20)]
    meta = yaml.safe_load(open(str(tmp_path / 'episode_old.yaml')))
    assert meta['ended_cleanly'] is False and meta['topics'] == {'/x': 20}
    assert meta['duration_s'] == pytest.approx(1.9)
    assert os.stat(whole.path).st_mtime_ns == whole_mtime  # a whole bag is left alone
    assert episode_folder.not_whole(directory) == []


def test_a_whole_bag_is_whole_from_its_header_alone(tmp_path):
    writer = episode_files.BagWriter(str(tmp_path), 'episode_x')
    assert not episode_folder.is_whole(writer.active_path)  # while written: no index yet
    writer.write('/x', raw_float(1.0), 1000.0)
    writer.close()
    assert episode_folder.is_whole(writer.path)
    with open(writer.path, 'r+b') as bag:  # cut off the index: the header points past the end
        bag.truncate(4096)
    assert not episode_folder.is_whole(writer.path)
    (tmp_path / 'notes.bag').write_text('not a rosbag')  # not ours to judge
    assert episode_folder.is_whole(str(tmp_path / 'notes.bag'))
