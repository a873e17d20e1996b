"""What the benchmark scripts share: a private roscore, percentiles, node processes and the
GUI benchmarks' measured frame loop."""
import contextlib
import glob
import math
import os
import shutil
import signal
import socket
import subprocess
import tempfile
import time

import psutil
import rosgraph
from PyQt5 import QtCore


def percentile(values, fraction):
    """Return the nearest-rank percentile of values, fraction in (0, 1] (0.99 for p99)."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(int(math.ceil(fraction * len(ordered))) - 1, 0))]


def start_process(args, log):
    """Start args in a session of its own (output to the open file log); return the Popen."""
    return subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def stop_process(process):
    """Stop a start_process Popen and its children: SIGINT to its group, SIGKILL after 10 s."""
    if process.poll() is None:
        os.killpg(process.pid, signal.SIGINT)
        try:
            process.wait(10)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            process.wait()


def _tree(process):
    """Return psutil.Processes of a Popen's process and its live children ([] once gone)."""
    try:
        root = psutil.Process(process.pid)
        return [root] + root.children(recursive=True)
    except psutil.NoSuchProcess:
        return []


def cpu_seconds(process):
    """Return the CPU time (s) used so far by a Popen's process and its live children."""
    total = 0.0
    for member in _tree(process):
        try:
            times = member.cpu_times()
        except psutil.NoSuchProcess:
            continue
        total += times.user + times.system
    return total


def run_queue_wait_s(process):
    """Return the time (s) the threads of a Popen's process tree have waited for a CPU so far.

    Linux schedstat (run_delay) summed over the live threads: time runnable but not running.
    """
    total_ns = 0
    for member in _tree(process):
        for path in glob.glob('/proc/%d/task/*/schedstat' % member.pid):
            try:
                with open(path) as stat:
                    total_ns += int(stat.read().split()[1])
            except (OSError, ValueError, IndexError):
                continue
    return total_ns / 1e9


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


def run_for(seconds):
    """Run a Qt event loop for `seconds` (not app.exec_: quitting the app more than once would
    trigger pyqtgraph's exit clean-up in the middle of the benchmark)."""
    loop = QtCore.QEventLoop()
    QtCore.QTimer.singleShot(int(seconds * 1000), loop.quit)
    loop.exec_()


def measure_frames(window, interval_ms, seconds, warm_up_s, also=(), reset=None):
    """Draw a GUI window's frames on a QTimer and measure them and this process's CPU.

    Every interval_ms (None: no frames, the feed alone) the timer calls window.frame() and then
    each function of `also`; after warm_up_s reset() (if given) clears the caller's counters,
    and then `seconds` are measured.

    Returns:
        (frame() calls per second, CPU time per wall second in % of one core, wall s measured)
    """
    timer = QtCore.QTimer()
    timer.timeout.connect(window.frame)
    for function in also:
        timer.timeout.connect(function)
    if interval_ms is not None:
        timer.start(interval_ms)
    run_for(warm_up_s)
    if reset is not None:
        reset()
    frames = window.frames
    start_wall, start_cpu = time.monotonic(), time.process_time()
    run_for(seconds)
    wall_s = time.monotonic() - start_wall
    cpu_s = time.process_time() - start_cpu
    timer.stop()
    return (window.frames - frames) / wall_s, 100.0 * cpu_s / wall_s, wall_s
