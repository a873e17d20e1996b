"""The bed's link does what it is told: one-way delay per direction, seeded loss, cut and restore.

Sockets are made inside the operator and robot namespaces from this process (netns.socket_in),
so both ends read one clock and one-way delays are measured directly. Needs root (skipped
otherwise). Run: tools/run_tests.py network, or pytest on this file after `. tools/env.sh`.
"""
import socket
import statistics
import struct
import threading
import time

import pytest

SLOT_S = 0.003   # spacing of probe packets
SO_TIMESTAMPNS = getattr(socket, 'SO_TIMESTAMPNS', 35)  # Linux: receive time, ns


def udp_pair(rb, src, dst, port):
    """Return (sender in src's namespace, receiver bound in dst's namespace)."""
    receiver = rb.bed.socket(dst, socket.AF_INET, socket.SOCK_DGRAM)
    receiver.bind((rb.address(dst), port))
    sender = rb.bed.socket(src, socket.AF_INET, socket.SOCK_DGRAM)
    return sender, receiver


def one_way_ms(rb, src, dst, count, port=9100, slot_s=SLOT_S):
    """Send `count` stamped UDP packets src -> dst; return {index: one-way delay ms}, timed by
    the kernel's receive timestamps (both ends read this machine's one clock)."""
    sender, receiver = udp_pair(rb, src, dst, port)
    receiver.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
    got = {}
    with sender, receiver:
        receiver.settimeout(0.05)
        for i in range(count):
            sender.sendto(struct.pack('<Id', i, time.time()), (rb.address(dst), port))
            time.sleep(slot_s)
        deadline = time.monotonic() + 0.6
        while time.monotonic() < deadline and len(got) < count:
            try:
                data, ancillary, _, _ = receiver.recvmsg(64, 64)
            except socket.timeout:
                continue
            index, sent_s = struct.unpack('<Id', data)
            for level, kind, value in ancillary:
                if level == socket.SOL_SOCKET and kind == SO_TIMESTAMPNS:
                    seconds, nanoseconds = struct.unpack('qq', value[:16])
                    got[index] = (seconds + nanoseconds * 1e-9 - sent_s) * 1e3
    return got


def test_each_direction_gets_the_delay_it_is_told(link_bed):
    link_bed.bed.set('to-robot', delay_ms=60, jitter_ms=0)
    link_bed.bed.set('to-operator', delay_ms=15, jitter_ms=0)
    to_robot = one_way_ms(link_bed, 'operator', 'robot', 40)
    to_operator = one_way_ms(link_bed, 'robot', 'operator', 40)
    assert len(to_robot) == len(to_operator) == 40
    # Lower bound exact (never early); upper bound generous: 2 shared cores.
    assert 60 <= min(to_robot.values()) and statistics.median(to_robot.values()) < 60 + 15
    assert 15 <= min(to_operator.values()) and statistics.median(to_operator.values()) < 15 + 15


def test_jitter_spreads_the_delay_but_keeps_the_order(link_bed):
    link_bed.bed.set(delay_ms=30, jitter_ms=10)
    delays = one_way_ms(link_bed, 'operator', 'robot', 100)
    assert len(delays) == 100
    values = [delays[i] for i in sorted(delays)]
    assert min(values) >= 20
    assert max(values) - min(values) > 5  # spread by the jitter
    assert statistics.median(values) < 30 + 10 + 15


def test_round_trip_over_tcp_is_twice_the_delay(link_bed):
    link_bed.bed.set(delay_ms=25, jitter_ms=0)
    server = link_bed.bed.socket('robot')
    server.bind((link_bed.address('robot'), 9200))
    server.listen(1)

    def echo():
        conn, _ = server.accept()
        with conn:
            while True:
                data = conn.recv(64)
                if not data:
                    return
                conn.sendall(data)
    threading.Thread(target=echo, daemon=True).start()
    client = link_bed.bed.socket('operator')
    client.settimeout(5)
    client.connect((link_bed.address('robot'), 9200))
    client.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    rtts = []
    with client, server:
        for _ in range(20):
            start = time.monotonic()
            client.sendall(b'x')
            assert client.recv(64) == b'x'
            rtts.append((time.monotonic() - start) * 1e3)
    assert 50 <= statistics.median(rtts) < 50 + 20


def lost_indices(rb, count, port):
    got = one_way_ms(rb, 'operator', 'robot', count, port, slot_s=0.0005)
    return set(range(count)) - set(got)


def test_loss_is_the_fraction_told_and_reproducible_with_the_seed(link_bed):
    count = 300

    def lost_on_a_new_link(seed):
        # A new forwarder, so the generator starts from its seed for these packets.
        link_bed.bed.up(seed=seed, owner_pid=link_bed.bed.state()['owner_pid'])
        link_bed.bed.set('to-robot', loss=0.2)
        return lost_indices(link_bed, count, 9300)
    lost = lost_on_a_new_link(5)
    links = link_bed.bed.status()['links']
    assert links['to-robot']['lost'] == len(lost)  # the forwarder is the only loss
    assert links['to-operator']['lost'] == 0
    assert 0.13 * count < len(lost) < 0.27 * count
    # The same seed and the same packets lose the same packets; another seed, others.
    assert lost_on_a_new_link(5) == lost
    assert lost_on_a_new_link(6) != lost


def test_cut_stops_everything_and_restore_keeps_a_tcp_connection(link_bed):
    server = link_bed.bed.socket('robot')
    server.bind((link_bed.address('robot'), 9400))
    server.listen(1)
    client = link_bed.bed.socket('operator')
    client.settimeout(5)
    client.connect((link_bed.address('robot'), 9400))
    conn, _ = server.accept()
    conn.settimeout(1.0)
    with client, conn, server:
        client.sendall(b'before')
        assert conn.recv(64) == b'before'
        link_bed.bed.cut()
        assert one_way_ms(link_bed, 'operator', 'robot', 10, 9401) == {}
        assert one_way_ms(link_bed, 'robot', 'operator', 10, 9402) == {}
        client.sendall(b'during')
        with pytest.raises(socket.timeout):
            conn.recv(64)
        link_bed.bed.restore()
        conn.settimeout(8.0)  # the next TCP retransmission (backing off) carries it
        assert conn.recv(64) == b'during'
        conn.sendall(b'after')
        assert client.recv(64) == b'after'
    assert link_bed.bed.status()['links']['to-robot']['cut'] > 0


def test_a_cut_of_one_direction_leaves_the_other(link_bed):
    link_bed.bed.cut('to-robot')
    assert one_way_ms(link_bed, 'operator', 'robot', 10, 9500) == {}
    assert len(one_way_ms(link_bed, 'robot', 'operator', 10, 9501)) == 10
    link_bed.bed.restore('to-robot')
    assert len(one_way_ms(link_bed, 'operator', 'robot', 10, 9502)) == 10
