"""What the benchmark scripts share: a private roscore and percentiles."""
import contextlib
import math
import os
import shutil
import socket
import subprocess
import tempfile
import time

import rosgraph


def percentile(values, fraction):
    """Return the nearest-rank percentile of values, fraction in (0, 1] (0.99 for p99)."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(int(math.ceil(fraction * len(ordered))) - 1, 0))]


def _free_port():
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        return sock.getsockname()[1]


@contextlib.contextmanager
def private_roscore(prefix):
    """Run a roscore on a free port, with ROS_HOME and logs in a temporary directory.

    Sets ROS_MASTER_URI, ROS_HOME and ROS_LOG_DIR for this process and its children, yields the
    temporary directory, and on exit stops the roscore and removes the directory.
    """
    work = tempfile.mkdtemp(prefix=prefix)
    port = _free_port()
    os.environ.update(ROS_MASTER_URI='http://127.0.0.1:%d' % port, ROS_HOME=work,
                      ROS_LOG_DIR=os.path.join(work, 'log'))
    core = subprocess.Popen(['roscore', '-p', str(port)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 20.0
        while not rosgraph.Master('/bench').is_online():
            if time.monotonic() > deadline or core.poll() is not None:
                raise RuntimeError('roscore did not start on port %d' % port)
            time.sleep(0.1)
        yield work
    finally:
        core.terminate()
        core.wait(10)
        shutil.rmtree(work, ignore_errors=True)
