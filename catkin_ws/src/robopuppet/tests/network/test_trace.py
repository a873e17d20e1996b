"""The forwarder's trace (tools/netbed/forwarder.py: trace, find): for a packet found by its bytes
it tells when it came in, when its delay ended and when it went out, as bench_remote.py needs to
subtract the delay the bed really gave a message from its latency. Needs root (skipped
otherwise). Run: tools/run_tests.py network -k trace.
"""
import socket
import time

import pytest

from netbed.bed import BedError

PORT = 9600
COUNT = 40
SLOT_S = 0.003
WRITE_SLACK_S = 0.005  # received_s may precede written_s by the TUN write's own duration
SO_TIMESTAMPNS = getattr(socket, 'SO_TIMESTAMPNS', 35)  # Linux: receive time, ns


def send_marked(rb, count, prefix):
    """Send `count` UDP packets operator -> robot, each holding prefix + its index; return
    {index: (sent, received)} in time.monotonic() (received from the kernel's timestamp)."""
    receiver = rb.bed.socket('robot', socket.AF_INET, socket.SOCK_DGRAM)
    receiver.bind((rb.address('robot'), PORT))
    receiver.setsockopt(socket.SOL_SOCKET, SO_TIMESTAMPNS, 1)
    sender = rb.bed.socket('operator', socket.AF_INET, socket.SOCK_DGRAM)
    sent, got = {}, {}
    with sender, receiver:
        receiver.settimeout(0.05)
        for i in range(count):
            sent[i] = time.monotonic()
            sender.sendto(b'%s%04d' % (prefix, i), (rb.address('robot'), PORT))
            time.sleep(SLOT_S)
        deadline = time.monotonic() + 0.6
        while time.monotonic() < deadline and len(got) < count:
            try:
                data, ancillary, _, _ = receiver.recvmsg(64, 64)
            except socket.timeout:
                continue
            mono_minus_wall = time.monotonic() - time.time()
            for level, kind, value in ancillary:
                if level == socket.SOL_SOCKET and kind == SO_TIMESTAMPNS:
                    seconds, nanoseconds = (int.from_bytes(value[k:k + 8], 'little')
                                            for k in (0, 8))
                    got[int(data[len(prefix):])] = seconds + nanoseconds * 1e-9 + mono_minus_wall
    return {i: (sent[i], got[i]) for i in got}


def find(rb, needle, direction='to-robot'):
    return rb.bed.request({'cmd': 'find', 'needle': needle.hex(),
                           'direction': direction})['found']


def test_find_tells_each_packets_arrival_delay_and_release(link_bed):
    link_bed.bed.set('to-robot', delay_ms=30, jitter_ms=10)
    link_bed.bed.request({'cmd': 'trace', 'keep_s': 5})
    times = send_marked(link_bed, COUNT, b'trace-probe-')
    assert len(times) == COUNT
    holds = []
    for i, (sent_s, received_s) in times.items():
        needle = b'trace-probe-%04d' % i
        found = find(link_bed, needle)
        assert len(found) == 1, (needle, found)
        offered_s, release_s, written_s, port = found[0]
        assert port is None  # UDP
        hold_s = release_s - offered_s
        # in order after when it was sent; its delay within delay +- jitter (in-order release
        # only raises it within that range); received after the forwarder wrote it. The
        # forwarder stamps written_s once its write to the TUN device has returned, and the
        # kernel may deliver (and timestamp) the packet within that write: WRITE_SLACK_S.
        assert sent_s <= offered_s <= release_s <= written_s <= received_s + WRITE_SLACK_S
        assert 0.020 - 1e-6 <= hold_s <= 0.040 + 1e-6
        holds.append(hold_s)
        assert find(link_bed, needle, 'to-operator') == []
    assert max(holds) - min(holds) > 0.005  # each packet's own delay, not the nominal one


def test_find_names_the_tcp_port_that_carried_the_bytes(link_bed):
    link_bed.bed.request({'cmd': 'trace', 'keep_s': 5})
    server = link_bed.bed.socket('robot')
    server.bind((link_bed.address('robot'), PORT + 10))
    server.listen(1)
    client = link_bed.bed.socket('operator')
    client.settimeout(5)
    with server, client:
        client.connect((link_bed.address('robot'), PORT + 10))
        conn, _ = server.accept()
        with conn:
            client.sendall(b'tcp-marker')
            conn.settimeout(5)
            assert conn.recv(64) == b'tcp-marker'
    assert [entry[3] for entry in find(link_bed, b'tcp-marker')] == [PORT + 10]


def test_a_trace_switched_off_keeps_nothing_and_bad_requests_are_refused(link_bed):
    link_bed.bed.request({'cmd': 'trace', 'keep_s': 0})
    send_marked(link_bed, 3, b'untraced-')
    assert find(link_bed, b'untraced-0000') == []
    with pytest.raises(BedError, match='needle'):
        link_bed.bed.request({'cmd': 'find', 'needle': ''})
    with pytest.raises(BedError, match='keep_s'):
        link_bed.bed.request({'cmd': 'trace', 'keep_s': -1})
