"""A tiny real file system for tests: full, read-only or writable (tmpfs, needs mount rights).

Shared by the config node's unit tests and rostests; unittest.SkipTest (which pytest honours
too) skips a test, saying why, where this machine does not let us mount.
"""
import contextlib
import os
import subprocess
import tempfile
import unittest


@contextlib.contextmanager
def tmpfs(size_kib, files, read_only=False, full=False):
    """Mount a tiny tmpfs holding files ({name: text}); yield its path; unmount it after.

    full: fill it with a file named 'filler' first; read_only: then remount it read-only.

    Raises unittest.SkipTest, saying why, when this machine does not let us mount.
    """
    mount_dir = tempfile.mkdtemp(prefix='robopuppet-config-tmpfs-')
    try:
        result = subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=%dk' % size_kib, 'tmpfs',
                                 mount_dir], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                check=False)
        if result.returncode != 0:
            raise unittest.SkipTest('cannot mount a tmpfs (needs root or CAP_SYS_ADMIN): %s'
                                    % result.stdout.decode(errors='replace').strip())
        try:
            for name, text in files.items():
                with open(os.path.join(mount_dir, name), 'w') as out:
                    out.write(text)
            if full:
                fd = os.open(os.path.join(mount_dir, 'filler'), os.O_WRONLY | os.O_CREAT)
                for chunk in (65536, 4096, 512, 1):
                    with contextlib.suppress(OSError):
                        while True:
                            os.write(fd, b'\0' * chunk)
                os.close(fd)
            if read_only:
                subprocess.run(['mount', '-o', 'remount,ro', mount_dir], check=True)
            yield mount_dir
        finally:
            if subprocess.run(['umount', mount_dir], check=False).returncode != 0:
                subprocess.run(['umount', '-l', mount_dir], check=False)
    finally:
        os.rmdir(mount_dir)
