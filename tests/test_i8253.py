"""The Intel 8253 model (rcl.sim.i8253) against the data sheet's facts its
docstring lists."""
import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcl.sim.i8253 import HIGH, LOW, Counter, I8253

CONTROL = 3


def programmed(control, *count_bytes):
    """A chip after one control word to offset 3 and count bytes to its counter."""
    chip = I8253()
    chip.write(CONTROL, control)
    offset = control >> 6
    for byte in count_bytes:
        chip.write(offset, byte)
    return chip


def read_word(chip, offset):
    """LSB then MSB from one counter address."""
    lsb = chip.read(offset)
    return lsb | chip.read(offset) << 8


def out_levels(counter, clocks):
    """OUT now and after each of `clocks` single CLK pulses."""
    levels = [counter.out]
    for _ in range(clocks):
        counter.clock(1)
        levels.append(counter.out)
    return levels


def run_lengths(levels):
    """[(level, how many in a row), ...]"""
    runs = []
    for level in levels:
        if runs and runs[-1][0] == level:
            runs[-1][1] += 1
        else:
            runs.append([level, 1])
    return [tuple(run) for run in runs]


# ----------------------------------------------------------------------
# Control word
# ----------------------------------------------------------------------

def test_control_0x36_selects_counter_0_lsb_msb_mode_3_binary():
    counter = programmed(0x36).counters[0]
    assert (counter.mode, counter.rw, counter.bcd) == (3, Counter.RW_BOTH, False)


def test_control_0x74_selects_counter_1_lsb_msb_mode_2():
    chip = programmed(0x74)
    assert (chip.counters[1].mode, chip.counters[1].rw) == (2, Counter.RW_BOTH)
    assert chip.counters[0].mode is None and chip.counters[2].mode is None


def test_control_0xb4_selects_counter_2_lsb_msb_mode_2():
    chip = programmed(0xB4)
    assert (chip.counters[2].mode, chip.counters[2].rw) == (2, Counter.RW_BOTH)
    assert chip.counters[0].mode is None and chip.counters[1].mode is None


def test_mode_bits_110_and_111_mean_modes_2_and_3():
    # 0x1C = 00 01 110 0, 0x1E = 00 01 111 0
    assert programmed(0x1C).counters[0].mode == 2
    assert programmed(0x1E).counters[0].mode == 3


def test_decode_splits_a_control_byte_into_its_fields():
    assert I8253.decode(0xB4) == (2, 3, 2, 0)
    assert I8253.decode(0x53) == (1, 1, 1, 1)


def test_select_counter_11_is_ignored_on_an_8253():
    chip = I8253()
    chip.write(CONTROL, 0xF6)
    assert all(counter.mode is None for counter in chip.counters)


def test_the_control_register_reads_0xff():
    chip = programmed(0x36, 0x10, 0x00)
    assert chip.read(CONTROL) == 0xFF


def test_offsets_are_decoded_from_a1_a0_only():
    chip = I8253()
    chip.write(7, 0x74)
    assert chip.counters[1].mode == 2


def test_a_control_word_sets_out_low_in_mode_0_and_high_in_the_others():
    assert programmed(0x30).counters[0].out == LOW
    for mode in (1, 2, 3, 4, 5):
        assert programmed(0x30 | mode << 1).counters[0].out == HIGH


def test_a_control_word_leaves_the_counter_waiting_for_a_new_count():
    chip = programmed(0x74, 0x10, 0x00)
    chip.write(CONTROL, 0x74)
    counter = chip.counters[1]
    before = counter.value
    counter.clock(5)
    assert counter.n is None and counter.value == before


# ----------------------------------------------------------------------
# Writing counts
# ----------------------------------------------------------------------

def test_a_counter_before_any_count_is_written_does_not_count():
    chip = programmed(0x74)
    counter = chip.counters[1]
    counter.clock(1000)
    assert counter.n is None and counter.value == 0 and counter.out == HIGH


def test_a_fresh_chip_ignores_count_writes_and_does_not_count():
    chip = I8253()
    chip.write(0, 0x12)
    chip.counters[0].clock(1000)
    assert chip.counters[0].n is None and chip.counters[0].value == 0


def test_rw_11_takes_the_lsb_first_then_the_msb():
    counter = programmed(0x74, 0x34, 0x12).counters[1]
    assert counter.n == 0x1234 and counter.value == 0x1234


def test_rw_11_count_is_not_complete_until_the_msb():
    counter = programmed(0x74, 0x34).counters[1]
    assert counter.n is None


def test_rw_01_writes_the_lsb_only_with_msb_zero():
    # 0x54 = 01 01 010 0: counter 1, LSB only, mode 2
    counter = programmed(0x54, 0x99).counters[1]
    assert counter.n == 0x0099


def test_rw_10_writes_the_msb_only_with_lsb_zero():
    # 0x64 = 01 10 010 0: counter 1, MSB only, mode 2
    counter = programmed(0x64, 0x12).counters[1]
    assert counter.n == 0x1200


def test_count_0_means_65536_in_binary():
    counter = programmed(0x74, 0x00, 0x00).counters[1]
    assert counter.n == 65536


def test_count_0_means_10000_in_bcd():
    # 0x75 = 01 11 010 1: counter 1, LSB+MSB, mode 2, BCD
    counter = programmed(0x75, 0x00, 0x00).counters[1]
    assert counter.n == 10000


def test_a_bcd_count_is_read_as_decimal_digits():
    counter = programmed(0x75, 0x34, 0x12).counters[1]
    assert counter.n == 1234


def test_rewriting_a_mode_2_count_takes_effect_at_the_next_reload():
    chip = programmed(0x74, 5, 0)
    counter = chip.counters[1]
    counter.clock(2)                        # CE 3
    chip.write(1, 10)
    chip.write(1, 0)
    counter.clock(2)                        # CE 1: the old period runs out
    assert counter.value == 1 and counter.out == LOW
    counter.clock(1)
    assert counter.value == 10 and counter.n == 10


def test_rewriting_a_mode_3_count_takes_effect_at_the_end_of_the_half_cycle():
    chip = programmed(0x36, 4, 0)
    counter = chip.counters[0]
    counter.clock(1)                        # one CLK into the high half of 2
    chip.write(0, 10)
    chip.write(0, 0)
    levels = out_levels(counter, 16)
    assert run_lengths(levels)[:3] == [(HIGH, 1), (LOW, 5), (HIGH, 5)]


def test_writing_the_first_byte_of_a_mode_0_count_stops_counting():
    chip = programmed(0x30, 100, 0)
    counter = chip.counters[0]
    counter.clock(10)
    chip.write(0, 50)
    counter.clock(10)
    assert counter.value == 90


def test_writing_the_second_byte_of_a_mode_0_count_starts_the_new_count():
    chip = programmed(0x30, 100, 0)
    counter = chip.counters[0]
    counter.clock(100)                      # terminal count: OUT high
    chip.write(0, 50)
    chip.write(0, 0)
    assert counter.value == 50 and counter.out == LOW
    counter.clock(10)
    assert counter.value == 40


def test_rewriting_a_mode_4_count_restarts_at_once():
    chip = programmed(0x38, 100, 0)         # 00 11 100 0: mode 4
    counter = chip.counters[0]
    counter.clock(30)
    chip.write(0, 20)
    chip.write(0, 0)
    assert counter.value == 20


# ----------------------------------------------------------------------
# Reading counts and the latch command
# ----------------------------------------------------------------------

@pytest.mark.parametrize("control, latch, offset",
                         [(0x34, 0x00, 0), (0x74, 0x40, 1), (0xB4, 0x80, 2)])
def test_latch_freezes_the_value_while_counting_continues(control, latch, offset):
    chip = programmed(control, 0x00, 0x00)
    counter = chip.counters[offset]
    counter.clock(0x1234)                   # CE = 0x10000 - 0x1234 = 0xEDCC
    chip.write(CONTROL, latch)
    counter.clock(300)
    assert chip.read(offset) == 0xCC
    counter.clock(300)
    assert chip.read(offset) == 0xED
    assert counter.value == 0xEDCC - 600


def test_after_the_latched_value_is_read_reads_follow_the_counter_again():
    chip = programmed(0x74, 0x00, 0x00)
    counter = chip.counters[1]
    chip.write(CONTROL, 0x40)
    counter.clock(0x102)
    assert read_word(chip, 1) == 0x0000
    assert read_word(chip, 1) == 0x10000 - 0x102


def test_a_second_latch_before_the_first_is_read_is_ignored():
    chip = programmed(0x74, 0x00, 0x00)
    counter = chip.counters[1]
    counter.clock(10)
    chip.write(CONTROL, 0x40)
    counter.clock(10)
    chip.write(CONTROL, 0x40)
    assert read_word(chip, 1) == 0x10000 - 10


def test_a_latch_half_read_still_ignores_a_second_latch():
    chip = programmed(0x74, 0x00, 0x00)
    counter = chip.counters[1]
    counter.clock(0x101)                    # CE 0xFEFF
    chip.write(CONTROL, 0x40)
    assert chip.read(1) == 0xFF
    counter.clock(0x100)
    chip.write(CONTROL, 0x40)
    assert chip.read(1) == 0xFE


def test_latching_one_counter_does_not_freeze_another():
    chip = programmed(0x74, 0x00, 0x00)
    chip.write(CONTROL, 0xB4)
    chip.write(2, 0x00)
    chip.write(2, 0x00)
    chip.write(CONTROL, 0x40)
    chip.counters[2].clock(5)
    assert read_word(chip, 2) == 0x10000 - 5


def test_a_plain_two_byte_read_does_not_tear():
    chip = programmed(0x74, 0x00, 0x01)     # count 0x0100
    counter = chip.counters[1]
    assert chip.read(1) == 0x00
    counter.clock(1)                        # CE 0x00FF
    assert chip.read(1) == 0x01


def test_rw_01_reads_return_the_lsb_every_time():
    chip = programmed(0x54, 0x99)
    counter = chip.counters[1]
    counter.clock(0x10)
    assert chip.read(1) == 0x89
    counter.clock(0x10)
    assert chip.read(1) == 0x79


def test_rw_10_reads_return_the_msb_every_time():
    chip = programmed(0x64, 0x12)
    counter = chip.counters[1]
    counter.clock(0x100)
    assert chip.read(1) == 0x11
    assert chip.read(1) == 0x11


def test_read_and_write_byte_flip_flops_are_separate():
    chip = programmed(0x74, 0x34)           # write flip-flop now wants the MSB
    assert chip.read(1) == 0x00             # read flip-flop still on the LSB
    chip.write(1, 0x12)
    assert chip.counters[1].n == 0x1234


# ----------------------------------------------------------------------
# BCD
# ----------------------------------------------------------------------

def test_bcd_0x1000_after_one_clock_reads_0x0999():
    # 0x31 = 00 11 000 1: counter 0, LSB+MSB, mode 0, BCD
    chip = programmed(0x31, 0x00, 0x10)
    chip.counters[0].clock(1)
    assert chip.read(0) == 0x99 and chip.read(0) == 0x09


def test_bcd_counting_wraps_from_0_to_9999():
    chip = programmed(0x31, 0x05, 0x00)
    chip.counters[0].clock(6)
    assert read_word(chip, 0) == 0x9999


def test_bcd_value_is_the_decimal_count():
    chip = programmed(0x31, 0x00, 0x10)
    chip.counters[0].clock(1)
    assert chip.counters[0].value == 999


# ----------------------------------------------------------------------
# Mode 0: interrupt on terminal count
# ----------------------------------------------------------------------

def test_mode_0_out_goes_high_at_terminal_count():
    counter = programmed(0x30, 5, 0).counters[0]
    assert out_levels(counter, 6) == [LOW] * 5 + [HIGH] * 2


def test_mode_0_the_counter_keeps_wrapping_past_terminal_count():
    counter = programmed(0x30, 5, 0).counters[0]
    counter.clock(5 + 65536 + 3)
    assert counter.value == 0xFFFD and counter.out == HIGH


def test_mode_0_gate_low_pauses_counting():
    counter = programmed(0x30, 100, 0).counters[0]
    counter.set_gate(0)
    counter.clock(50)
    counter.set_gate(1)
    counter.clock(10)
    assert counter.value == 90


# ----------------------------------------------------------------------
# Mode 2: rate generator
# ----------------------------------------------------------------------

def test_mode_2_has_period_n_with_out_low_for_one_clk():
    counter = programmed(0x74, 5, 0).counters[1]
    levels = out_levels(counter, 10)
    assert levels == [HIGH, HIGH, HIGH, HIGH, LOW] * 2 + [HIGH]


def test_mode_2_reloads_the_count_at_terminal_count():
    counter = programmed(0x74, 5, 0).counters[1]
    counter.clock(4)
    assert counter.value == 1
    counter.clock(1)
    assert counter.value == 5


def test_mode_2_gate_low_stops_counting_and_forces_out_high():
    counter = programmed(0x74, 5, 0).counters[1]
    counter.clock(4)                        # CE 1, OUT low
    counter.set_gate(0)
    assert counter.out == HIGH
    counter.clock(10)
    assert counter.value == 1 and counter.out == HIGH


def test_mode_2_gate_rising_edge_reloads_the_count():
    counter = programmed(0x74, 5, 0).counters[1]
    counter.clock(3)
    counter.set_gate(0)
    counter.set_gate(1)
    assert counter.value == 5 and counter.out == HIGH


def test_mode_2_count_0_counts_65536_pulses_per_period():
    counter = programmed(0x74, 0, 0).counters[1]
    counter.clock(65535)
    assert counter.value == 1 and counter.out == LOW
    counter.clock(1)
    assert counter.value == 0 and counter.out == HIGH


def test_mode_2_event_counter_deltas_give_every_pulse():
    # 2.6: mode 2, count 0, latch and read, delta = (previous - current) mod 65536
    chip = programmed(0x74, 0x00, 0x00)
    previous, total = read_word(chip, 1), 0
    for batch in (12345, 30000, 27655, 1, 65535):
        chip.counters[1].clock(batch)
        chip.write(CONTROL, 0x40)
        current = read_word(chip, 1)
        total += (previous - current) % 65536
        previous = current
    assert total == 12345 + 30000 + 27655 + 1 + 65535


def lines_run(call):
    """call() -> the number of Python lines it ran (at most 10,000: a
    pulse-by-pulse loop stops there instead of running for ever)."""
    seen = [0]

    def trace(frame, event, arg):
        if event == "line":
            seen[0] += 1
            if seen[0] > 10_000:
                raise RuntimeError("more than 10,000 lines")
        return trace
    sys.settrace(trace)
    try:
        call()
    finally:
        sys.settrace(None)
    return seen[0]


def test_clock_applies_a_huge_batch_at_once():
    # A closed form, counted in the lines it runs (not timed: the same on a busy host)
    counter = programmed(0x74, 7, 0).counters[1]
    assert lines_run(lambda: counter.clock(10 ** 15)) < 100
    assert counter.value == 7 - 10 ** 15 % 7


# ----------------------------------------------------------------------
# Mode 3: square wave
# ----------------------------------------------------------------------

def test_mode_3_even_n_is_high_n_over_2_and_low_n_over_2():
    counter = programmed(0x36, 4, 0).counters[0]
    assert run_lengths(out_levels(counter, 11)) == [(HIGH, 2), (LOW, 2)] * 3


def test_mode_3_odd_n_is_high_n_plus_1_over_2_and_low_n_minus_1_over_2():
    counter = programmed(0x36, 5, 0).counters[0]
    assert run_lengths(out_levels(counter, 14)) == [(HIGH, 3), (LOW, 2)] * 3


def test_mode_3_a_batch_of_clocks_matches_single_steps():
    single = programmed(0x36, 7, 0).counters[0]
    for clocks in range(1, 30):
        single.clock(1)
        batch = programmed(0x36, 7, 0).counters[0]
        batch.clock(clocks)
        assert (batch.out, batch.value) == (single.out, single.value)


def test_mode_3_counter_steps_by_2_per_clock():
    counter = programmed(0x36, 6, 0).counters[0]
    values = [counter.value]
    for _ in range(6):
        counter.clock(1)
        values.append(counter.value)
    assert values == [6, 4, 2, 6, 4, 2, 6]


def test_mode_3_frequency_for_count_125_at_125_khz_is_1000_hz():
    counter = programmed(0x36, 125, 0).counters[0]
    assert counter.frequency(125000) == 1000.0


def test_mode_3_count_0_gives_the_slowest_frequency():
    counter = programmed(0x36, 0, 0).counters[0]
    assert counter.frequency(125000) == 125000 / 65536


def test_frequency_is_0_before_a_count_is_written():
    assert programmed(0x36).counters[0].frequency(125000) == 0.0


def test_frequency_is_0_outside_modes_2_and_3():
    assert programmed(0x30, 125, 0).counters[0].frequency(125000) == 0.0


def test_frequency_is_0_while_gate_is_low():
    counter = programmed(0x36, 125, 0).counters[0]
    counter.set_gate(0)
    assert counter.frequency(125000) == 0.0


def test_frequency_follows_the_last_complete_count():
    chip = programmed(0x36, 125, 0)
    chip.write(0, 250)
    chip.write(0, 0)
    assert chip.counters[0].frequency(125000) == 500.0


# ----------------------------------------------------------------------
# Modes 1, 4 and 5
# ----------------------------------------------------------------------

def test_mode_1_waits_for_a_gate_trigger():
    counter = programmed(0x32, 3, 0).counters[0]    # 00 11 001 0: mode 1
    counter.clock(10)
    assert counter.out == HIGH and counter.value == 0


def test_mode_1_gate_rising_edge_gives_out_low_for_n_clocks():
    counter = programmed(0x32, 3, 0).counters[0]
    counter.set_gate(0)
    counter.set_gate(1)
    assert out_levels(counter, 4) == [LOW, LOW, LOW, HIGH, HIGH]


def test_mode_1_a_new_trigger_restarts_the_one_shot():
    counter = programmed(0x32, 3, 0).counters[0]
    counter.set_gate(0)
    counter.set_gate(1)
    counter.clock(2)
    counter.set_gate(0)
    counter.set_gate(1)
    assert out_levels(counter, 3) == [LOW, LOW, LOW, HIGH]


def test_mode_4_strobes_out_low_for_one_clk_once():
    counter = programmed(0x38, 3, 0).counters[0]
    levels = out_levels(counter, 3 + 65536 + 2)
    assert run_lengths(levels) == [(HIGH, 3), (LOW, 1), (HIGH, 65538)]


def test_mode_4_strobe_after_a_batch_ending_exactly_at_terminal_count():
    counter = programmed(0x38, 100, 0).counters[0]
    counter.clock(100)
    assert counter.out == LOW
    counter.clock(1000)
    assert counter.out == HIGH and counter.value == 65536 - 1000


def test_mode_5_counting_starts_at_a_gate_rising_edge():
    counter = programmed(0x3A, 3, 0).counters[0]    # 00 11 101 0: mode 5
    counter.clock(10)
    assert counter.value == 0
    counter.set_gate(0)
    counter.set_gate(1)
    assert run_lengths(out_levels(counter, 5)) == [(HIGH, 3), (LOW, 1), (HIGH, 2)]


# ----------------------------------------------------------------------
# Counting in parts: the board hands over the pulses of many milliseconds at once
# ----------------------------------------------------------------------

@settings(max_examples=300, deadline=None)
@given(mode=st.integers(0, 5), bcd=st.booleans(), count=st.integers(0, 0xFFFF),
       parts=st.lists(st.integers(1, 70000), min_size=1, max_size=6))
def test_n_clocks_at_once_leave_the_counter_as_the_same_clocks_in_parts(mode, bcd, count, parts):
    control = 0x40 | 0x30 | mode << 1 | int(bcd)            # counter 1, LSB then MSB
    if bcd:
        count = int("%04d" % (count % 10000), 16)
    at_once, in_parts = (programmed(control, count & 0xFF, count >> 8) for _ in range(2))
    for chip in (at_once, in_parts):
        chip.counters[1].set_gate(0)
        chip.counters[1].set_gate(1)                        # a rising edge: triggers modes 1 and 5
    at_once.counters[1].clock(sum(parts))
    for n in parts:
        in_parts.counters[1].clock(n)
    assert vars(at_once.counters[1]) == vars(in_parts.counters[1])
    assert read_word(at_once, 1) == read_word(in_parts, 1)


@settings(max_examples=300, deadline=None)
@given(mode=st.integers(0, 5), count=st.integers(0, 0xFFFF), new=st.integers(0, 0xFFFF),
       before=st.integers(0, 70000), after=st.integers(1, 70000))
def test_clks_may_come_after_a_first_count_byte_that_does_not_act(mode, count, new, before, after):
    # the board brings CLK up before a count byte only when write_acts() says it acts
    control = 0x30 | mode << 1                              # counter 0, LSB then MSB
    first, late = (programmed(control, count & 0xFF, count >> 8) for _ in range(2))
    for chip in (first, late):
        chip.counters[0].clock(before)
    assert first.counters[0].write_acts(new & 0xFF) == (mode == 0)   # an LSB acts only in mode 0
    first.counters[0].clock(after)
    first.write(0, new & 0xFF)
    if not late.counters[0].write_acts(new & 0xFF):
        late.write(0, new & 0xFF)
        late.counters[0].clock(after)
        assert vars(late.counters[0]) == vars(first.counters[0])
    # a count's last byte acts, unless it completes the count a running
    # mode 2 or 3 counter reloads from
    repeats = mode in (2, 3, 6, 7) and (new or 0x10000) == (count or 0x10000)
    assert first.counters[0].write_acts(new >> 8) == (not repeats)


@settings(max_examples=300, deadline=None)
@given(mode=st.sampled_from([2, 3]), rw=st.sampled_from([0x10, 0x20, 0x30]), bcd=st.booleans(),
       count=st.integers(0, 0xFFFF), before=st.integers(0, 70000), after=st.integers(1, 70000))
def test_clks_may_come_after_a_count_that_repeats_the_running_one(mode, rw, bcd, count, before, after):
    # the control word writes the same speed count every tick: the board
    # need not bring CLK up for it (write_acts says so), nor see OUT's
    # frequency change
    control = rw | mode << 1 | int(bcd)                     # counter 0
    if bcd:
        count = int("%04d" % (count % 10000), 16)
    lsb, msb = count & 0xFF, count >> 8
    if rw == 0x10:
        msb = 0
    elif rw == 0x20:
        lsb = 0
    count_bytes = {0x10: [lsb], 0x20: [msb], 0x30: [lsb, msb]}[rw]
    first, late = (programmed(control, *count_bytes) for _ in range(2))
    for chip in (first, late):
        chip.counters[0].clock(before)
    frequency = first.counters[0].frequency(125_000)
    first.counters[0].clock(after)
    for byte in count_bytes:
        first.write(0, byte)
    for byte in count_bytes[:-1]:
        late.write(0, byte)
    assert not late.counters[0].write_acts(count_bytes[-1])
    late.write(0, count_bytes[-1])
    late.counters[0].clock(after)
    assert vars(late.counters[0]) == vars(first.counters[0])
    assert first.counters[0].frequency(125_000) == frequency
