"""The bed itself: its command line, bad requests, a dead forwarder, and cleanup after a crash.

Needs root (skipped otherwise). Run: tools/run_tests.py network.
"""
import json
import os
import signal
import socket
import subprocess
import sys
import time

import pytest

from netbed_testing import ROOT, bedlib, netns

NETBED = str(ROOT / 'tools' / 'netbed' / 'netbed')


def netbed(bed, *args):
    return subprocess.run([NETBED, args[0], '--name', bed.name] + list(args[1:]),
                          capture_output=True, text=True, timeout=60)


def udp_arrives(rb, src, dst, port):
    """Return True when a UDP packet src -> dst arrives within 0.5 s."""
    receiver = rb.bed.socket(dst, socket.AF_INET, socket.SOCK_DGRAM)
    sender = rb.bed.socket(src, socket.AF_INET, socket.SOCK_DGRAM)
    with receiver, sender:
        receiver.bind((rb.address(dst), port))
        receiver.settimeout(0.5)
        sender.sendto(b'?', (rb.address(dst), port))
        try:
            return receiver.recv(8) == b'?'
        except socket.timeout:
            return False


def test_the_command_line_sets_the_link_and_runs_commands_with_ros_ip(link_bed):
    done = netbed(link_bed.bed, 'set', '--delay-ms', '30', '--jitter-ms', '2', '--loss', '0.1',
                  '--direction', 'to-operator')
    assert done.returncode == 0, done.stderr
    links = link_bed.bed.status()['links']
    assert (links['to-operator']['delay_ms'], links['to-operator']['jitter_ms'],
            links['to-operator']['loss']) == (30.0, 2.0, 0.1)
    assert links['to-robot']['delay_ms'] == 0.0
    done = netbed(link_bed.bed, 'exec', 'robot', sys.executable, '-c',
                  'import os; print(os.environ["ROS_IP"], "ROS_HOSTNAME" in os.environ)')
    assert done.stdout.split() == [link_bed.address('robot'), 'False']


def test_bad_settings_get_a_clear_error_and_the_forwarder_goes_on(link_bed):
    done = netbed(link_bed.bed, 'set', '--loss', '1.5')
    assert done.returncode == 1 and 'loss must be within [0, 1]' in done.stderr
    with pytest.raises(bedlib.BedError, match='direction'):
        link_bed.bed.request({'cmd': 'cut', 'direction': 'sideways'})
    with pytest.raises(bedlib.BedError, match='unknown command'):
        link_bed.bed.request({'cmd': 'explode'})
    garbage = socket.socket(socket.AF_UNIX)
    garbage.connect(link_bed.bed.control_path)
    garbage.sendall(b'not json\n')
    assert json.loads(garbage.recv(4096).decode())['ok'] is False
    garbage.close()
    assert link_bed.bed.status()['links']['to-robot']['loss'] == 0.0
    assert udp_arrives(link_bed, 'operator', 'robot', 9600)


def test_a_dead_forwarder_stops_the_traffic_instead_of_bypassing_the_delay(ros_bed):
    assert udp_arrives(ros_bed, 'operator', 'robot', 9601)
    os.kill(ros_bed.bed.state()['forwarder_pid'], signal.SIGKILL)
    time.sleep(0.2)
    assert not udp_arrives(ros_bed, 'operator', 'robot', 9602)
    assert not udp_arrives(ros_bed, 'robot', 'operator', 9603)


def test_the_bed_of_a_crashed_run_is_removed(tmp_path):
    try:
        import netbed_testing
        netbed_testing.check_usable()
    except netbed_testing.BedUnavailable as err:
        pytest.skip(str(err))
    owner = subprocess.Popen(['sleep', '60'])
    bed = bedlib.Bed('rp%dgc' % os.getpid())
    try:
        bed.up(owner_pid=owner.pid)
        forwarder = bed.state()['forwarder_pid']
        assert bed.name not in bedlib.gc()  # its owner lives: kept
        owner.kill()
        owner.wait()
        assert bed.name in bedlib.gc()
        assert not bed.exists() and not os.path.exists(bed.state_dir)
        assert not netns.alive(forwarder)
        bed.down()  # idempotent
        done = subprocess.run([NETBED, 'down', '--name', bed.name], capture_output=True,
                              text=True)
        assert done.returncode == 0, done.stderr
    finally:
        owner.kill()
        owner.wait()
        bed.down()
