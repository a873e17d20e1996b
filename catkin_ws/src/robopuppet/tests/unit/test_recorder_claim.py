"""Unit tests of the recorder's hold on its episodes folder (recorder_claim.FolderHold): refused
while another process holds the lock, taken at a later claim, the folder repaired once under it."""
from robopuppet.episodes import episode_folder, recorder_claim
from test_episode_files import holder, unindexed  # noqa: F401  (holder: a fixture)


def test_a_busy_folder_is_claimed_once_free_and_repaired_once(tmp_path, holder):  # noqa: F811
    proc = holder()
    hold = recorder_claim.FolderHold(str(tmp_path), None, '/recorder')
    assert 'is in use by another recorder (pid %d /holder)' % proc.pid in hold.claim()
    old = unindexed(str(tmp_path), 'episode_old', 3)
    assert not episode_folder.is_whole(old)   # not repaired without the lock
    proc.kill()
    proc.wait(5)
    assert hold.claim() == ''
    assert episode_folder.is_whole(old)
    later = unindexed(str(tmp_path), 'episode_later', 3)
    assert hold.claim() == ''
    assert not episode_folder.is_whole(later)  # repaired at the first claim only
