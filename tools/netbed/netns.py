"""Network-namespace primitives for the bed: ip commands, sysctls, threads and sockets inside a
namespace, and stopping a namespace's processes by their ids.

    from netbed import netns
    netns.add('rp123-op')
    netns.ip('-n', 'rp123-op', 'link', 'set', 'lo', 'up')
    sock = netns.socket_in('rp123-op', socket.AF_INET, socket.SOCK_DGRAM)  # lives in rp123-op
    netns.call_in('rp123-op', some_function, arg)   # runs in a thread that entered rp123-op
    netns.stop_processes('rp123-op'); netns.delete('rp123-op')

A thread that enters a namespace (setns) affects only itself, and a socket belongs for good to
the namespace it was created in: so a test can talk through the bed from its own process
without starting one per probe. Needs root (CAP_SYS_ADMIN) and iproute2's `ip`.
"""
import ctypes
import os
import signal
import socket
import subprocess
import threading
import time

CLONE_NEWNET = 0x40000000
NETNS_DIR = '/run/netns'
_libc = ctypes.CDLL(None, use_errno=True)


class NetnsError(RuntimeError):
    """An ip command or a namespace operation failed."""


def ip(*args, check=True, input_text=None):
    """Run `ip ARGS...`; return its stdout. Raises NetnsError with ip's message on failure."""
    proc = subprocess.run(('ip',) + args, input=input_text, capture_output=True, text=True)
    if check and proc.returncode != 0:
        raise NetnsError('ip %s: %s' % (' '.join(args), proc.stderr.strip()))
    return proc.stdout


def exists(name):
    """Return True when the named network namespace exists."""
    return os.path.exists(os.path.join(NETNS_DIR, name))


def listed():
    """Return the names of every named network namespace."""
    return [line.split()[0] for line in ip('netns', 'list').splitlines() if line.strip()]


def add(name):
    """Create a named network namespace with its loopback up."""
    ip('netns', 'add', name)
    ip('-n', name, 'link', 'set', 'lo', 'up')


def delete(name):
    """Delete a named network namespace (its devices go with it); nothing if it is gone."""
    if exists(name):
        ip('netns', 'delete', name, check=False)


def _enter(name):
    fd = os.open(os.path.join(NETNS_DIR, name), os.O_RDONLY)
    try:
        if _libc.setns(fd, CLONE_NEWNET) != 0:
            err = ctypes.get_errno()
            raise NetnsError('setns(%s): %s' % (name, os.strerror(err)))
    finally:
        os.close(fd)


def call_in(name, function, *args, **kwargs):
    """Run function(*args, **kwargs) in a new thread inside namespace `name`; return its result
    or raise its exception. Sockets it creates stay in that namespace."""
    result = {}

    def body():
        try:
            _enter(name)
            result['value'] = function(*args, **kwargs)
        except BaseException as err:  # handed to the caller's thread below
            result['error'] = err
    thread = threading.Thread(target=body, name='netns-%s' % name, daemon=True)
    thread.start()
    thread.join()
    if 'error' in result:
        raise result['error']
    return result['value']


def start_thread_in(name, function, *args):
    """Start a daemon thread that enters namespace `name` and runs function(*args)."""
    def body():
        _enter(name)
        function(*args)
    thread = threading.Thread(target=body, name='netns-%s' % name, daemon=True)
    thread.start()
    return thread


def socket_in(name, family=socket.AF_INET, kind=socket.SOCK_STREAM):
    """Return a socket that lives in namespace `name` (usable from any thread)."""
    return call_in(name, socket.socket, family, kind)


def set_sysctls(name, values):
    """Write net sysctls ({'net.ipv4.ip_forward': 1, ...}) inside namespace `name`."""
    def write():
        for key, value in values.items():
            with open('/proc/sys/' + key.replace('.', '/'), 'w') as f:
                f.write('%s\n' % value)
    call_in(name, write)


def pids(name):
    """Return the ids of the processes whose network namespace is `name`."""
    if not exists(name):
        return []
    out = ip('netns', 'pids', name, check=False)
    return [int(word) for word in out.split() if word.isdigit()]


def alive(pid):
    """Return True when process `pid` exists and is not a zombie."""
    try:
        with open('/proc/%d/stat' % pid) as f:
            return f.read().rsplit(')', 1)[1].split()[0] != 'Z'
    except (OSError, IndexError):
        return False


def start_time(pid):
    """Return when process `pid` started (clock ticks since boot), or None: with the pid it
    names one process, even after the pid is reused."""
    try:
        with open('/proc/%d/stat' % pid) as f:
            return int(f.read().rsplit(')', 1)[1].split()[19])
    except (OSError, IndexError, ValueError):
        return None


def stop_pids(pid_list, timeout_s=3.0):
    """SIGTERM the given processes, then SIGKILL those still alive after timeout_s."""
    for sig, wait_s in ((signal.SIGTERM, timeout_s), (signal.SIGKILL, 1.0)):
        pid_list = [pid for pid in pid_list if alive(pid)]
        for pid in pid_list:
            try:
                os.kill(pid, sig)
            except ProcessLookupError:
                pass
        deadline = time.monotonic() + wait_s
        while pid_list and time.monotonic() < deadline:
            pid_list = [pid for pid in pid_list if alive(pid)]
            time.sleep(0.05)


def stop_processes(name, timeout_s=3.0):
    """Stop every process inside namespace `name` (by id: SIGTERM, then SIGKILL)."""
    stop_pids(pids(name), timeout_s)
