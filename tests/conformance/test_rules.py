"""docs/protocol.md as rules, each checked on every board the project
ships (conftest.py) with raw frames over the byte stream (wire.py): the
same results on all. A rule for lockstep boards only, or for the others
only, says so and is "n/a" on the rest.

Section numbers are the document's. Board time, where a rule needs it to
pass, is the board's own (a lockstep board keeps the host's, which it is
given by CLOCK); the wall clock only bounds a wait for a broken board.
"""
import time

import pytest

import wire
from starved import Starved
from wire import (ACK, CLOCK, FAR_FETCH, HEARTBEAT, HELLO, IDENTIFY, IN8, NAK, OUT8,
                  PING, REFUSED, RESULTS, SAFE, SNAPSHOT, TICK, TICK_DONE,
                  TICK_FAILED, VALUE, WAIT, frame, ops, u16, u32)

LEFT, RIGHT = 0x80, 0x84                # the two 8253s (docs/firmware.md's port map)
MOTOR, AUX, STATUS = 0x88, 0x89, 0x8A
T0CON, T0MAX, TIMER_MASK = 0xFF56, 0xFF52, 0xFF32
FORTH_CS = 0x1000


def lockstep_only(s):
    if not s.lockstep:
        pytest.skip("a rule for lockstep boards only (section 5)")


def not_lockstep(s):
    if s.lockstep:
        pytest.skip("a rule for boards that are not lockstep (section 5)")


def load_counter(s, chip, counter, count):
    """8253 counter 1 or 2 in mode 2, LSB then MSB (control word 0x74 or 0xB4,
    as RCL's INIT-COUNTERS sets them)."""
    s.out8(chip + 3, (counter << 6) | 0x34)
    s.out8(chip + counter, count & 0xFF)
    s.out8(chip + counter, count >> 8)


def read_counter(s, chip, counter):
    """Latch and read a counter at once (RUN); -> its count."""
    lo, hi = s.run([(0, chip + 3, counter << 6), (1, chip + counter, 0),
                    (1, chip + counter, 0)]).results
    return lo | hi << 8


def start_ticks(s, script=(), off=0x2A10):
    """Timer 0 at RCL's 6667 counts (10 ms) and INT 1Ch -> 1000:off."""
    if script:
        assert s.request(SNAPSHOT, ops(script)).type == ACK
    assert s.out16(T0MAX, 6667).type == ACK
    s.store32(0, 0x70, FORTH_CS << 16 | off)


def next_tick(s, wanted=0xFFFF, seconds=wire.BOUND):
    """The next TICK; a lockstep host sends WAIT while it waits (section 4)."""
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if s.lockstep:
            s.send(frame(0, WAIT, u16(wanted)))
        f = s.receive({TICK}, 0.01)
        if f is None:
            continue
        if wanted != 0xFFFF and (f.tick()[0] - wanted) & 0xFFFF >= 0x8000:
            continue                    # one taken already, sent again for a WAIT
        return f
    return None


def answer_tick(s, f, writes=()):
    """The tick's final TICK_DONE, with its writes; -> the tick number."""
    tick = f.tick()[0]
    payload = u16(tick) + b"\x01" + u16(0) + b"".join(u16(p) + bytes((v,)) for p, v in writes)
    assert s.request(TICK_DONE, payload).type == ACK
    return tick


def run_ticks(s, n):
    """n ticks, each answered; -> the TICK frames."""
    got, wanted = [], 0xFFFF
    for _ in range(n):
        f = next_tick(s, wanted)
        assert f is not None, "no TICK came"
        got.append(f)
        wanted = (answer_tick(s, f) + 1) & 0xFFFF
    return got


# The left wheel, turned by its PLL at counter 0's reference (mode 3, 500
# counts of 125 kHz: 250 Hz) and counted down by counter 1.
def start_left_wheel(s):
    s.out8(LEFT + 3, 0x36)
    s.out8(LEFT, 500 & 0xFF)
    s.out8(LEFT, 500 >> 8)
    load_counter(s, LEFT, 1, 0)
    s.out8(MOTOR, 0x11)                 # M1-ON | M1-GO


def turned(s, ms):
    """Counts the left wheel turned in `ms` of board time."""
    before = read_counter(s, LEFT, 1)
    s.advance(ms)
    return (before - read_counter(s, LEFT, 1)) & 0xFFFF


def stopped(s):
    """The wheel came to rest: braked, it runs out a few counts (300 ms:
    six braking constants), then turns less than 2 in 300 ms."""
    s.advance(300)
    return turned(s, 300) < 2


# ------------------------------------------------- 1. frames, the receiver
def test_the_suites_crc_has_the_documents_check_value():
    assert wire.crc16(b"123456789") == 0x29B1
    assert frame(1, OUT8, u16(0x88) + b"\x0f").hex(" ") == "a5 03 01 02 88 00 0f e4 dd"


def test_hello_is_answered_by_identify_with_seq_0_version_1_and_the_10_ms_tick(s):
    assert s.ident.seq == 0 and s.ident.type == IDENTIFY
    fields = s.ident.identify()
    assert fields["version"] == 1 and fields["tick_us"] == 10_000


def test_identify_sets_no_flag_but_bit_0_and_names_the_board_in_text(s):
    fields = s.ident.identify()
    assert fields["flags"] & ~wire.LOCKSTEP == 0
    assert fields["name"].strip() and len(s.ident.payload) <= 64


def test_the_documents_worked_example_is_acknowledged_with_board_seq_1(s):
    s.send(bytes.fromhex("a5 03 01 02 88 00 0f e4 dd"))
    ack = s.receive({ACK})
    assert ack.ack == 1 and ack.payload == b"\x01"
    # board SEQ 1, or the next after HEARTBEATs sent since HELLO
    assert [f.seq for f in s.frames[1:]] == list(range(1, ack.seq + 1))


def test_board_frames_after_hello_are_numbered_1_2_3_without_a_gap(s):
    for _ in range(5):
        s.in8(STATUS)
    seqs = [f.seq for f in s.frames if f.type != IDENTIFY]
    assert seqs == list(range(1, len(seqs) + 1)) and len(seqs) >= 5


def test_a_frame_with_a_bad_crc_is_not_acted_on_and_uses_up_no_seq(s):
    bad = bytearray(frame(1, IN8, u16(STATUS)))
    bad[-1] ^= 0x01
    s.send(bad)
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


def test_terminal_noise_before_a_frame_is_skipped(s):
    s.send(b"ATZ\r\n+++ATH0\r\n\x1b[2J\xa5\xff\xa5\x40" + bytes(range(256)) + b"\x00" * 70)
    assert s.request(IN8, u16(STATUS)).type == VALUE


def test_a_len_over_64_loses_only_its_sync_and_a_frame_just_after_is_found(s):
    s.send(b"\xa5\x41" + frame(1, IN8, u16(STATUS)))
    assert s.receive({VALUE}).ack == 1


def test_a_good_frame_that_begins_inside_a_bad_one_is_found(s):
    real = frame(1, IN8, u16(STATUS))        # 8 bytes, inside a 15-byte "frame"
    s.send(b"\xa5\x09" + real + frame(0, PING))
    assert s.receive({VALUE}).ack == 1


def test_a_frame_split_into_single_bytes_is_read_whole(s):
    began = time.monotonic()
    for byte in frame(1, IN8, u16(STATUS)):
        s.send(bytes((byte,)))
        time.sleep(0.002)
    took = time.monotonic() - began
    if took >= 0.045:                         # section 1 step 3: then it is rightly no frame
        raise Starved("the 8 bytes took this process %d ms to send (a busy machine)"
                      % (took * 1000))
    assert s.receive({VALUE}).ack == 1


def test_a_frame_still_incomplete_50_ms_after_its_sync_is_no_frame_and_the_next_is_found(s):
    s.send(b"\xa5\x20\x00\x0c")                 # a PING whose LEN turned 0 -> 32
    time.sleep(0.1)                           # the line quiet: it will never be whole
    s.send(frame(1, IN8, u16(STATUS)))        # waited for, it would be swallowed,
    answer = s.receive({VALUE}, keep_alive=False)   # and no more bytes would come
    assert answer is not None and answer.ack == 1


def test_an_unknown_type_is_dropped_unanswered_and_uses_up_no_seq(s):
    for t in (0x00, 0x11, 0x20, 0x7F, 0x88, 0xFF):
        s.send(frame(1, t, u16(STATUS)))
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


def test_a_board_frame_echoed_to_the_board_is_no_frame_and_uses_up_no_seq(s):
    echo = frame(1, ACK, b"\x01") + frame(1, VALUE, b"\x01\x34\x12") + s.ident.raw
    s.send(echo)
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


def test_a_payload_that_does_not_fit_is_refused_bad_payload_in_sequence(s):
    for payload in (u16(MOTOR), u16(MOTOR) + b"\x00\x00"):        # OUT8 short, long
        refused = s.request(OUT8, payload)
        assert refused.type == REFUSED and refused.reason == "bad payload"


def test_a_refused_misfit_uses_up_its_seq_and_a_repeat_gets_the_refusal_again(s):
    first = s.request(IN8, u16(STATUS) + b"\x00", seq=1)
    assert first.type == REFUSED
    again = s.request(IN8, u16(STATUS), seq=1)           # now a repeat of SEQ 1
    assert again.raw == first.raw
    assert s.request(IN8, u16(STATUS), seq=2).type == VALUE


def test_a_misfit_out_of_sequence_is_ignored(s):
    s.send(frame(7, IN8, b"\x8a"))
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


def test_every_refused_reason_is_text_of_at_most_19_bytes(s):
    for payload in (b"", b"\x01" * 7):
        refused = s.request(FAR_FETCH, payload)
        assert refused.type == REFUSED and 0 < len(refused.payload) - 1 <= 19


# ----------------------------------------------------------- 3. sequencing
def test_a_repeat_is_answered_byte_for_byte_and_not_acted_on_twice(s):
    load_counter(s, LEFT, 1, 0x1234)
    s.out8(LEFT + 3, 0x40)                               # latch counter 1
    seq = s.seq
    first = s.request(IN8, u16(LEFT + 1))
    assert first.value == 0x34                           # the LSB
    again = s.request(IN8, u16(LEFT + 1), seq=seq)
    assert again.raw == first.raw
    assert s.in8(LEFT + 1) == 0x12                       # acted on once: now the MSB


def test_a_frame_with_another_seq_is_ignored(s):
    s.send(frame(5, IN8, u16(STATUS)))
    s.send(frame(200, IN8, u16(STATUS)))
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


def test_a_sequenced_message_with_seq_0_is_not_acted_on(s):
    s.send(frame(0, IN8, u16(STATUS)))
    assert s.answers(0.1) == []


def test_right_after_hello_seq_255_is_no_repeat_and_gets_nothing(s):
    s.in8(STATUS)
    s.hello()
    s.send(frame(255, IN8, u16(STATUS)))
    assert s.answers(0.1) == []


def test_host_seq_wraps_from_255_to_1_and_board_seq_from_255_to_0(s):
    for _ in range(258):
        assert s.request(IN8, u16(STATUS)).type == VALUE
    hosts = [f.ack for f in s.frames if f.type == VALUE]
    assert hosts[253:257] == [254, 255, 1, 2]
    boards = [f.seq for f in s.frames if f.type != IDENTIFY]
    assert boards[254:258] == [255, 0, 1, 2]


def test_hello_restarts_both_sequences(s):
    for _ in range(3):
        s.in8(STATUS)
    s.hello()
    answer = s.request(IN8, u16(STATUS))
    assert answer.ack == 1
    assert [f.seq for f in s.frames[1:]] == list(range(1, answer.seq + 1))


def test_nak_brings_back_a_kept_board_frame_byte_for_byte(s):
    answers = [s.request(IN8, u16(STATUS)) for _ in range(5)]
    s.send(frame(0, NAK, bytes((answers[1].seq,))))
    again = s.receive({VALUE})
    assert again.raw == answers[1].raw


def test_the_last_16_board_frames_are_kept_for_nak(s):
    for _ in range(16):
        assert s.request(IN8, u16(STATUS)).type == VALUE
    oldest = [f for f in s.frames if f.type != IDENTIFY][-16]
    s.send(frame(0, NAK, bytes((oldest.seq,))))
    assert s.receive_raw(oldest.raw) is not None


def test_nak_is_unsequenced_and_uses_up_no_seq(s):
    s.in8(STATUS)
    s.send(frame(0, NAK, b"\x01"))
    s.quiet(0.05)
    assert s.request(IN8, u16(STATUS), seq=2).ack == 2


def test_a_nak_that_does_not_fit_is_ignored(s):
    s.in8(STATUS)
    s.send(frame(0, NAK, b"\x01\x00"))
    assert s.answers(0.1) == []


def test_ping_gets_no_answer_and_uses_up_no_seq(s):
    s.send(frame(0, PING))
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


def test_wait_gets_no_answer_and_uses_up_no_seq(s):
    s.send(frame(0, WAIT, u16(0xFFFF)))
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


# ----------------------------------------------------------- 4. messages
def test_an_empty_hello_starts_no_session_and_gets_no_answer(s):
    s.in8(STATUS)
    s.send(frame(0, HELLO))
    s.send(frame(0, HELLO, b"\x01\x00"))
    assert s.receive({IDENTIFY}, 0.2) is None
    assert s.request(IN8, u16(STATUS), seq=2).ack == 2     # the session goes on


def test_hello_of_another_version_is_answered_with_the_boards_own(s):
    assert s.hello(version=2)["version"] == 1


def test_out8_is_acknowledged_with_the_seq_it_answers(s):
    seq = s.seq
    ack = s.out8(AUX, 0)
    assert ack.type == ACK and ack.payload == bytes((seq,))


def test_in8_answers_value_with_the_byte_in_the_low_half(s):
    load_counter(s, LEFT, 2, 0xBEEF)
    s.out8(LEFT + 3, 0x80)
    v = s.request(IN8, u16(LEFT + 2))
    assert v.type == VALUE and v.value == 0xEF


def test_a_port_with_nothing_behind_it_reads_ff(s):
    assert s.in8(0x0000) == 0xFF and s.in8(0x1234) == 0xFF and s.in8(MOTOR) == 0xFF


def test_out16_below_ff00_writes_the_low_byte_to_port_and_the_high_to_port_plus_1(s):
    s.out8(LEFT + 3, 0x74)                   # counter 1, LSB then MSB, mode 2
    s.out8(LEFT + 3, 0xB4)                   # counter 2 likewise
    s.out16(LEFT + 1, 0x1234)                # 0x34 -> counter 1, 0x12 -> counter 2
    s.out8(LEFT + 1, 0x00)
    s.out8(LEFT + 2, 0x00)
    assert read_counter(s, LEFT, 1) == 0x0034
    assert read_counter(s, LEFT, 2) == 0x0012


def test_in16_below_ff00_reads_the_low_byte_from_port_and_the_high_from_port_plus_1(s):
    load_counter(s, LEFT, 1, 0x5678)
    load_counter(s, LEFT, 2, 0x9ABC)
    s.out8(LEFT + 3, 0x40)
    s.out8(LEFT + 3, 0x80)
    assert s.in16(LEFT + 1) == 0xBC78        # counter 1's LSB, counter 2's LSB


def test_out16_and_in16_at_ff00_and_above_move_one_word(s):
    assert s.out16(T0MAX, 6667).type == ACK
    assert s.in16(T0MAX) == 6667


def test_a_pcb_access_at_an_odd_address_is_the_word_at_the_even_one(s):
    s.out16(T0MAX, 0x1A0B)
    assert s.in16(T0MAX + 1) == 0x1A0B


def test_far_store_and_far_fetch_reach_the_vector_table(s):
    s.store32(0, 0x70, 0x1000_2A10)
    assert s.fetch32(0, 0x70) == 0x1000_2A10


def test_the_bios_day_is_1573040_ticks_at_power_on(s):
    assert s.fetch32(0x40, 0xF0) == 1_573_040


def test_the_bios_tick_count_wraps_at_ticks_per_day_and_sets_the_midnight_flag(s):
    s.store32(0x40, 0xF0, 3)                 # a day of 3 ticks
    s.store32(0x40, 0x6C, 0)
    flag = 0
    for _ in range(40):                      # 54.9 ms ticks: 3 come in 200 ms
        s.advance(50)
        flag = s.fetch(0x40, 0x70)
        if flag:
            break
    assert flag == 1 and s.fetch32(0x40, 0x6C) < 3


def test_snapshot_of_16_records_is_acknowledged(s):
    script = [(1, STATUS, 0)] * 16
    assert s.request(SNAPSHOT, ops(script)).type == ACK


def test_run_carries_out_its_records_at_once_and_results_hold_the_reads(s):
    load_counter(s, RIGHT, 1, 0x0102)
    answer = s.run([(0, RIGHT + 3, 0x40), (1, RIGHT + 1, 0), (1, RIGHT + 1, 0)])
    assert answer.type == RESULTS and answer.results == [0x02, 0x01]


def test_run_with_no_records_gives_empty_results(s):
    answer = s.run([])
    assert answer.type == RESULTS and answer.results == []


def test_no_tick_comes_while_int_1ch_points_outside_the_forth_segment(s):
    s.out16(T0MAX, 6667)
    s.advance(100)
    assert not [f for f in s.frames if f.type == TICK]


def test_ticks_come_numbered_in_order_with_the_scripts_reads(s):
    load_counter(s, LEFT, 1, 0x1234)
    start_ticks(s, [(0, LEFT + 3, 0x40), (1, LEFT + 1, 0), (1, LEFT + 1, 0)])
    ticks = [f.tick() for f in run_ticks(s, 5)]
    numbers = [t for t, _, _ in ticks]
    assert numbers == [(numbers[0] + i) & 0xFFFF for i in range(5)]
    assert all(off == 0x2A10 and results == [0x34, 0x12] for _, off, results in ticks)


def test_tick_done_writes_are_carried_out_in_order(s):
    start_ticks(s)
    f = next_tick(s)
    answer_tick(s, f, [(LEFT + 3, 0x74), (LEFT + 1, 0x21), (LEFT + 1, 0x43)])
    assert read_counter(s, LEFT, 1) == 0x4321


def test_tick_failed_clears_int_keeps_en_and_the_other_bits_and_stops_the_ticks(s):
    start_ticks(s)
    assert next_tick(s) is not None
    before = s.in16(T0CON)
    assert s.request(TICK_FAILED).type == ACK
    after = s.in16(T0CON)
    assert after & 0x2000 == 0 and after & 0x8000            # INT off, EN on
    assert after & ~0x2020 == before & ~0x2020               # the rest kept (MC apart)
    assert after & 0x4000 == 0                               # INH reads 0
    s.drain()
    s.advance(100)
    assert not [f for f in s.unread + s.quiet(0.05) if f.type == TICK]


def test_heartbeats_come_when_nothing_else_is_sent_and_board_time_never_runs_back(s):
    beats = [s.receive({HEARTBEAT}) for _ in range(4)]
    assert None not in beats
    times = [b.heartbeat()[0] for b in beats]
    assert all(0 <= (b - a) & 0xFFFFFFFF < 1 << 31 for a, b in zip(times, times[1:]))
    assert all(b.heartbeat()[1] == 0 for b in beats)          # no TICK will come


def test_board_time_moves_between_heartbeats_within_the_hosts_250_ms(s):
    not_lockstep(s)                           # (a lockstep board's time stands still)
    beats = [s.receive({HEARTBEAT}) for _ in range(4)]
    times = [b.heartbeat()[0] for b in beats]
    # 50 ms each on an idle line; a loaded machine delays a board process,
    # never past the 250 ms after which its host would say Link lost
    assert all(0 < b - a < 250_000 for a, b in zip(times, times[1:]))


def test_clock_is_acknowledged_by_a_lockstep_board(s):
    lockstep_only(s)
    assert s.request(CLOCK, u32(40_000)).type == ACK


def test_clock_is_an_unknown_type_to_any_other_board(s):
    not_lockstep(s)
    s.send(frame(1, CLOCK, u32(40_000)))
    assert s.answers(0.1) == []
    assert s.request(IN8, u16(STATUS), seq=1).type == VALUE


def test_a_lockstep_board_holds_its_time_until_clock_moves_it(s):
    lockstep_only(s)
    first = s.receive({HEARTBEAT}).heartbeat()[0]
    second = s.receive({HEARTBEAT}).heartbeat()[0]
    assert second == first
    s.advance(100)
    third = s.receive({HEARTBEAT}).heartbeat()[0]
    assert 99_000 <= (third - first) & 0xFFFFFFFF <= 101_000


# ------------------------------------------------- 6. safe state, watchdog
def test_the_wheel_turns_while_the_host_keeps_the_link_fed(s):
    start_left_wheel(s)
    assert turned(s, 200) > 20


def test_the_watchdog_stops_the_wheels_after_250_ms_of_silence(s):
    start_left_wheel(s)
    assert turned(s, 150) > 10
    s.advance(500, keep_alive=False)          # 250 ms of silence and more
    assert stopped(s)


def test_pings_alone_feed_the_watchdog(s):
    start_left_wheel(s)
    s.longest_silence = 0.0
    if s.lockstep:                            # (its watchdog counts the wall clock)
        s.quiet(0.6)                          # PINGs every 100 ms, nothing else
    else:
        s.board_time(600)
    n = turned(s, 200)
    if n <= 20 and s.longest_silence > 0.25:  # our PINGs, not the board, stopped for 250 ms
        raise Starved("this process sent nothing for %d ms (a busy machine)"
                      % (s.longest_silence * 1000))
    assert n > 20


def test_echoed_board_frames_do_not_feed_the_watchdog(s):
    start_left_wheel(s)
    echo = s.frames[-1].raw                   # the board's last frame, every 40 ms
    s.advance(600, keep_alive=False, chatter=echo)
    assert stopped(s)


def test_safe_with_seq_0_stops_the_wheels_unanswered_and_uses_up_no_seq(s):
    start_left_wheel(s)
    s.send(frame(0, SAFE))
    assert stopped(s)                         # (its requests went on in sequence)
    assert [f for f in s.frames if f.type in wire.ANSWERS and f.ack == 0] == []


def test_safe_with_a_payload_still_stops_the_wheels_and_is_refused(s):
    start_left_wheel(s)
    refused = s.request(SAFE, b"\x01")
    assert refused.type == REFUSED and refused.reason == "bad payload"
    assert stopped(s)


def test_after_the_watchdog_only_a_motor_latch_write_turns_the_wheel_again(s):
    start_left_wheel(s)
    s.advance(500, keep_alive=False)
    s.hello()                           # a new session: the board as at power-on (section 6)
    assert stopped(s)
    start_left_wheel(s)                 # the reference set again, then the latch
    assert turned(s, 200) > 20
