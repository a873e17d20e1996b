"""Unit tests of episode_folder: the folder lock within one process, which bags did not end
whole (from their header alone), and the ini fingerprint. test_episode_files runs the lock
against other processes."""
import hashlib
import os
import struct

import pytest

from robopuppet.episodes import episode_folder, recording


def bag_header(index_pos):
    """Return the start of a rosbag 2.0 whose header record says index_pos."""
    field = b'index_pos=' + struct.pack('<Q', index_pos)
    record = struct.pack('<i', len(field)) + field
    return episode_folder.BAG_VERSION_LINE + struct.pack('<i', len(record)) + record


def test_one_process_holds_a_folder_once_and_gives_it_back(tmp_path):
    lock = episode_folder.FolderLock(str(tmp_path / 'new'), '/first')
    assert lock.held()
    with pytest.raises(episode_folder.FolderBusy):  # flock: per open file, so also in-process
        episode_folder.FolderLock(str(tmp_path / 'new'), '/second')
    lock.release()
    assert not lock.held()
    episode_folder.FolderLock(str(tmp_path / 'new'), '/second').release()


def test_the_lock_file_names_its_holder(tmp_path):
    lock = episode_folder.FolderLock(str(tmp_path), '/recorder')
    assert lock.path == str(tmp_path / recording.LOCK_FILE)
    with open(lock.path) as source:
        assert source.read() == 'pid %d /recorder\n' % os.getpid()
    lock.release()


def test_a_bag_is_whole_when_its_index_lies_inside_the_file(tmp_path):
    whole, open_one, cut = (tmp_path / n for n in ('a.bag', 'b.bag', 'c.bag'))
    whole.write_bytes(bag_header(100).ljust(200, b'\0'))
    open_one.write_bytes(bag_header(0).ljust(200, b'\0'))  # as while it is written
    cut.write_bytes(bag_header(500).ljust(200, b'\0'))     # the index was cut off
    assert [episode_folder.is_whole(str(p)) for p in (whole, open_one, cut)] == [
        True, False, False]
    assert episode_folder.not_whole(str(tmp_path)) == [str(open_one), str(cut)]


def test_leftovers_are_the_active_bags(tmp_path):
    for name in ('episode_a' + recording.ACTIVE, 'episode_b' + recording.BAG, 'x.yaml'):
        (tmp_path / name).write_bytes(b'')
    assert episode_folder.leftovers(str(tmp_path)) == [
        str(tmp_path / ('episode_a' + recording.ACTIVE))]


def test_the_ini_fingerprint_is_the_files_sha256(tmp_path):
    ini = tmp_path / 'arm_R.ini'
    ini.write_bytes(b'[joint_0]\nhome_angle = 0.1\n')
    assert episode_folder.ini_fingerprint(str(ini)) == hashlib.sha256(
        ini.read_bytes()).hexdigest()
    assert episode_folder.ini_fingerprint(str(tmp_path / 'missing.ini')) is None
