"""The terminal command `calibrate` (and `sim_pose`) without ROS: its help names the keys and
the exit codes, and with no ROS master it says so and exits 1 within a few seconds."""
import os
import pathlib
import socket
import subprocess
import sys
import time

import pytest

from robopuppet.calibration import procedure

NODES = pathlib.Path(__file__).resolve().parents[2] / 'nodes'
NO_MASTER_BOUND_S = 8.0  # the command's own bound is 3 s; the rest is Python and rospy starting


def free_port():
    with socket.socket() as sock:
        sock.bind(('127.0.0.1', 0))
        return sock.getsockname()[1]


def run(command, *args, env=None, timeout_s=30.0):
    return subprocess.run([sys.executable, str(NODES / command)] + list(args),
                          capture_output=True, text=True, timeout=timeout_s,
                          env=dict(os.environ, **(env or {})))


def test_help_names_the_keys_and_the_exit_codes():
    done = run('calibrate', '--help')
    assert done.returncode == 0
    text = done.stdout
    for key in ('Enter  capture', 'r      take the previous pose again',
                'p      pose the virtual puppet', 'q      quit'):
        assert key in text
    assert 'exit status' in text
    for code in ('0  stored', '1  quit, Ctrl-C', '2  a joint flagged', '3  the store failed'):
        assert code in text
    assert 'no ROS master' in text


@pytest.mark.parametrize('command, args', [('calibrate', ['--side', 'R']),
                                           ('sim_pose', ['--side', 'R', 'pose', 'A'])])
def test_no_ros_master_fails_with_a_clear_message_within_seconds(command, args):
    uri = 'http://127.0.0.1:%d' % free_port()
    start = time.monotonic()
    done = run(command, *args, env={'ROS_MASTER_URI': uri}, timeout_s=3 * NO_MASTER_BOUND_S)
    assert time.monotonic() - start < NO_MASTER_BOUND_S
    assert done.returncode == 1
    assert 'no ROS master at %s' % uri in done.stderr


@pytest.mark.parametrize('words, name', [
    (['pose', 'A'], 'pose A'), (['b'], 'pose B'), (['zero'], "Baxter's zero pose"),
    (["Baxter's", 'zero', 'pose'], "Baxter's zero pose")])
def test_a_pose_by_name(words, name):
    assert procedure.pose_from_words(words).name == name


def test_a_typed_pose_and_refusals():
    assert procedure.pose_from_words('0 -0.5 0 0.5 0 0.5 0.03'.split()).angles_rad == (
        0.0, -0.5, 0.0, 0.5, 0.0, 0.5, 0.03)
    for words in (['pose', 'C'], ['1', '2'], '0 0 0 0 0 0 4'.split(), '0 0 0 0 0 0 nan'.split()):
        with pytest.raises(ValueError):
            procedure.pose_from_words(words)
    assert run('sim_pose', '--side', 'R', '1', '2').returncode == 2
