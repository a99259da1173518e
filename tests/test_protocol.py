"""The frame protocol (rcl/hw/protocol.py, docs/protocol.md): CRC, the
message table, and a reader that resynchronises and never hands over a
corrupted frame."""
import random

from hypothesis import given, settings, strategies as st

from rcl.hw import protocol as P

SAMPLES = {
    "HELLO": dict(version=1), "OUT8": dict(port=0x88, value=0x0F),
    "OUT16": dict(port=0xFF56, value=0xE001), "IN8": dict(port=0x8A), "IN16": dict(port=0xFF32),
    "FAR_STORE": dict(seg=0, off=0x70, value=0x34), "FAR_FETCH": dict(seg=0x40, off=0x6C),
    "SNAPSHOT": dict(ops=[(0, 0x83, 0x40), (1, 0x81, 0)]),
    "TICK_DONE": dict(tick=513, final=1, us=2750, writes=[(0x80, 0xAD), (0x80, 0)]),
    "SAFE": {}, "TICK_FAILED": {}, "PING": {}, "NAK": dict(seq=9),
    "WAIT": dict(tick=0x0102), "CLOCK": dict(us=40_416),
    "RUN": dict(ops=[(0, 0x87, 0x40), (1, 0x85, 0)]),
    "IDENTIFY": dict(version=1, tick_us=10_000, flags=0, name="R-E Robot"),
    "ACK": dict(ack=7), "VALUE": dict(ack=7, value=0x1234),
    "TICK": dict(tick=65535, off=0x2A10, results=[(1,), (2,)]),
    "HEARTBEAT": dict(time_us=123_456_789, ticking=1),
    "RESULTS": dict(ack=3, results=[(0xFE,)]), "REFUSED": dict(ack=3, reason="unknown"),
}


def test_the_crc_is_ccitt_false_with_its_check_value():
    assert P.crc16(b"123456789") == 0x29B1


def test_the_worked_example_of_the_protocol_document_is_what_the_code_sends():
    assert P.frame(1, "OUT8", port=0x88, value=0x0F).hex(" ") == "a5 03 01 02 88 00 0f e4 dd"


def test_every_message_in_the_table_round_trips_through_a_frame():
    assert set(SAMPLES) == set(P.BY_NAME)
    reader = P.FrameReader()
    for seq, (name, values) in enumerate(SAMPLES.items()):
        (f,) = reader.feed(P.frame(seq, name, **values))
        assert (f.seq, f.name, f.values) == (seq, name, values)


def test_message_ids_are_unique_and_say_who_sends_them():
    assert len(P.BY_ID) == len(P.TABLE)
    for m in P.TABLE:
        assert (m.id >= 0x80) == (m.sender == P.BOARD)


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(0.0, 0.05))
def test_the_reader_returns_only_frames_that_were_sent_whatever_the_noise(seed, rate):
    rng = random.Random(seed)
    sent = [P.frame(i & 0xFF, "VALUE", ack=i & 0xFF, value=rng.randrange(65536))
            for i in range(60)]
    stream = bytearray(b"".join(sent))
    for i in range(len(stream)):
        if rng.random() < rate:
            stream[i] ^= 1 << rng.randrange(8)
    reader, got = P.FrameReader(), []
    for i in range(0, len(stream), 7):            # arbitrary splits
        got += reader.feed(bytes(stream[i:i + 7]))
    originals = {P.frame(f.seq, "VALUE", **f.values) for f in got}
    assert originals <= set(sent)
    if rate == 0:
        assert len(got) == len(sent)


def test_terminal_noise_before_a_frame_is_skipped():
    reader = P.FrameReader()
    noise = b"ATZ\r\n+++\x1b[2J\xa5\xa5\xff\x00 hello \xa5"
    (f,) = reader.feed(noise + P.frame(4, "ACK", ack=4))
    assert f.name == "ACK" and reader.skipped > 0


def test_every_hex_example_in_the_protocol_document_is_a_good_frame():
    import pathlib
    import re
    doc = pathlib.Path(__file__).parent.parent / "docs" / "protocol.md"
    lines = re.findall(r"^    (a5(?: [0-9a-f]{2})+)$", doc.read_text(), re.M)
    reader, names = P.FrameReader(), set()
    for line in lines:
        (f,) = reader.feed(bytes.fromhex(line))
        assert f.seq == (1 if f.message.sequenced else 0), line
        names.add(f.name)
    assert names == set(P.BY_NAME) and reader.bad == 0


def test_host_sequence_numbers_run_1_to_255_and_never_0():
    assert P.following(254) == 255 and P.following(255) == 1
    assert P.previous(1) == 255 and P.previous(2) == 1


def test_each_end_knows_only_the_other_ends_types_and_clock_only_in_lockstep():
    board = P.FrameReader(P.received_by(P.BOARD))
    echo = P.frame(1, "ACK", ack=1) + P.frame(1, "CLOCK", us=5)
    assert board.feed(echo + P.frame(1, "OUT8", port=0x88, value=0))[0].name == "OUT8"
    lockstep = P.FrameReader(P.received_by(P.BOARD, lockstep=True))
    assert [f.name for f in lockstep.feed(echo)] == ["CLOCK"]
    host = P.FrameReader(P.received_by(P.HOST))
    assert [f.name for f in host.feed(echo)] == ["ACK"]


def test_a_good_frame_whose_payload_does_not_fit_is_kept_for_a_refusal_when_asked():
    body = bytes((2, 1, 0x02, 0x88, 0x00))              # OUT8 with no value byte
    crc = P.crc16(body)
    data = bytes((P.SYNC,)) + body + bytes((crc >> 8, crc & 0xFF))
    assert P.FrameReader().feed(data) == []
    (f,) = P.FrameReader(keep_bad=True).feed(data)
    assert f.name == "OUT8" and f.seq == 1 and f.values is None and "too short" in f.error


def bad_len(frame, length):
    """The frame with its LEN byte corrupted to `length` (the CRC not mended)."""
    return frame[:1] + bytes((length,)) + frame[2:]


def test_a_frame_still_incomplete_50_ms_after_its_sync_is_dropped_and_the_frames_it_hid_are_found():
    ping = P.frame(0, "PING")
    reader = P.FrameReader()
    # a PING whose LEN turned 0 -> 32 (bit 5) claims 38 bytes: 5 more PINGs
    assert reader.feed(bad_len(ping, 32), now=0.000) == []
    assert reader.feed(ping, now=0.049) == []                # 49 ms: still waited for
    got = reader.feed(ping, now=0.100)                      # 100 ms: dropped; both PINGs found
    assert [f.name for f in got] == ["PING", "PING"] and reader.bad == 1
    assert reader.feed(ping, now=0.150)[0].name == "PING"   # in step again


def test_a_reader_without_a_clock_the_hosts_waits_for_a_frame_however_long():
    ping = P.frame(0, "PING")
    reader = P.FrameReader()          # the host's: a board may stall mid-frame (section 1)
    got = reader.feed(bad_len(ping, 32))
    for _ in range(5):
        got += reader.feed(ping)
    assert got == []
    assert len(reader.feed(ping)) == 6                   # the 38th byte: all six at once


def test_a_frame_split_between_two_reads_by_a_long_stall_is_still_taken_whole():
    ack = P.frame(7, "ACK", ack=7)
    reader = P.FrameReader()
    assert reader.feed(ack[:3], now=0.0) == []
    # our stall: the rest was waiting, and is read before the gap is judged
    (f,) = reader.feed(ack[3:], now=0.400)
    assert f.name == "ACK" and reader.bad == 0
