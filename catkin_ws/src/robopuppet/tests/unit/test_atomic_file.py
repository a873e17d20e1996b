"""Unit tests of atomic_file: a file replaced whole or not at all (the kill test of the ini
files: test_config_store)."""
import os

import pytest

from robopuppet import atomic_file


def test_text_and_bytes_replace_the_file_and_keep_its_permissions(tmp_path):
    path = tmp_path / 'deeper' / 'model.npz'
    atomic_file.write_atomic(str(path), b'\x00\x01binary')     # the folder is made
    assert path.read_bytes() == b'\x00\x01binary'
    os.chmod(str(path), 0o600)
    atomic_file.write_atomic(str(path), 'text\n')
    assert path.read_text() == 'text\n' and (path.stat().st_mode & 0o777) == 0o600
    assert os.listdir(str(path.parent)) == ['model.npz']


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path, monkeypatch):
    path = tmp_path / 'arm_R.ini'
    path.write_text('old\n')

    def broken_replace(src, dst):
        raise OSError('disk full')

    monkeypatch.setattr(os, 'replace', broken_replace)
    with pytest.raises(OSError, match='disk full'):
        atomic_file.write_atomic(str(path), 'new\n' * 1000)
    assert path.read_text() == 'old\n'
    assert os.listdir(str(tmp_path)) == ['arm_R.ini']


def test_only_the_files_own_stale_temporaries_are_removed(tmp_path):
    (tmp_path / 'meta.yaml').write_text('kept')
    (tmp_path / '.meta.yaml.k3j2.tmp').write_text('half')
    (tmp_path / '.other.yaml.k3j2.tmp').write_text('not ours')
    removed = atomic_file.remove_stale_temporaries(str(tmp_path / 'meta.yaml'))
    assert removed == [str(tmp_path / '.meta.yaml.k3j2.tmp')]
    assert sorted(os.listdir(str(tmp_path))) == ['.other.yaml.k3j2.tmp', 'meta.yaml']
