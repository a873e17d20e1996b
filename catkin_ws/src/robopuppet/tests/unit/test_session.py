"""Unit tests of the recorder's episodes (session.Recorder) and its files (episode_files)."""
import io
import os
import signal
import subprocess
import sys
import textwrap
import time
import types

import pytest
import rosbag
import rospy
import yaml
from std_msgs.msg import Float32, UInt8

from robopuppet.episodes import episode_files, episode_folder, metadata, recording
from robopuppet.episodes.session import Recorder

FREE = 10e9


def raw(msg, topic):
    """Return msg as rospy.AnyMsg receives it: its bytes and connection header."""
    buff = io.BytesIO()
    msg.serialize(buff)
    anymsg = rospy.AnyMsg()
    anymsg._buff = buff.getvalue()
    anymsg._connection_header = {'topic': topic, 'type': msg._type, 'md5sum': msg._md5sum,
                                 'message_definition': msg._full_text, 'latching': '0'}
    return anymsg


def files(free=FREE):
    """episode_files with a free-space figure of our choosing (bytes, or an OSError)."""
    def free_bytes(_):
        if isinstance(free, Exception):
            raise free
        return free
    return types.SimpleNamespace(BagWriter=episode_files.BagWriter, free_bytes=free_bytes,
                                 write_metadata=metadata.write_metadata)


def start(recorder, notes='', stamp_s=100.0):
    return recorder.start(notes, stamp_s, 1706711101.0, 10.0, {'R': 'f' * 64}, True)


def test_an_episode_is_a_bag_with_every_message_and_metadata_after_a_clean_stop(tmp_path):
    recorder = Recorder(str(tmp_path / 'new'), ('R',), ('room_camera',), 200.0, files())
    ok, error, episode = start(recorder, 'first notes')
    active = episode + '.active'  # written as .bag.active, named by its final .bag
    assert ok and error == '' and episode.endswith('.bag') and os.path.exists(active)
    assert not os.path.exists(episode)
    meta_path = episode[:-len('.bag')] + '.yaml'
    assert yaml.safe_load(open(meta_path))['ended_cleanly'] is False
    for k in range(50):
        recorder.write('/puppet/arm_R/gripper_0', raw(Float32(k), 'x'), 100.0 + k * 0.01)
    recorder.write('/puppet/arm_R/user_btn', raw(UInt8(4), 'x'), 100.6)
    assert recorder.status(101.0)[:2] == (True, episode)
    assert recorder.status(101.0).messages == 51
    ok, error, bag_path = recorder.stop('better notes', 102.0)
    assert ok and bag_path == episode and not os.path.exists(active)
    with rosbag.Bag(bag_path) as bag:
        values = [m.data for _, m, _ in bag.read_messages('/puppet/arm_R/gripper_0')]
        stamps = [t.to_sec() for _, _, t in bag.read_messages()]
    assert values == list(range(50)) and stamps[0] == pytest.approx(100.0)
    meta = yaml.safe_load(open(meta_path))
    assert meta['ended_cleanly'] is True and meta['duration_s'] == 2.0
    assert meta['notes'] == 'better notes' and meta['sides'] == ['R'] and meta['sim'] is True
    assert meta['cameras'] == ['room_camera']
    assert meta['topics'] == {'/puppet/arm_R/gripper_0': 50, '/puppet/arm_R/user_btn': 1}
    assert recorder.status(200.0) == recording.Status(False, bag_path, 2.0,
                                                      os.path.getsize(bag_path), 51, '')


def test_an_episode_holds_only_what_came_while_it_ran(tmp_path):
    recorder = Recorder(str(tmp_path), ('R',), (), 200.0, files())
    recorder.write('/a', raw(Float32(-1), 'x'), 99.0)  # idle: dropped, not kept for later
    bags = []
    for episode in range(2):
        bags.append(start(recorder, stamp_s=100.0 + 10 * episode)[2])
        recorder.write('/a', raw(Float32(episode), 'x'), 100.5 + 10 * episode)
        recorder.stop('', 101.0 + 10 * episode)
        recorder.write('/a', raw(Float32(-2), 'x'), 101.5 + 10 * episode)
    for episode, bag_path in enumerate(bags):
        with rosbag.Bag(bag_path) as bag:
            got = [(t, m.data, s.to_sec()) for t, m, s in bag.read_messages()]
        assert got == [('/a', float(episode), 100.5 + 10 * episode)]


def test_one_episode_at_a_time_and_names_never_collide(tmp_path):
    recorder = Recorder(str(tmp_path), ('R',), (), 200.0, files())
    first = start(recorder)[2]
    assert start(recorder) == (False, 'already recording %s' % first, first)
    assert recorder.stop('', 101.0)[0]
    second = start(recorder)[2]  # same wall-clock second: a suffix
    assert second.endswith('_2.bag')
    assert recorder.stop('', 101.0)[0]
    assert recorder.stop('', 101.0)[:2] == (False, 'not recording')


def test_a_nearly_full_disk_refuses_to_start_and_stops_a_running_episode(tmp_path):
    low = files(free=150e6)
    recorder = Recorder(str(tmp_path), ('R',), (), 200.0, low)
    ok, error, _ = start(recorder)
    assert not ok and 'disk nearly full' in error and os.listdir(str(tmp_path)) == []
    assert recorder.status(100.0).problem == error
    recorder._files = files()
    assert start(recorder)[0]
    recorder.write('/a', raw(Float32(1), 'x'), 100.5)
    recorder._files = low
    recorder.tick(101.0)
    status = recorder.status(101.0)
    assert not status.recording and 'disk nearly full' in status.problem
    bag_path = status.episode
    with rosbag.Bag(bag_path) as bag:  # what was written is kept, readable
        assert bag.get_message_count() == 1


def test_an_unwritable_directory_is_a_clear_refusal(tmp_path):
    recorder = Recorder(str(tmp_path / 'a_file' / 'below'), ('R',), (), 200.0, files())
    (tmp_path / 'a_file').write_text('')
    ok, error, episode = start(recorder)
    assert not ok and episode == '' and 'cannot use' in error and 'a_file' in error
    broken = Recorder(str(tmp_path), ('R',), (), 200.0, files(free=PermissionError(13, 'denied')))
    assert 'denied' in start(broken)[1]


def test_a_failing_write_stops_the_episode_and_says_why(tmp_path):
    recorder = Recorder(str(tmp_path), ('R',), (), 200.0, files())
    start(recorder)

    class Full:
        def __getattr__(self, name):
            raise OSError(28, 'No space left on device')
    recorder._writer._bag = Full()
    assert recorder.write('/a', raw(Float32(1), 'x'), 100.5) is True
    status = recorder.status(101.0)
    assert not status.recording and 'No space left on device' in status.problem
    assert recorder.write('/a', raw(Float32(1), 'x'), 100.6) is False  # idle: ignored


WRITER = textwrap.dedent('''
    import sys, time
    import rospy
    from std_msgs.msg import Float32
    from robopuppet.episodes import episode_files
    sys.path.insert(0, %r)
    from test_session import raw
    writer = episode_files.BagWriter(sys.argv[1], 'episode_killed')
    start, last_flush, k = time.monotonic(), time.monotonic(), 0
    while True:
        writer.write('/x', raw(Float32(k), '/x'), 1000.0 + time.monotonic() - start)
        k += 1
        if time.monotonic() - last_flush >= 0.5:
            writer.flush()
            last_flush = time.monotonic()
            print(k, time.monotonic() - start, flush=True)
        time.sleep(0.002)
''') % os.path.dirname(os.path.abspath(__file__))


def test_a_killed_writer_leaves_an_active_bag_that_repair_recovers(tmp_path):
    metadata.write_metadata(str(tmp_path / 'episode_killed.yaml'),
                            {'name': 'episode_killed', 'ended_cleanly': False})
    proc = subprocess.Popen([sys.executable, '-c', WRITER, str(tmp_path)],
                            stdout=subprocess.PIPE, text=True)
    try:
        lines = []
        while len(lines) < 4:  # two seconds of writing, flushed every half second
            lines.append(proc.stdout.readline())
            assert lines[-1], 'the writer died'
        killed_at = time.monotonic()
        proc.send_signal(signal.SIGKILL)
        proc.wait(5)
    finally:
        proc.kill()
    written_s = float(lines[-1].split()[1]) + (time.monotonic() - killed_at)
    assert episode_folder.leftovers(str(tmp_path)) == [str(tmp_path / 'episode_killed.bag.active')]
    path = episode_files.repair(str(tmp_path / 'episode_killed.bag.active'))
    assert episode_folder.leftovers(str(tmp_path)) == []
    with rosbag.Bag(path) as bag:
        values = [m.data for _, m, _ in bag.read_messages('/x')]
        end_s = bag.get_end_time() - 1000.0
    assert values == [float(k) for k in range(len(values))]  # in order, none missing
    assert len(values) >= int(lines[-1].split()[0])           # all that was flushed
    assert end_s > written_s - 1.0                            # at most ~1 s lost
    meta = yaml.safe_load(open(str(tmp_path / 'episode_killed.yaml')))
    assert meta['ended_cleanly'] is False and meta['topics'] == {'/x': len(values)}
