"""Harness for two-host ROS tests: a network test bed (tools/netbed) with a ROS master on the
robot host, processes started inside the hosts' namespaces, and a teardown that always runs.

    from netbed_testing import RosBed
    with RosBed(work_dir) as rb:               # skip (pytest) when namespaces cannot be made
        rb.roscore()                           # master in the robot namespace, on a free port
        rb.roslaunch('robot', 'robot.launch', 'run_side_L:=false')
        rb.roslaunch('operator', 'operator.launch', 'sim_puppet:=true', 'rviz:=false')
        listener = rb.python('operator', HELPERS / 'ros_node.py', 'listen', '/chatter',
                             'std_msgs/String')
        lines = listener.wait_for(lambda p: p.json_lines()[1:] or None, 20, 'a message')
        rb.bed.set(delay_ms=20, loss=0.01); rb.bed.cut(); rb.bed.restore()
        rb.call_in('intruder', some_probe)     # a function run inside a namespace, in-process

In pytest, use the `ros_bed` fixture of conftest.py. Each process gets ROS_MASTER_URI (the
robot host's master), ROS_IP (its host's address; ROS_HOSTNAME removed: no host name must
resolve), its host's ROS_HOME and ROS_LOG_DIR under work_dir, and a log file
work_dir/logs/NAME.log holding its stdout and stderr (read it with Proc.lines()). rospy can
init only once per process, so ROS code runs in child processes (helpers/ros_node.py) that
report through their stdout; plain sockets and XML-RPC probes run in-process through call_in.
Teardown stops every process by its process group (SIGINT, SIGTERM, SIGKILL), then removes
the bed, whether the test passed or not; beds of earlier crashed runs are removed first.
"""
import json
import os
import pathlib
import shutil
import signal
import socket
import subprocess
import sys
import time
import xmlrpc.client

ROOT = pathlib.Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / 'tools'))
from netbed import bed as bedlib  # noqa: E402
from netbed import netns  # noqa: E402
from ros_probes import xmlrpc_call  # noqa: E402

HELPERS = pathlib.Path(__file__).resolve().parent / 'helpers'
RULES = ROOT / 'catkin_ws' / 'src' / 'robopuppet' / 'config' / 'nftables' / 'robopuppet.nft'
PYTHON = '/usr/bin/python3'


class BedUnavailable(RuntimeError):
    """This machine cannot build a bed (not root, no network namespaces, no TUN device)."""


def check_usable():
    """Raise BedUnavailable, saying why, when a bed cannot be built here."""
    if os.geteuid() != 0:
        raise BedUnavailable('network tests need root: they create network namespaces')
    for tool in ('ip',):
        if shutil.which(tool) is None:
            raise BedUnavailable('network tests need `%s` (Debian package iproute2)' % tool)
    if not os.path.exists('/dev/net/tun'):
        raise BedUnavailable('network tests need the TUN device /dev/net/tun')
    probe = 'rpchk%d' % os.getpid()
    try:
        netns.add(probe)
    except netns.NetnsError as err:
        raise BedUnavailable('cannot create a network namespace: %s' % err) from None
    finally:
        netns.delete(probe)


def require_ros():
    """Fail clearly when ROS is not in the environment (source tools/env.sh)."""
    if shutil.which('roscore') is None or 'ROS_PACKAGE_PATH' not in os.environ:
        raise RuntimeError('ROS is not set up: run `. tools/env.sh` first')


class Proc:
    """A process started in a namespace, with its log file."""

    def __init__(self, name, host, popen, log_path):
        self.name, self.host, self.popen, self.log_path = name, host, popen, log_path

    @property
    def pid(self):
        return self.popen.pid

    def alive(self):
        return self.popen.poll() is None

    def text(self):
        try:
            return pathlib.Path(self.log_path).read_text(errors='replace')
        except OSError:
            return ''

    def lines(self):
        return self.text().splitlines()

    def json_lines(self):
        """Return the lines of its output that are JSON objects, parsed."""
        out = []
        for line in self.lines():
            if line.startswith('{'):
                try:
                    out.append(json.loads(line))
                except ValueError:
                    pass
        return out

    def tail(self, n_chars=3000):
        return '--- %s (%s, pid %d, log %s) ---\n%s' % (
            self.name, self.host, self.pid, self.log_path, self.text()[-n_chars:])

    def wait_for(self, probe, timeout_s, what):
        """Poll probe(self) until it returns something truthy; return that.

        Raises:
            AssertionError: timeout_s passed, or the process ended first (with its log tail).
        """
        deadline = time.monotonic() + timeout_s
        while True:
            value = probe(self)
            if value:
                return value
            if not self.alive():
                raise AssertionError('%s ended (code %s) before %s\n%s'
                                     % (self.name, self.popen.returncode, what, self.tail()))
            if time.monotonic() > deadline:
                raise AssertionError('%s: no %s within %.0f s\n%s'
                                     % (self.name, what, timeout_s, self.tail()))
            time.sleep(0.1)

    def signal(self, sig):
        """Send sig to its process group, if it still runs."""
        if self.popen.poll() is None:
            try:
                os.killpg(self.pid, sig)
            except ProcessLookupError:
                pass

    def stop(self, timeout_s=8.0):
        """Stop its process group: SIGINT (roslaunch shuts down cleanly), SIGTERM, SIGKILL."""
        stop_all([self], timeout_s)


def stop_all(procs, timeout_s=8.0):
    """Stop processes together (each by its process group): SIGINT, then SIGTERM after
    timeout_s, then SIGKILL. (What escaped its group goes with the bed: Bed.down() stops every
    process left in its namespaces, by id.)"""
    for sig, wait_s in ((signal.SIGINT, timeout_s), (signal.SIGTERM, 3.0),
                        (signal.SIGKILL, 3.0)):
        running = [p for p in procs if p.popen.poll() is None]
        for proc in running:
            proc.signal(sig)
        deadline = time.monotonic() + wait_s
        for proc in running:
            try:
                proc.popen.wait(max(deadline - time.monotonic(), 0.01))
            except subprocess.TimeoutExpired:
                pass


class RosBed:
    """A bed with a ROS master on the robot host, and the processes of one test."""

    def __init__(self, work_dir, name=None, seed=1):
        self.work_dir = pathlib.Path(work_dir)
        self.bed = bedlib.Bed(name or 'rp%d' % os.getpid())
        self.seed = seed
        self.master_uri = None
        self.procs = []
        self._master_proc = None
        self._started = 0  # processes ever started: numbers their log files

    def __enter__(self):
        check_usable()
        bedlib.gc()
        (self.work_dir / 'logs').mkdir(parents=True, exist_ok=True)
        self.bed.up(seed=self.seed, owner_pid=os.getpid())
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def close(self):
        """Stop every process (the master last) and remove the bed, whatever happens."""
        try:
            try:
                self.reset_link()  # shutdown traffic (unregistering) should not crawl
            except bedlib.BedError:
                pass  # the forwarder is gone already; Bed.down() cleans up anyway
            # The master last: nodes unregister as they shut down (roscpp's wait for it).
            stop_all([p for p in self.procs if p is not self._master_proc])
            stop_all(self.procs)
        finally:
            self.bed.down()

    def reset_link(self):
        """Restore both directions and clear delay, jitter and loss."""
        self.bed.restore()
        self.bed.set(delay_ms=0, jitter_ms=0, loss=0)

    def stop_started(self, first):
        """Stop the processes started after the first `first` ones (those of one test)."""
        stop_all(self.procs[first:])
        del self.procs[first:]

    def address(self, host):
        return self.bed.address(host)

    def env(self, host, extra=None):
        """Return the environment of a process on `host` (see the module docstring)."""
        env = self.bed.host_env(host)
        home = self.work_dir / host
        env.update(ROS_HOME=str(home / 'ros_home'), ROS_LOG_DIR=str(home / 'log'),
                   PYTHONUNBUFFERED='1')
        if self.master_uri:
            env['ROS_MASTER_URI'] = self.master_uri
        env.update(extra or {})
        return env

    def start(self, host, argv, name=None, env=None):
        """Start argv inside `host`'s namespace in a process group of its own; return a Proc."""
        self._started += 1
        name = '%d-%s' % (self._started,
                          name or '%s-%s' % (host, os.path.basename(str(argv[0]))))
        log_path = self.work_dir / 'logs' / ('%s.log' % name)
        with open(log_path, 'w') as log:
            popen = subprocess.Popen(self.bed.command(host, [str(a) for a in argv]),
                                     env=self.env(host, env), stdout=log,
                                     stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                     start_new_session=True, cwd=str(self.work_dir))
        proc = Proc(name, host, popen, log_path)
        self.procs.append(proc)
        return proc

    def free_port(self, host):
        """Return a TCP port free on `host`'s address (its namespace is the bed's own)."""
        def pick():
            sock = socket.socket()
            try:
                sock.bind((self.address(host), 0))
                return sock.getsockname()[1]
            finally:
                sock.close()
        return self.bed.call_in(host, pick)

    def call_in(self, host, function, *args, **kwargs):
        """Run function(*args, **kwargs) in a thread inside `host`'s namespace."""
        return self.bed.call_in(host, function, *args, **kwargs)

    def master_call(self, host, method, *args, timeout_s=2.0):
        """Call a ROS master API method from `host`; return its value (code 1 checked)."""
        code, message, value = self.call_in(host, xmlrpc_call, self.master_uri, method,
                                            '/netbed_test', *args, timeout_s=timeout_s)
        if code != 1:
            raise RuntimeError('master %s: %s' % (method, message))
        return value

    def roscore(self, timeout_s=30.0):
        """Start roscore in the robot namespace on a free port; return the master's URI once
        it answers."""
        require_ros()
        port = self.free_port('robot')
        self.master_uri = 'http://%s:%d/' % (self.address('robot'), port)
        proc = self._master_proc = self.start('robot', ['roscore', '-p', port], name='roscore')

        def answers(_proc):
            try:
                self.master_call('robot', 'getPid', timeout_s=1.0)
                return True
            except (OSError, RuntimeError, xmlrpc.client.Error):
                return False
        proc.wait_for(answers, timeout_s, 'master answering at %s' % self.master_uri)
        return self.master_uri

    def roslaunch(self, host, launch_file, *args, name=None):
        """Start `roslaunch robopuppet launch_file args...` on `host` (master must be up)."""
        return self.start(host, ['roslaunch', '--wait', 'robopuppet', launch_file] + list(args),
                          name=name or '%s-%s' % (host, launch_file.replace('.launch', '')))

    def rosrun(self, host, package, executable, *args, name=None):
        return self.start(host, ['rosrun', package, executable] + list(args),
                          name=name or '%s-%s' % (host, executable))

    def python(self, host, script, *args, name=None):
        """Start a helper script with /usr/bin/python3 on `host`."""
        return self.start(host, [PYTHON, script] + list(args),
                          name=name or '%s-%s' % (host, pathlib.Path(script).stem))

    def wait_registered(self, host, kind, name, timeout_s=30.0):
        """Wait until the master lists `name` as a topic publisher, subscriber or a service
        (kind 0, 1, 2 of getSystemState); return the nodes that provide it."""
        deadline = time.monotonic() + timeout_s
        while True:
            try:
                for entry, nodes in self.master_call(host, 'getSystemState')[kind]:
                    if entry == name and nodes:
                        return nodes
            except (OSError, RuntimeError, xmlrpc.client.Error):
                pass
            if time.monotonic() > deadline:
                raise AssertionError('%s not registered within %.0f s\n%s' % (
                    name, timeout_s, '\n'.join(p.tail(1500) for p in self.procs)))
            time.sleep(0.2)

    def lock_down(self, hosts=('operator', 'robot')):
        """Load the repository's nftables rule set into the hosts' namespaces."""
        text = RULES.read_text()
        for host in hosts:
            bedlib.load_rules(self.bed, host, text)
