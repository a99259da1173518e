"""The simulated board, driven from Forth through its ports as RCL drives
it (rcl/sim: the 80188's timers, the 8253s, the latches, the motor model),
with the numbers of rcl/sim/constants.py and docs/guide.md section 13."""
import io
import pathlib

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import rcl
import rcl.sim.board
from rcl.forth.primitives import CLOCK_HZ
from rcl.sim.observe import Trace
from rcl.sim.pace import Pacer

TICK = 6667 * 54_000            # 10.0005 ms in clock units
MS = CLOCK_HZ // 1000

# A minimal hardware layer of our own (RCL's real one is in screens/).
LAYER = (pathlib.Path(__file__).parent / "board_layer.fs").read_text()
BOTH_FORWARD = 0x35             # M1-ON M2-ON M1-GO M2-GO
SPIN_CW = 0x3D                  # as BOTH_FORWARD, plus M2-REV


@pytest.fixture
def m():
    m = rcl.open(screens=False)
    m.evaluate(LAYER)
    return m


def drive(m, relays, count_left, count_right=None):
    count_right = count_left if count_right is None else count_right
    m.evaluate("%d 128 REF!  %d 132 REF!  %d 136 PC!" % (count_left, count_right, relays))


def forward_counts(m):
    m.evaluate("128 READ 132 READ")
    lf, lr, rf, rr = (v & 0xFFFF for v in m.stack)
    m.evaluate("2DROP 2DROP")
    return lf, rf


# --------------------------------------------------------------- ports
def test_unused_ports_read_ff_and_ignore_writes(m):
    assert m.evaluate("HEX 0 PC@ . 7F PC@ . 1234 P@ U. 55 10 PC! 10 PC@ . DECIMAL") \
        == "FF FF FFFF FF "


def test_write_only_latches_read_back_as_floating_bus(m):
    assert m.evaluate("HEX 35 88 PC! 88 PC@ . 10 89 PC! 89 PC@ . DECIMAL") == "FF FF "
    assert m.sim.relays == (0x35, 0x10)


def test_status_at_power_on_shows_the_arm_at_the_top_and_the_jaws_closed(m):
    assert m.evaluate("138 PC@ .") == "9 "


# ------------------------------------------------------ 80188 and BIOS
def test_the_bios_tick_runs_every_36617_counts_at_power_on(m):
    m.sim.run(10.0)
    assert m.sim.ticks == 10 * CLOCK_HZ // (36617 * 54_000)        # 182
    assert m.sim.bios_ticks == m.sim.ticks


def test_6667_max_count_with_the_1_5_us_clock_gives_a_10_0005_ms_tick(m):
    times = []
    m.sim.board.observers.append(lambda b: times.append(b.machine.clock))
    m.evaluate("6667 SET-TIMER")
    m.sim.run(1.0)
    gaps = {b - a for a, b in zip(times[1:], times[2:])}
    assert gaps == {TICK}
    assert TICK / CLOCK_HZ == 0.0100005


def test_a_forth_word_in_the_vector_table_runs_each_tick_on_its_own_stacks(m):
    m.evaluate("VARIABLE N  VARIABLE DEEP  : TICK  DEPTH DEEP !  1 N +!  7 8 9 ;")
    m.evaluate("6667 SET-TIMER  ' TICK GET-CS 28 SET-INT")
    m.evaluate("11 22 33 : BUSY 20000 0 DO LOOP ; BUSY")
    ticks = m.sim.ticks
    assert ticks >= 50
    assert m.evaluate("N @ . DEEP @ .") == "%d 0 " % ticks
    assert m.stack == [11, 22, 33]
    assert m.sim.bios_ticks == ticks


def test_a_handler_that_does_too_much_overruns_and_the_overrun_is_counted(m):
    m.evaluate(": HEAVY  500 0 DO LOOP ;  6667 SET-TIMER  ' HEAVY GET-CS 28 SET-INT")
    m.evaluate(": BUSY 3000 0 DO LOOP ; BUSY")                   # ~14 ms per handler
    assert m.sim.overruns > 0
    assert m.sim.board.pcb.missed > 0


def test_interrupts_off_stops_the_ticks_while_the_timer_keeps_counting(m):
    m.evaluate("HEX C009 FF56 P! DECIMAL")
    before = m.evaluate("HEX FF50 P@ U. DECIMAL")
    m.sim.run(1.0)
    assert m.sim.ticks == 0
    assert m.evaluate("HEX FF50 P@ U. DECIMAL") != before
    m.evaluate("HEX E009 FF56 P! DECIMAL")
    m.sim.run(1.0)
    assert m.sim.ticks > 0


# ----------------------------------------------------------- physics
def test_count_125_on_both_wheels_gives_1000_counts_a_second_and_35_2_inches(m):
    drive(m, BOTH_FORWARD, 125)
    m.sim.run(1.0)                                              # settle
    (l0, r0), (x0, _, _), t0 = forward_counts(m), m.sim.pose, m.sim.seconds
    m.sim.run(1.0)
    (l1, r1), (x1, y1, heading), t1 = forward_counts(m), m.sim.pose, m.sim.seconds
    # The 8253s count down: the pulses are the drop of the counters.
    assert abs((l0 - l1) % 65536 - 1000 * (t1 - t0)) <= 1
    assert abs((r0 - r1) % 65536 - 1000 * (t1 - t0)) <= 1
    assert (x1 - x0) / (t1 - t0) == pytest.approx(35.2, abs=0.05)
    assert (y1, heading) == (pytest.approx(0, abs=1e-9), pytest.approx(0, abs=1e-9))


def test_opposite_directions_spin_in_place_1250_counts_per_wheel_a_turn(m):
    drive(m, SPIN_CW, 125)
    m.sim.run(3.0)
    left, right = m.sim.wheel_counts
    x, y, heading = m.sim.pose
    assert left > 2000 and right == pytest.approx(-left, abs=2)
    assert heading == pytest.approx(-360 * left / 1250, abs=0.2)   # clockwise
    assert (x, y) == (pytest.approx(0, abs=0.01), pytest.approx(0, abs=0.01))


def test_a_stalled_wheel_delivers_no_counts(m):
    m.sim.stall("left")
    drive(m, BOTH_FORWARD, 125)
    m.sim.run(1.0)
    left, right = m.sim.wheel_counts
    assert left == 0 and right > 900


def test_a_too_fast_reference_change_lags_by_the_torque_limit(m):
    drive(m, BOTH_FORWARD, 50)                                  # 0 -> 2500 Hz at once
    m.sim.run(0.1)
    assert m.sim.wheel_rates[0] <= 0.5 * 386.4 * 625 / 22 * 0.1 + 1   # 548.9 counts/s
    assert m.sim.references[0] == 2500.0


def test_coasting_and_braking_stop_the_wheels(m):
    drive(m, BOTH_FORWARD, 125)
    m.sim.run(1.0)
    m.evaluate("HEX 5 88 PC! DECIMAL")                          # ON, GO off: coast
    m.sim.run(0.3)
    coasting = m.sim.wheel_rates[0]
    m.evaluate("0 136 PC!")                                     # relays off: brake
    m.sim.run(0.3)
    assert 300 < coasting < 400                                 # e^-1 of 1000
    assert abs(m.sim.wheel_rates[0]) < 0.01 * coasting


def test_the_arm_moves_an_inch_a_second_and_stops_at_its_limit(m):
    m.evaluate("HEX 3 89 PC! DECIMAL")                          # ARM-ON, down
    m.sim.run(3.1)
    m.evaluate("0 137 PC!")
    assert m.sim.arm == pytest.approx(4.9, abs=0.002)
    m.evaluate("1 137 PC!")                                     # up, past the top
    m.sim.run(5.0)
    assert m.sim.arm == 8.0
    assert int(m.evaluate("138 PC@ .")) & 1                      # ARM-TOP


def test_the_gripper_stops_on_an_object_and_says_closed(m):
    m.evaluate("HEX 4 89 PC! DECIMAL")                          # open: 3 in at 0.5 in/s
    m.sim.run(7.0)
    assert m.sim.jaw == 3.0 and int(m.evaluate("138 PC@ .")) & 4   # GRIP-OPENED
    m.sim.block_gripper(1.5)
    m.evaluate("HEX C 89 PC! DECIMAL")                          # close
    m.sim.run(7.0)
    assert m.sim.jaw == pytest.approx(1.5)
    assert int(m.evaluate("138 PC@ .")) & 8                      # GRIP-CLOSED


def test_the_charger_shows_on_the_status_port(m):
    m.sim.charger(True)
    assert int(m.evaluate("138 PC@ .")) & 64


def test_beeper_intervals_are_recorded_in_seconds(m):
    m.evaluate("16 137 PC!  100 MS  0 137 PC!")
    (start, end), = m.sim.beeps
    assert end - start == pytest.approx(0.1, abs=1e-4)          # + the PC! words


# --------------------------------------------------- time and tracing
def waiting_trace(busy):
    """Wheels moving, a Forth handler reading the encoders every tick, and
    the foreground waiting 3 s either by a busy loop or by skipping ahead."""
    m = rcl.open(screens=False)
    m.evaluate(LAYER)
    m.evaluate("2VARIABLE SEEN  : TICK  128 READ SEEN 2! ;"
               "  6667 SET-TIMER  ' TICK GET-CS 28 SET-INT")
    drive(m, BOTH_FORWARD, 125, 200)
    trace = Trace(m.sim.board, keep=True)
    m.evaluate(": BUSYMS  0 ?DO 33 0 DO LOOP LOOP ;")   # Listing 3's calibrated loop
    m.evaluate(("%d BUSYMS" if busy else "%d MS") % 3000)
    return [row[1:] for row in trace.rows], m


def test_skipping_ahead_while_waiting_gives_the_same_ticks_as_a_busy_wait():
    busy, mb = waiting_trace(busy=True)
    skipped, ms = waiting_trace(busy=False)
    n = min(len(busy), len(skipped))
    assert n > 290
    assert busy[:n] == skipped[:n]


def test_idle_waiting_counts_the_bios_ticks_exactly():
    m = rcl.open(screens=False)
    m.evaluate(": HOUR  60 0 DO 60000 MS LOOP ;  HOUR")
    assert m.sim.bios_ticks == 3600 * CLOCK_HZ // (36617 * 54_000)   # 65,543


def test_the_bios_count_wraps_at_midnight_with_the_flag_set(m):
    m.sim.board.low_store32(0x46C, 1_573_040 - 2)
    m.sim.run(0.2)
    assert m.sim.bios_ticks < 10 and m.sim.board.low[0x470] == 1


def test_the_trace_writes_a_row_only_for_ticks_in_which_something_changed(m):
    out = io.StringIO()
    Trace(m.sim.board, out)
    m.evaluate("6667 SET-TIMER")
    m.sim.run(1.0)                                              # nothing moves
    idle_rows = out.getvalue().count("\n")
    drive(m, BOTH_FORWARD, 125)
    m.sim.run(1.0)
    rows = out.getvalue().splitlines()
    assert rows[0].startswith("t,x,y,heading,left,right")
    assert idle_rows <= 3
    assert len(rows) - idle_rows >= 99


def test_real_time_pace_sleeps_until_the_wall_clock_catches_up():
    wall = [100.0]
    slept = []
    pacer = Pacer(0, wall=lambda: wall[0], sleep=lambda s: slept.append(s))
    pacer.wait(CLOCK_HZ // 100)                                 # 10 ms ahead of the wall
    wall[0] += 0.5                                              # the host fell behind
    pacer.wait(CLOCK_HZ // 50)
    assert slept == [pytest.approx(0.01)]
    assert list(pacer.lateness) == [0.0, pytest.approx(0.48)]
    assert (pacer.ticks, pacer.late, pacer.worst) == (2, 1, pytest.approx(0.48))


def test_real_time_pace_keeps_its_memory_bounded_however_long_it_runs():
    wall = [0.0]
    pacer = Pacer(0, wall=lambda: wall[0], sleep=lambda s: wall.__setitem__(0, wall[0] + s))
    for tick in range(1, 20_001):                               # 200 s of ticks
        pacer.wait(tick * CLOCK_HZ // 100)
    assert len(pacer.lateness) == 6000                          # the last minute
    assert (pacer.ticks, pacer.late) == (20_000, 0)


def test_open_gives_a_machine_on_the_simulated_board_at_power_on():
    m = rcl.open(screens=False)
    assert m.sim.pose == (0.0, 0.0, 0.0)
    assert (m.sim.arm, m.sim.jaw, m.sim.wheel_counts) == (8.0, 0.0, (0, 0))
    assert m.evaluate("2 3 + .") == "5 "


def two_boards_driving(relays, count):
    """Two boards alike, their wheels told to drive (relays, speed count)."""
    boards = []
    for _ in range(2):
        m = rcl.open(screens=False)
        m.evaluate(LAYER)
        drive(m, relays, count)
        boards.append(m.sim.board)
    return boards


def board_state(b):
    """Everything the physics decides, to the last bit."""
    d = b.drive
    return ([(w.rate, w.pos_frac, w.forward_counts, w.reverse_counts) for w in (d.left, d.right)],
            (d.robot.x, d.robot.y, d.robot.heading_rad),
            [c.value for chip in b.chips.values() for c in chip.counters[1:]])


@pytest.mark.parametrize("relays, count", [(BOTH_FORWARD, 50), (SPIN_CW, 60)])
def test_a_stretch_of_accelerating_milliseconds_brought_up_at_once_equals_one_at_a_time(relays, count):
    # physics_to hands a stepped stretch's pulses to the 8253s once, at its end
    at_once, one_by_one = two_boards_driving(relays, count)
    start = at_once.physics_ms
    at_once.physics_to(start + 90)
    for ms in range(start + 1, start + 91):
        one_by_one.physics_to(ms)
    assert not at_once.drive.steady(at_once.motor_latch, at_once.aux_latch, *at_once.refs)
    assert board_state(at_once) == board_state(one_by_one)
    assert at_once.drive.left.forward_counts + at_once.drive.left.reverse_counts > 5


def all_counters(b):
    """Every 8253 counter's count and OUT, the speed references' too."""
    for base in b.chips:
        b._clock_ref(base, b.machine.clock)
    return [(c.value, c.out) for chip in b.chips.values() for c in chip.counters]


@settings(max_examples=40, deadline=None, derandomize=True, database=None)
@given(relays=st.sampled_from([BOTH_FORWARD, SPIN_CW]), count=st.sampled_from([50, 125, 200]),
       cuts=st.lists(st.integers(1, 1499), max_size=30))
def test_the_physics_brought_up_at_any_moments_equals_it_brought_up_at_once(relays, count, cuts):
    # a ramp, then a steady stretch: a port access may come at any millisecond
    at_once, cut = two_boards_driving(relays, count)
    start = at_once.physics_ms
    at_once.physics_to(start + 1500)
    for ms in sorted(set(cuts)) + [1500]:
        cut.physics_to(start + ms)
    assert at_once.drive.steady(at_once.motor_latch, at_once.aux_latch, *at_once.refs)
    assert board_state(cut) == board_state(at_once)


class EagerBoard(rcl.sim.board.SimBoard):
    """The physics and the 8253s' CLK brought up at every port access."""

    def out8(self, port, byte):
        self.sync()
        for base in self.chips:
            self._clock_ref(base, self.machine.clock)
        super().out8(port, byte)

    def in8(self, port):
        self.sync()
        return super().in8(port)

    def port_script(self, ops):
        self.sync()
        return super().port_script(ops)


def test_the_board_that_brings_its_physics_up_only_when_it_must_ends_on_the_same_bits():
    # RCL's control word writes both speed counts every tick, most of them
    # the same again: such writes and latched reads leave the physics alone
    words = ".1 G RERB 25.5 IPS  3.5 FEET FORWARD 90 DEGREES LEFT  1 FEET BACKWARD"
    lazy, eager = rcl.open(board=rcl.sim.board.SimBoard()), rcl.open(board=EagerBoard())
    for m in (lazy, eager):
        m.evaluate(words)
        m.sim.board.sync()
    assert lazy.clock == eager.clock and lazy.sim.ticks == eager.sim.ticks
    assert board_state(lazy.sim.board) == board_state(eager.sim.board)
    assert all_counters(lazy.sim.board) == all_counters(eager.sim.board)
    assert lazy.sim.board.drive.left.forward_counts > 1000
