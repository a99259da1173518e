"""The 80188 timers and timer interrupts (rcl/sim/timer80188.py, after
Intel's data sheet; the BIOS's power-on state: docs/protocol.md section 6).

Offsets are from the PCB base 0xFF00: 0x56 is timer 0's control at 0xFF56.
Time is in clock units of 1/36 ns; one timer-0 count (1.5 us) is 54,000.
"""
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcl.forth.primitives import CLOCK_HZ
from rcl.sim.timer80188 import (
    T0_BIOS_COUNT, T0_CLOCK, T0_RCL_COUNT, TIMER_CLOCK, Timer, Timer80188, error)

T0_COUNT, T0_MAX_A, T0_CONTROL = 0x50, 0x52, 0x56
T1_COUNT, T1_MAX_A, T1_CONTROL = 0x58, 0x5A, 0x5E
T2_COUNT, T2_MAX, T2_CONTROL = 0x60, 0x62, 0x66
EOI, MASK, IN_SERVICE, REQUEST, TIMER_CONTROL = 0x22, 0x28, 0x2C, 0x2E, 0x32
INT_ON, INT_OFF = 0xE009, 0xC009          # RCL's INT-ON / INT-OFF words
RCL_PERIOD = 360_018_000                  # 6667 x 1.5 us = 10.0005 ms
BIOS_PERIOD = 1_977_318_000               # 36,617 x 1.5 us = 54.9255 ms


def tenths_of_us(units):
    return units * 10_000_000 // CLOCK_HZ


def rcl_rate(now=0):
    """A chip after RCL's INSTALL at `now`: max count 6667, count restarted."""
    chip = Timer80188.power_on(now)
    chip.write16(T0_CONTROL, INT_OFF, now)
    chip.write16(T0_MAX_A, T0_RCL_COUNT, now)
    chip.write16(T0_COUNT, 0, now)
    chip.write16(T0_CONTROL, INT_ON, now)
    return chip


def serve(chip, now):
    """Acknowledge and end the interrupt at `now`; return its type."""
    kind = chip.acknowledge(now)
    chip.write16(EOI, 0x0008, now)
    return kind


def test_timer_clock_constants_are_the_reference_numbers():
    assert TIMER_CLOCK == 18_000                      # 0.5 us, 2 MHz
    assert T0_CLOCK == 54_000                         # 1.5 us, 2 MHz / 3


def test_max_count_6667_with_the_prescaler_gives_a_10_0005_ms_period():
    chip = rcl_rate()
    first = chip.next_interrupt(0)
    assert first == RCL_PERIOD
    assert tenths_of_us(RCL_PERIOD) == 100_005       # 10.0005 ms


def test_consecutive_rcl_interrupts_are_exactly_one_period_apart():
    chip = rcl_rate()
    times = []
    now = 0
    for _ in range(5):
        now = chip.next_interrupt(now)
        times.append(now)
        assert serve(chip, now) == 8
    assert [b - a for a, b in zip(times, times[1:])] == [RCL_PERIOD] * 4


def test_power_on_period_is_36617_counts_or_54_9255_ms():
    chip = Timer80188.power_on()
    first = chip.next_interrupt(0)
    serve(chip, first)
    assert first == T0_BIOS_COUNT * T0_CLOCK == BIOS_PERIOD
    assert chip.next_interrupt(first) - first == BIOS_PERIOD
    assert tenths_of_us(BIOS_PERIOD) == 549_255      # 54.9255 ms


def test_power_on_registers_read_back_the_bios_setup():
    chip = Timer80188.power_on()
    assert chip.read16(T0_MAX_A, 0) == 36_617
    assert chip.read16(T0_CONTROL, 0) == 0xA009       # EN INT P CONT, INH reads 0
    assert chip.read16(T2_MAX, 0) == 3
    assert chip.read16(T2_CONTROL, 0) == 0x8001       # EN CONT
    assert chip.read16(TIMER_CONTROL, 0) & 0x0008 == 0


def test_int_off_stops_requests_while_the_count_keeps_advancing():
    chip = rcl_rate()
    chip.write16(T0_CONTROL, INT_OFF, 0)
    before = chip.read16(T0_COUNT, 100 * T0_CLOCK)
    after = chip.read16(T0_COUNT, 200 * T0_CLOCK)
    assert (before, after) == (100, 200)
    assert chip.next_interrupt(5 * RCL_PERIOD) is None
    assert chip.timer0_expiries == 5


def test_int_on_resumes_requests_at_the_next_expiry():
    chip = rcl_rate()
    chip.write16(T0_CONTROL, INT_OFF, 0)
    now = 5 * RCL_PERIOD + 1000
    chip.write16(T0_CONTROL, INT_ON, now)
    assert chip.read16(T0_CONTROL, now) == 0xA009
    assert chip.next_interrupt(now) == 6 * RCL_PERIOD


def test_en_cannot_be_set_without_inh():
    chip = Timer80188()
    chip.write16(T1_MAX_A, 10, 0)
    chip.write16(T1_CONTROL, 0x8001, 0)               # EN CONT, no INH
    assert chip.read16(T1_CONTROL, 0) == 0x0001
    assert chip.read16(T1_COUNT, 50 * TIMER_CLOCK) == 0


def test_en_cannot_be_cleared_without_inh():
    chip = Timer80188.power_on()
    chip.write16(T0_CONTROL, 0x2009, 0)               # INT P CONT, no EN, no INH
    assert chip.read16(T0_CONTROL, 0) == 0xA009
    assert chip.read16(T0_COUNT, 7 * T0_CLOCK) == 7


def test_en_cleared_with_inh_stops_the_count():
    chip = Timer80188.power_on()
    chip.write16(T0_CONTROL, 0x6009, 7 * T0_CLOCK)    # INH, EN = 0
    assert chip.read16(T0_CONTROL, 7 * T0_CLOCK) == 0x2009
    assert chip.read16(T0_COUNT, 70 * T0_CLOCK) == 7


def test_count_register_counts_up_and_wraps_at_the_max_count():
    chip = Timer80188()
    chip.write16(T1_MAX_A, 5, 0)
    chip.write16(T1_CONTROL, 0xC001, 0)               # EN INH CONT, 2 MHz clock
    counts = [chip.read16(T1_COUNT, k * TIMER_CLOCK) for k in range(12)]
    assert counts == [0, 1, 2, 3, 4, 0, 1, 2, 3, 4, 0, 1]


def test_timer_2_prescaler_counts_0_1_2_every_half_microsecond():
    chip = Timer80188.power_on()
    counts = [chip.read16(T2_COUNT, k * TIMER_CLOCK) for k in range(7)]
    assert counts == [0, 1, 2, 0, 1, 2, 0]


def test_max_count_0_means_65536():
    chip = Timer80188()
    chip.write16(T1_CONTROL, 0xC001, 0)
    assert chip.read16(T1_COUNT, 65_535 * TIMER_CLOCK) == 65_535
    assert chip.read16(T1_COUNT, 65_536 * TIMER_CLOCK) == 0
    assert chip.timers[1].expiries == 1


def test_mc_is_set_at_expiry_and_cleared_by_software():
    chip = Timer80188.power_on()
    assert chip.read16(T0_CONTROL, BIOS_PERIOD - 1) & 0x0020 == 0
    assert chip.read16(T0_CONTROL, BIOS_PERIOD) & 0x0020
    chip.write16(T0_CONTROL, INT_ON, BIOS_PERIOD)
    assert chip.read16(T0_CONTROL, BIOS_PERIOD) & 0x0020 == 0


def test_a_non_continuous_timer_stops_after_one_expiry():
    chip = Timer80188()
    chip.write16(T1_MAX_A, 4, 0)
    chip.write16(T1_CONTROL, 0xC000, 0)               # EN INH, no CONT
    assert chip.read16(T1_CONTROL, 4 * TIMER_CLOCK) == 0x0020   # EN gone, MC
    assert chip.read16(T1_COUNT, 100 * TIMER_CLOCK) == 0
    assert chip.timers[1].expiries == 1


def test_alternate_mode_uses_max_count_a_then_b():
    chip = Timer80188()
    chip.write16(T1_MAX_A, 3, 0)
    chip.write16(0x5C, 5, 0)                          # max count B
    chip.write16(T1_CONTROL, 0xC003, 0)               # EN INH ALT CONT
    assert chip.read16(T1_CONTROL, 3 * TIMER_CLOCK) & 0x1000    # RIU: B in use
    assert chip.read16(T1_CONTROL, 8 * TIMER_CLOCK) & 0x1000 == 0
    assert chip.read16(T1_COUNT, (8 * 1000 + 4) * TIMER_CLOCK) == 1
    assert chip.timers[1].expiries == 2001


def test_masking_via_0x32_bit_3_stops_requests():
    chip = Timer80188.power_on()
    chip.write16(TIMER_CONTROL, 0x0008, 0)
    assert chip.next_interrupt(0) is None
    assert chip.read16(MASK, 0) & 1
    chip.write16(TIMER_CONTROL, 0x0000, 0)
    assert chip.next_interrupt(0) == BIOS_PERIOD


def test_masking_via_the_mask_register_bit_0_stops_requests():
    chip = Timer80188.power_on()
    chip.write16(MASK, 0x0001, 0)
    assert chip.next_interrupt(0) is None
    assert chip.read16(TIMER_CONTROL, 0) & 0x0008


def test_an_interrupt_in_service_blocks_the_next_until_eoi():
    chip = rcl_rate()
    assert chip.acknowledge(chip.next_interrupt(0)) == 8
    assert chip.read16(IN_SERVICE, RCL_PERIOD) == 1
    assert chip.next_interrupt(RCL_PERIOD) is None
    assert chip.next_interrupt(3 * RCL_PERIOD) is None
    chip.write16(EOI, 0x8000, 3 * RCL_PERIOD)         # non-specific EOI
    assert chip.read16(IN_SERVICE, 3 * RCL_PERIOD) == 0
    assert chip.next_interrupt(3 * RCL_PERIOD) == 2 * RCL_PERIOD   # late


def test_expiries_during_service_are_counted_as_missed():
    chip = rcl_rate()
    chip.acknowledge(RCL_PERIOD)
    later = 4 * RCL_PERIOD + RCL_PERIOD // 2          # 3 more expiries pass
    chip.write16(EOI, 0x0008, later)
    assert chip.acknowledge(later) == 8
    assert chip.missed == 2                           # one served late, two lost
    assert chip.timer0_expiries == 4


def test_on_time_interrupts_miss_nothing():
    chip = rcl_rate()
    now = 0
    for _ in range(10):
        now = chip.next_interrupt(now)
        serve(chip, now)
    assert chip.missed == 0
    assert chip.timer0_expiries == 10


def test_request_register_shows_a_latched_timer_request():
    chip = Timer80188.power_on()
    assert chip.read16(REQUEST, BIOS_PERIOD - 1) == 0
    assert chip.read16(REQUEST, BIOS_PERIOD) == 1
    chip.acknowledge(BIOS_PERIOD)
    assert chip.read16(REQUEST, BIOS_PERIOD) == 0


def test_timer_2_max_count_sets_timer_0_period_through_the_prescaler():
    chip = Timer80188.power_on()
    chip.write16(T2_MAX, 4, 0)                        # 2 MHz / 4 = 2 us per count
    first = chip.next_interrupt(0)
    serve(chip, first)
    assert first == T0_BIOS_COUNT * 4 * TIMER_CLOCK
    assert chip.next_interrupt(first) - first == T0_BIOS_COUNT * 72_000


def test_timer_0_stops_counting_when_the_prescaler_stops():
    chip = Timer80188.power_on()
    chip.write16(T2_CONTROL, 0x4001, 0)               # INH, EN = 0
    assert chip.read16(T0_COUNT, BIOS_PERIOD) == 0
    assert chip.next_interrupt(BIOS_PERIOD) is None


def test_timers_1_and_2_interrupt_with_types_18_and_19():
    chip = Timer80188()
    chip.write16(TIMER_CONTROL, 0, 0)
    chip.write16(T1_MAX_A, 10, 0)
    chip.write16(T1_CONTROL, 0xE001, 0)               # EN INH INT CONT
    chip.write16(T2_MAX, 10, 0)
    chip.write16(T2_CONTROL, 0xE001, 0)
    assert chip.next_interrupt(0) == 10 * TIMER_CLOCK
    assert serve(chip, 10 * TIMER_CLOCK) == 18
    assert serve(chip, 10 * TIMER_CLOCK) == 19


def test_1000_expiries_are_computed_at_once():
    chip = rcl_rate()
    later = 1000 * RCL_PERIOD + 5 * T0_CLOCK
    assert chip.next_interrupt(later) == RCL_PERIOD  # the first, still latched
    assert chip.timer0_expiries == 1000
    assert chip.read16(T0_COUNT, later) == 5
    chip.acknowledge(later)
    assert chip.missed == 999


def test_a_day_of_rcl_ticks_is_counted_exactly():
    chip = rcl_rate()
    chip.write16(T0_CONTROL, INT_OFF, 0)
    chip.read16(T0_COUNT, 8_640_000 * RCL_PERIOD)
    assert chip.timer0_expiries == 8_640_000


def test_unknown_offsets_read_0_and_ignore_writes():
    chip = Timer80188.power_on()
    for offset in (0x00, 0x40, 0x64, 0xFE):
        chip.write16(offset, 0xFFFF, 0)
        assert chip.read16(offset, 0) == 0


def test_timer_2_control_keeps_only_en_int_mc_and_cont():
    chip = Timer80188()
    chip.write16(T2_CONTROL, 0xFFFF, 0)
    assert chip.read16(T2_CONTROL, 0) == 0xA021


def test_time_running_backwards_is_an_error():
    chip = Timer80188.power_on(1000)
    with pytest.raises(error):
        chip.read16(T0_COUNT, 999)


def test_one_big_catch_up_agrees_with_stepping_one_timer_clock_at_a_time():
    setup = [(T2_MAX, 3), (T2_CONTROL, 0xE001), (T0_MAX_A, 4), (0x54, 7),
             (T0_CONTROL, 0xE00B), (T1_MAX_A, 5), (T1_CONTROL, 0xE001), (TIMER_CONTROL, 0)]
    lazy, stepped = Timer80188(), Timer80188()
    for offset, word in setup:
        lazy.write16(offset, word, 0)
        stepped.write16(offset, word, 0)
    end = 500 * TIMER_CLOCK + 7
    for k in range(1, 501):
        stepped.read16(T0_COUNT, k * TIMER_CLOCK)
    registers = (T0_COUNT, T0_CONTROL, T1_COUNT, T1_CONTROL, T2_COUNT, 0x30)
    assert [lazy.read16(r, end) for r in registers] == \
        [stepped.read16(r, end) for r in registers]
    assert [t.pending_at for t in lazy.timers] == [t.pending_at for t in stepped.timers]
    assert [t.requests for t in lazy.timers] == [t.requests for t in stepped.timers]


@settings(max_examples=200, deadline=None)
@given(control=st.sampled_from([0x8001, 0x8003, 0x8000, 0xA001, 0x9003]),
       max_a=st.sampled_from([0, 1, 2, 3, 7, 6667, 65535]), max_b=st.sampled_from([0, 1, 5]),
       count=st.integers(0, 0xFFFF), n=st.integers(0, 70_000))
def test_n_input_clocks_at_once_count_as_n_one_at_a_time(control, max_a, max_b, count, n):
    # Timer.advance's closed form for a restarting timer (and its loop
    # otherwise) against the datasheet's rule applied clock by clock.
    at_once, stepped = Timer(0), Timer(0)
    for t in (at_once, stepped):
        t.control, t.max_a, t.max_b, t.count = control, max_a, max_b, count
    expiries, first = at_once.advance(n)
    total, first_stepped = 0, None
    for k in range(1, n + 1):
        if stepped.advance(1)[0]:
            total, first_stepped = total + 1, first_stepped or k
    assert (expiries, first) == (total, first_stepped)
    assert (at_once.count, at_once.control, at_once.expiries) == \
        (stepped.count, stepped.control, stepped.expiries)
