"""The bed's user-space forwarder: IP packets between the hosts, with delay, jitter, loss, cuts.

It runs inside the bed's "network" namespace (bed.py starts it; you do not run it by hand):

    ip netns exec NS /usr/bin/python3 -m netbed.forwarder --tun fwd0 --control CTL.sock \
        --seed 1 --host operator=10.77.1.2 --host robot=10.77.2.2 --host intruder=10.77.3.2

Policy routing sends every packet that arrives from a host's veth into the TUN device fwd0; this
process reads it, holds it for its direction's delay (impairment.Impairment) and writes it back
into fwd0, whence the kernel routes it out of the destination host's veth. Directions:
'to-robot' (operator -> robot) and 'to-operator' (robot -> operator) are impaired; a packet
between any other two hosts of the bed (the intruder's) passes at once; a packet that is not
IPv4 or whose source or destination is not a host of the bed is dropped (nothing leaves the
bed). Random draws use one generator per direction seeded from --seed.

Control: a UNIX stream socket at --control takes one JSON request line per connection and
answers one JSON line: {"cmd": "ping"}, {"cmd": "status"},
{"cmd": "set", "direction": "both", "delay_ms": 50, "jitter_ms": 10, "loss": 0.01},
{"cmd": "cut", "direction": "to-robot"}, {"cmd": "restore", "direction": "both"},
{"cmd": "stop"}. A bad request gets {"ok": false, "error": ...} and the forwarder goes on.
SIGTERM and SIGINT stop it.

Scheduling: it asks for real-time scheduling (SCHED_FIFO, priority RT_PRIORITY), so that the
hosts' processes, which share this machine's cores, do not make the "network" late: a real link
does not wait for the hosts' CPUs. Its work is small (5-7 % of a core at the bed's heaviest
traffic; it blocks in select between packets), and the kernel's real-time throttling keeps a
share for everyone else. Where that is refused it runs at normal priority and says so.

Tracing, for benchmarks that must tell the bed's delay from the software's:
{"cmd": "trace", "keep_s": 5} keeps every released packet of the impaired directions for 5 s
(0: off, the default; it costs a little CPU per packet); {"cmd": "find", "needle": HEX,
"direction": "to-robot"} answers with "found": [[offered_s, release_s, written_s, port], ...]
for the kept packets that contain those bytes (e.g. a message's header stamp), oldest first:
when the packet came in, when its delay (with jitter and in-order release) was due to end, when
it was written back (time.monotonic(), the clock all the bed's namespaces share), and its TCP
destination port (None for other protocols), which tells whose connection carried it.
"""
import argparse
import collections
import fcntl
import ipaddress
import json
import os
import select
import signal
import socket
import struct
import sys
import time

from netbed.impairment import Impairment

TUNSETIFF = 0x400454ca
IFF_TUN = 0x0001
IFF_NO_PI = 0x1000
READ_BATCH = 256           # packets read per wake-up at most, so releases are not starved
MAX_PACKET_BYTES = 65536
RT_PRIORITY = 10           # SCHED_FIFO priority asked for (run)
IMPAIRED = {('operator', 'robot'): 'to-robot', ('robot', 'operator'): 'to-operator'}
DIRECTIONS = ('to-robot', 'to-operator')


def open_tun(name):
    """Attach to the TUN device `name` (IPv4 packets without a packet-information header)."""
    fd = os.open('/dev/net/tun', os.O_RDWR | os.O_NONBLOCK)
    fcntl.ioctl(fd, TUNSETIFF, struct.pack('16sH22x', name.encode(), IFF_TUN | IFF_NO_PI))
    return fd


def tcp_port(packet):
    """Return the destination port of an IPv4 TCP packet, or None."""
    header = (packet[0] & 0x0f) * 4
    if packet[9] != socket.IPPROTO_TCP or len(packet) < header + 4:
        return None
    return struct.unpack('!H', packet[header + 2:header + 4])[0]


class Forwarder:
    """Move packets between the bed's hosts through the TUN device, impairing two directions."""

    def __init__(self, tun_fd, hosts, seed, clock=time.monotonic):
        self._fd = tun_fd
        self._clock = clock
        self._hosts = {ipaddress.IPv4Address(addr).packed: name for name, addr in hosts.items()}
        self.links = {d: Impairment('%s:%s' % (seed, d)) for d in DIRECTIONS}
        self._direct = Impairment('%s:direct' % seed)  # no settings: passes at once
        self.counts = {'unroutable': 0, 'write_errors': 0}
        self.running = True
        self.trace_keep_s = 0.0
        self._trace = collections.deque()  # (written_s, direction, offered_s, release_s, packet)

    def link_for(self, packet):
        """Return the Impairment a packet goes through, or None when it must be dropped."""
        if len(packet) < 20 or packet[0] >> 4 != 4:
            return None
        src = self._hosts.get(packet[12:16])
        dst = self._hosts.get(packet[16:20])
        if src is None or dst is None or src == dst:
            return None
        direction = IMPAIRED.get((src, dst))
        return self.links[direction] if direction else self._direct

    def read_packets(self):
        """Read what the TUN device holds (up to READ_BATCH packets) and queue it."""
        for _ in range(READ_BATCH):
            try:
                packet = os.read(self._fd, MAX_PACKET_BYTES)
            except BlockingIOError:
                return
            link = self.link_for(packet)
            if link is None:
                self.counts['unroutable'] += 1
            else:
                # The clock after each read: a packet that came in while this process was
                # descheduled mid-batch must not be timed from before it arrived (early release).
                link.offer(packet, self._clock())

    def release_due(self):
        """Write every packet whose time has come back into the TUN device; return the delay
        until the next one (s), or None when none is in flight."""
        now_s = self._clock()
        nexts = []
        for direction, link in (('direct', self._direct),) + tuple(self.links.items()):
            for packet, offered_s, release_s in link.due_timed(now_s):
                try:
                    os.write(self._fd, packet)
                except OSError:
                    self.counts['write_errors'] += 1
                    continue
                if self.trace_keep_s and direction != 'direct':
                    self._trace.append((self._clock(), direction, offered_s, release_s, packet))
            release_s = link.next_release_s()
            if release_s is not None:
                nexts.append(release_s)
        while self._trace and self._trace[0][0] < now_s - self.trace_keep_s:
            self._trace.popleft()
        return max(min(nexts) - self._clock(), 0.0) if nexts else None

    def find(self, needle, directions):
        """Return [offered_s, release_s, written_s, TCP destination port or None] of the traced
        packets of `directions` that contain the bytes `needle`, oldest first."""
        return [[offered_s, release_s, written_s, tcp_port(packet)]
                for written_s, direction, offered_s, release_s, packet in self._trace
                if direction in directions and needle in packet]

    def handle(self, request):
        """Answer one control request (a dict); return the answer (a dict)."""
        cmd = request.get('cmd')
        direction = request.get('direction', 'both')
        if direction not in DIRECTIONS + ('both',):
            raise ValueError('direction must be one of %s or both, not %r'
                             % (', '.join(DIRECTIONS), direction))
        links = list(self.links.values()) if direction == 'both' else [self.links[direction]]
        if cmd == 'set':
            values = {}
            for key, name, scale in (('delay_ms', 'delay_s', 1e-3), ('jitter_ms', 'jitter_s', 1e-3),
                                     ('loss', 'loss', 1.0)):
                if request.get(key) is not None:
                    values[name] = float(request[key]) * scale
            Impairment(0).configure(**values)  # validate first: all directions or none
            for link in links:
                link.configure(**values)
        elif cmd == 'cut':
            for link in links:
                link.cut()
        elif cmd == 'restore':
            for link in links:
                link.restore()
        elif cmd == 'stop':
            self.running = False
        elif cmd == 'trace':
            keep_s = float(request.get('keep_s', 0.0))
            if not keep_s >= 0.0:
                raise ValueError('keep_s must be >= 0, not %r' % (keep_s,))
            self.trace_keep_s = keep_s
            if not keep_s:
                self._trace.clear()
        elif cmd == 'find':
            needle = bytes.fromhex(request.get('needle', ''))
            if not needle:
                raise ValueError('find needs a needle: the hex of the bytes to look for')
            found = self.find(needle,
                              DIRECTIONS if direction == 'both' else (direction,))
            return {'ok': True, 'found': found}
        elif cmd not in ('ping', 'status'):
            raise ValueError('unknown command %r' % (cmd,))
        times = os.times()
        return {'ok': True, 'pid': os.getpid(), 'cpu_s': times.user + times.system,
                'links': {d: link.status() for d, link in self.links.items()},
                'direct': self._direct.status(), **self.counts}


def serve_control(listener, forwarder):
    """Accept one control connection, answer its request line, close it."""
    conn, _ = listener.accept()
    with conn:
        conn.settimeout(0.5)  # a stuck client stalls forwarding at most this long
        try:
            data = b''
            while not data.endswith(b'\n') and len(data) < 65536:
                chunk = conn.recv(4096)
                if not chunk:
                    break
                data += chunk
            try:
                answer = forwarder.handle(json.loads(data.decode() or '{}'))
            except (ValueError, TypeError, AttributeError) as err:
                answer = {'ok': False, 'error': str(err)}
            conn.sendall(json.dumps(answer).encode() + b'\n')
        except OSError:
            pass  # the client went away; nothing to answer


def run(args):
    """Forward until stopped."""
    hosts = dict(item.split('=', 1) for item in args.host)
    fd = open_tun(args.tun)
    forwarder = Forwarder(fd, hosts, args.seed)
    if os.path.exists(args.control):
        os.unlink(args.control)
    listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    listener.bind(args.control)
    listener.listen(8)

    def stop(_signum, _frame):
        forwarder.running = False
    wake_r, wake_w = os.pipe()  # a signal wakes select at once (set_wakeup_fd writes here)
    os.set_blocking(wake_w, False)
    signal.set_wakeup_fd(wake_w)
    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    try:
        os.sched_setscheduler(0, os.SCHED_FIFO, os.sched_param(RT_PRIORITY))
        scheduling = 'SCHED_FIFO %d' % RT_PRIORITY
    except OSError as err:
        scheduling = 'normal priority (SCHED_FIFO refused: %s)' % err
    print('forwarder %d: tun %s, hosts %s, seed %s, %s' % (
        os.getpid(), args.tun, hosts, args.seed, scheduling), flush=True)
    timeout_s = None
    while forwarder.running:
        try:
            readable, _, _ = select.select([fd, listener, wake_r], [], [], timeout_s)
        except InterruptedError:
            readable = []
        if fd in readable:
            forwarder.read_packets()
        if listener in readable:
            serve_control(listener, forwarder)
        timeout_s = forwarder.release_due()
        if timeout_s is None:
            timeout_s = 1.0
    listener.close()
    os.unlink(args.control)
    os.close(fd)
    print('forwarder %d: stopped' % os.getpid(), flush=True)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--tun', required=True, help='TUN device to attach to')
    parser.add_argument('--control', required=True, help='path of the control socket')
    parser.add_argument('--seed', default='1', help='seed of the random generators')
    parser.add_argument('--host', action='append', default=[], help='NAME=IPv4 address')
    run(parser.parse_args(argv))
    return 0


if __name__ == '__main__':
    sys.exit(main())
