"""A two-host network test bed on one machine: operator and robot namespaces joined by a faulty
link through a "network" namespace, plus an intruder namespace on that network.

    import sys; sys.path.insert(0, 'tools')          # the folder that holds netbed/
    from netbed.bed import Bed
    bed = Bed('rp%d' % os.getpid())
    bed.up(seed=1)                     # namespaces rp123-op, rp123-rb, rp123-net, rp123-in
    bed.set(delay_ms=50, jitter_ms=10, loss=0.01)    # both directions; or direction='to-robot'
    bed.cut(); bed.restore()
    subprocess.Popen(bed.command('operator', ['ping', '-c1', bed.address('robot')]),
                     env=bed.host_env('operator'))
    bed.down()                         # idempotent, also after a crash (Bed(name).down())

Layout (addresses are private to the bed's namespaces; nothing else is ever addressed):

    operator 10.77.1.2 (link0) -- op0 10.77.1.1 \
    robot    10.77.2.2 (link0) -- rb0 10.77.2.1  >- network: policy routing -> TUN fwd0 ->
    intruder 10.77.3.2 (link0) -- in0 10.77.3.1 /     forwarder.py -> fwd0 -> out the right veth

Every packet arriving from a host's veth goes through the forwarder (forwarder.py), which delays
and drops operator<->robot packets per direction ('to-robot', 'to-operator') with a seeded
generator; if the forwarder dies, the routing rules blackhole the traffic rather than forward
it unimpaired. The state (forwarder pid, owner pid) and the control socket live in
/run/netbed/NAME/; `gc()` removes the beds whose owning process has died.
"""
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import time

from netbed import netns

TOOLS_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STATE_ROOT = '/run/netbed'
LINK_IF = 'link0'          # each host's interface on the private link
TUN_IF = 'fwd0'
# The hosts' TCP congestion control, as two lab machines would run it: Linux's default is cubic,
# which a namespace here cannot choose (this machine allows reno and bbr); reno acts as cubic on
# the bed's thin loss-free streams. A namespace would otherwise inherit this machine's bbr, whose
# ProbeRTT clamps each connection to 4 packets in flight for 200 ms + a round trip every 10 s
# (docs/remote.md: 55-63 ms p99 of samples held in serial_R's socket at 100 ms one way).
HOST_TCP_CC = 'reno'
ROUTE_TABLE = '100'
# host: (namespace suffix, address, the network's address on that host's link, its veth there)
HOSTS = {
    'operator': ('op', '10.77.1.2', '10.77.1.1', 'op0'),
    'robot': ('rb', '10.77.2.2', '10.77.2.1', 'rb0'),
    'intruder': ('in', '10.77.3.2', '10.77.3.1', 'in0'),
}
NETWORK = 'network'
NETWORK_SUFFIX = 'net'
PREFIX_LEN = 24
NAME_RE = re.compile(r'^[a-z][a-z0-9]{0,15}$')
PEERS = {'operator': 'robot', 'robot': 'operator'}


class BedError(RuntimeError):
    """The bed could not be built, reached or controlled."""


class Bed:
    """One bed, named `name` (lower-case letters and digits; namespaces are NAME-op etc.)."""

    def __init__(self, name, state_root=STATE_ROOT):
        if not NAME_RE.match(name):
            raise ValueError('bed name %r: use 1-16 lower-case letters and digits' % name)
        self.name = name
        self.state_dir = os.path.join(state_root, name)
        self.control_path = os.path.join(self.state_dir, 'ctl.sock')
        self._forwarder = None

    def namespace(self, host):
        """Return the namespace name of a host ('operator', 'robot', 'intruder', 'network')."""
        if host == NETWORK:
            return '%s-%s' % (self.name, NETWORK_SUFFIX)
        if host not in HOSTS:
            raise ValueError('unknown host %r: one of %s, network' % (host, ', '.join(HOSTS)))
        return '%s-%s' % (self.name, HOSTS[host][0])

    def namespaces(self):
        return [self.namespace(h) for h in (*HOSTS, NETWORK)]

    @staticmethod
    def address(host):
        """Return a host's address on the private link."""
        return HOSTS[host][1]

    def exists(self):
        return any(netns.exists(ns) for ns in self.namespaces())

    def up(self, seed='1', owner_pid=None):
        """Build the bed (after removing any remains of one with this name) and start its
        forwarder. owner_pid: the process whose death makes the bed garbage for gc()."""
        self.down()
        os.makedirs(self.state_dir)
        try:
            self._write_state(owner_pid)  # first, so that gc() finds a half-built bed too
            self._build(seed)
            self._write_state(owner_pid)
        except BaseException:
            self.down()
            raise

    def _build(self, seed):
        net = self.namespace(NETWORK)
        for ns in self.namespaces():
            netns.add(ns)
            # Quiet links: no IPv6 chatter; the network forwards with no reverse-path checks
            # (packets come back from the TUN device with the hosts' source addresses).
            netns.set_sysctls(ns, {'net.ipv6.conf.all.disable_ipv6': 1,
                                   'net.ipv6.conf.default.disable_ipv6': 1,
                                   'net.ipv4.conf.all.rp_filter': 0,
                                   'net.ipv4.conf.default.rp_filter': 0})
        netns.set_sysctls(net, {'net.ipv4.ip_forward': 1})
        for host, (_, address, gateway, veth) in HOSTS.items():
            ns = self.namespace(host)
            netns.set_sysctls(ns, {'net.ipv4.tcp_congestion_control': HOST_TCP_CC})
            # Both ends are created inside their namespaces: nothing appears in the root one.
            netns.ip('link', 'add', 'name', LINK_IF, 'netns', ns, 'type', 'veth',
                     'peer', 'name', veth, 'netns', net)
            netns.ip('-n', ns, 'addr', 'add', '%s/%d' % (address, PREFIX_LEN), 'dev', LINK_IF)
            netns.ip('-n', ns, 'link', 'set', LINK_IF, 'up')
            netns.ip('-n', ns, 'route', 'add', 'default', 'via', gateway)
            netns.ip('-n', net, 'addr', 'add', '%s/%d' % (gateway, PREFIX_LEN), 'dev', veth)
            netns.ip('-n', net, 'link', 'set', veth, 'up')
            # What comes in from a host goes to the forwarder; if the TUN route is gone
            # (forwarder dead) it is dropped, never forwarded unimpaired.
            netns.ip('-n', net, 'rule', 'add', 'iif', veth, 'lookup', ROUTE_TABLE, 'pref', '100')
            netns.ip('-n', net, 'rule', 'add', 'iif', veth, 'blackhole', 'pref', '200')
        netns.ip('-n', net, 'tuntap', 'add', 'dev', TUN_IF, 'mode', 'tun')
        netns.ip('-n', net, 'link', 'set', TUN_IF, 'up')
        netns.ip('-n', net, 'route', 'add', 'default', 'dev', TUN_IF, 'table', ROUTE_TABLE)
        self._start_forwarder(seed)

    def _start_forwarder(self, seed):
        log_path = os.path.join(self.state_dir, 'forwarder.log')
        argv = ['ip', 'netns', 'exec', self.namespace(NETWORK), sys.executable, '-m',
                'netbed.forwarder', '--tun', TUN_IF, '--control', self.control_path,
                '--seed', str(seed)]
        argv += ['--host=%s=%s' % (h, self.address(h)) for h in HOSTS]
        env = dict(os.environ, PYTHONPATH=TOOLS_DIR)
        with open(log_path, 'w') as log:
            self._forwarder = subprocess.Popen(argv, env=env, stdout=log, cwd='/',
                                               stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                                               start_new_session=True)
        deadline = time.monotonic() + 10.0
        while True:
            try:
                self.request({'cmd': 'ping'})
                return
            except BedError:
                if self._forwarder.poll() is not None or time.monotonic() > deadline:
                    with open(log_path) as log:
                        raise BedError('forwarder did not start:\n' + log.read()[-2000:])
                time.sleep(0.05)

    def _write_state(self, owner_pid):
        state = {'name': self.name, 'owner_pid': owner_pid,
                 'owner_started': netns.start_time(owner_pid) if owner_pid else None,
                 'forwarder_pid': self._forwarder.pid if self._forwarder else None,
                 'namespaces': self.namespaces(), 'created': time.time(),
                 'addresses': {h: self.address(h) for h in HOSTS}}
        with open(os.path.join(self.state_dir, 'state.json'), 'w') as f:
            json.dump(state, f, indent=1)

    def state(self):
        """Return the bed's state file as a dict ({} when there is none)."""
        try:
            with open(os.path.join(self.state_dir, 'state.json')) as f:
                return json.load(f)
        except (OSError, ValueError):
            return {}

    def down(self):
        """Remove everything the bed made: its processes (by id), namespaces, state folder.
        Idempotent, and works from a fresh Bed(name) after a crash."""
        for ns in self.namespaces():
            netns.stop_processes(ns)  # the forwarder and anything started inside
        if self._forwarder is not None:
            self._forwarder.wait()
            self._forwarder = None
        for ns in self.namespaces():
            netns.delete(ns)
        shutil.rmtree(self.state_dir, ignore_errors=True)

    def request(self, message, timeout_s=5.0):
        """Send one control request to the forwarder; return its answer (a dict).

        Raises:
            BedError: no forwarder answers, or it refused the request.
        """
        try:
            with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
                sock.settimeout(timeout_s)
                sock.connect(self.control_path)
                sock.sendall(json.dumps(message).encode() + b'\n')
                data = b''
                while not data.endswith(b'\n'):
                    chunk = sock.recv(65536)
                    if not chunk:
                        break
                    data += chunk
        except OSError as err:
            raise BedError('bed %s: no forwarder at %s (%s); is the bed up?'
                           % (self.name, self.control_path, err)) from None
        try:
            answer = json.loads(data.decode())
        except ValueError:
            raise BedError('bed %s: unreadable answer %r' % (self.name, data)) from None
        if not answer.get('ok'):
            raise BedError('bed %s: %s' % (self.name, answer.get('error')))
        return answer

    def set(self, direction='both', delay_ms=None, jitter_ms=None, loss=None):
        """Set one-way delay (ms), jitter (+- ms, uniform) and loss (0-1) of a direction."""
        return self.request({'cmd': 'set', 'direction': direction, 'delay_ms': delay_ms,
                             'jitter_ms': jitter_ms, 'loss': loss})

    def cut(self, direction='both'):
        """Cut the link (drops everything, including packets in flight) until restore()."""
        return self.request({'cmd': 'cut', 'direction': direction})

    def restore(self, direction='both'):
        return self.request({'cmd': 'restore', 'direction': direction})

    def status(self):
        """Return the forwarder's settings and counters per direction, and its CPU time."""
        return self.request({'cmd': 'status'})

    def host_env(self, host, env=None):
        """Return env (default os.environ) for a process on `host`: ROS_IP is the host's
        address and ROS_HOSTNAME is unset, so no host name ever needs to resolve."""
        env = dict(os.environ if env is None else env)
        env.pop('ROS_HOSTNAME', None)
        if host in HOSTS:
            env['ROS_IP'] = self.address(host)
        return env

    def command(self, host, argv):
        """Return the argv that runs `argv` inside a host's namespace."""
        return ['ip', 'netns', 'exec', self.namespace(host)] + list(argv)

    def call_in(self, host, function, *args, **kwargs):
        """Run function in a thread inside a host's namespace (netns.call_in)."""
        return netns.call_in(self.namespace(host), function, *args, **kwargs)

    def socket(self, host, family=socket.AF_INET, kind=socket.SOCK_STREAM):
        """Return a socket living in a host's namespace."""
        return netns.socket_in(self.namespace(host), family, kind)


def rules_for(text, link_if, peer_address):
    """Return the nftables rule set `text` with its LINK_IF and PEER_ADDR defines replaced."""
    out, n = re.subn(r'(?m)^define\s+LINK_IF\s*=.*$', 'define LINK_IF = "%s"' % link_if, text)
    out, m = re.subn(r'(?m)^define\s+PEER_ADDR\s*=.*$', 'define PEER_ADDR = %s' % peer_address,
                     out)
    if n != 1 or m != 1:
        raise BedError('the rule set must define LINK_IF and PEER_ADDR once each')
    return out


def load_rules(bed, host, text):
    """Load an nftables rule set, adapted to `host` of the bed (its link, its peer), into the
    host's namespace. Raises BedError with nft's message when nft refuses it."""
    rules = rules_for(text, LINK_IF, bed.address(PEERS[host]))
    proc = subprocess.run(bed.command(host, ['nft', '-f', '-']), input=rules, text=True,
                          capture_output=True)
    if proc.returncode != 0:
        raise BedError('nft in %s: %s' % (host, proc.stderr.strip()))


def beds(state_root=STATE_ROOT):
    """Return the names of the beds with a state folder."""
    try:
        return sorted(n for n in os.listdir(state_root) if NAME_RE.match(n))
    except OSError:
        return []


def gc(state_root=STATE_ROOT):
    """Remove the beds whose owner process has died (left by a crashed test run); return them."""
    removed = []
    for name in beds(state_root):
        bed = Bed(name, state_root)
        state = bed.state()
        owner = state.get('owner_pid')
        if owner and (not netns.alive(owner)
                      or netns.start_time(owner) != state.get('owner_started')):
            bed.down()
            removed.append(name)
    return removed
