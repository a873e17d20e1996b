"""Unit tests of study.input_events: the record codec and the sources a device is read from."""
import os
import random
import select
import socket

import pytest
from evdev import ecodes as e

from robopuppet.study import input_events as ie
from robopuppet.study.input_events import InputEvent


def batch(t, *events):
    """Return the bytes of a writer's batch: the events, then SYN_REPORT."""
    return b''.join(ie.encode(InputEvent(t, *event)) for event in events) + ie.encode(ie.sync(t))


def test_a_record_is_the_kernels_24_byte_input_event():
    assert ie.RECORD.size == 24
    data = ie.encode(InputEvent(12.25, e.EV_KEY, e.KEY_A, 1))
    assert ie.RECORD.unpack(data) == (12, 250000, e.EV_KEY, e.KEY_A, 1)


def test_encode_decode_round_trip_keeps_time_type_code_and_negative_values():
    events = [InputEvent(1700000000.123456, e.EV_ABS, e.ABS_RY, -32768),
              InputEvent(3.999999, e.EV_REL, e.REL_RZ, -350), ie.sync(4.0)]
    decoded, rest = ie.decode(b''.join(ie.encode(x) for x in events))
    assert rest == b''
    for got, want in zip(decoded, events):
        assert got[1:] == want[1:] and got.t == pytest.approx(want.t, abs=1e-6)


def test_a_partial_record_waits_and_completes_with_the_next_bytes():
    data = batch(5.0, (e.EV_KEY, e.KEY_SPACE, 1))
    events, rest = ie.decode(data[:30])
    assert [x.code for x in events] == [e.KEY_SPACE] and len(rest) == 6
    events, rest = ie.decode(rest + data[30:])
    assert [(x.type, x.code) for x in events] == [(e.EV_SYN, e.SYN_REPORT)] and rest == b''


@pytest.mark.parametrize('length', [0, 1, 23, 25, 47, 49, 100, 239])
def test_garbage_of_any_length_gives_whole_records_and_the_rest(length):
    data = bytes(random.Random(length).randrange(256) for _ in range(length))
    events, rest = ie.decode(data)
    assert len(events) == length // 24 and rest == data[len(events) * 24:]


def test_fed_one_byte_at_a_time_the_same_events_come_out():
    data = batch(1.5, (e.EV_KEY, e.KEY_A, 1), (e.EV_ABS, e.ABS_X, 1234)) * 3
    whole = ie.decode(data)[0]
    events, rest = [], b''
    for byte in data:
        more, rest = ie.decode(rest + bytes([byte]))
        events += more
    assert events == whole and len(events) == 9


def test_a_fifo_source_reads_what_a_writer_writes_and_nothing_before(tmp_path):
    path = str(tmp_path / 'keyboard_R')
    os.mkfifo(path)
    source = ie.open_source(path)
    try:
        assert isinstance(source, ie.RecordSource) and source.read() == []   # no writer yet
        for _ in range(2):   # a writer that closes and a second one
            writer = os.open(path, os.O_WRONLY)
            data = batch(7.0, (e.EV_KEY, e.KEY_F3, 1))
            os.write(writer, data[:10])
            assert source.read() == []    # a partial record waits
            os.write(writer, data[10:])
            os.close(writer)
            assert [(x.code, x.value) for x in source.read()] == [(e.KEY_F3, 1), (0, 0)]
            assert source.read() == []
    finally:
        source.close()


def test_a_recorded_file_is_read_as_raw_records(tmp_path):
    path = tmp_path / 'recorded'
    path.write_bytes(batch(2.0, (e.EV_REL, e.REL_X, 100)))
    source = ie.open_source(str(path))
    assert [x.code for x in source.read()] == [e.REL_X, e.SYN_REPORT]
    assert source.ranges() == {}
    source.close()


def test_a_missing_path_is_an_os_error(tmp_path):
    with pytest.raises(OSError):
        ie.open_source(str(tmp_path / 'nothing'))


def spacenav(*values):
    return ie.SPACENAV.pack(*(list(values) + [0] * (8 - len(values))))


def test_spacenavd_motion_becomes_the_kernels_rel_axes_and_buttons_btn_n():
    # spacenavd: x right, y up, z away; kernel: x right, y toward the user, z down
    events, rest = ie.decode_spacenav(spacenav(0, 10, 20, 30, 1, 2, 3, 16) + spacenav(1, 1)
                                      + spacenav(2, 0) + spacenav(3, 1, 2), 9.5)
    assert rest == b''
    assert [(x.type, x.code, x.value) for x in events] == [
        (e.EV_REL, e.REL_X, 10), (e.EV_REL, e.REL_Y, -30), (e.EV_REL, e.REL_Z, -20),
        (e.EV_REL, e.REL_RX, 1), (e.EV_REL, e.REL_RY, -3), (e.EV_REL, e.REL_RZ, -2),
        (e.EV_SYN, e.SYN_REPORT, 0), (e.EV_KEY, e.BTN_1, 1), (e.EV_SYN, e.SYN_REPORT, 0),
        (e.EV_KEY, e.BTN_0, 0), (e.EV_SYN, e.SYN_REPORT, 0)]   # a device event (3) skipped
    assert all(x.t == 9.5 for x in events)
    events, rest = ie.decode_spacenav(spacenav(1, 0)[:20], 0.0)
    assert events == [] and len(rest) == 20


def test_a_spacenavd_socket_source_reads_its_packets_whole(tmp_path):
    path = str(tmp_path / 'spnav.sock')
    server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
    server.bind(path)
    server.listen(1)
    source = ie.open_source(path)
    client, _ = server.accept()
    try:
        assert isinstance(source, ie.SpacenavSource) and source.read() == []
        data = spacenav(0, 0, 0, -350) + spacenav(1, 0)
        client.sendall(data[:40])
        select.select([source], [], [], 2.0)
        assert [(x.code, x.value) for x in source.read()] == [
            (e.REL_X, 0), (e.REL_Y, 350), (e.REL_Z, 0), (e.REL_RX, 0), (e.REL_RY, 0),
            (e.REL_RZ, 0), (e.SYN_REPORT, 0)]
        client.sendall(data[40:])
        select.select([source], [], [], 2.0)
        assert [(x.code, x.value) for x in source.read()] == [(e.BTN_0, 1), (e.SYN_REPORT, 0)]
        client.close()
        select.select([source], [], [], 2.0)
        with pytest.raises(OSError):
            source.read()
    finally:
        source.close()
        server.close()
