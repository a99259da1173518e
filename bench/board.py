"""How many simulated seconds the board advances per wall second.

    python3 bench/board.py

(a) driving: both wheels running (counts 125 and 200), RCL's 10 ms tick
    (6667 SET-TIMER) with a small Forth handler in INT 1Ch that latches and
    reads both 8253s every tick, while the foreground waits 100 s with MS.
    Target: at least 100 simulated seconds per wall second.
(b) idle: the power-on BIOS tick (54.9 ms) with its do-nothing INT 1Ch,
    the foreground waiting for a time of day 8 hours ahead by polling the
    BIOS tick count between one-second waits. Target: at least 10,000.
"""
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
import rcl  # noqa: E402

LAYER = (pathlib.Path(__file__).resolve().parent.parent / "tests" / "board_layer.fs").read_text()
DRIVING = """
2VARIABLE L  2VARIABLE R
: TICK  128 READ L 2!  132 READ R 2! ;
6667 SET-TIMER  ' TICK GET-CS 28 SET-INT
125 128 REF!  200 132 REF!  53 136 PC!
: WAIT-100-S  100 0 DO 1000 MS LOOP ;
"""
IDLE = """
: WAIT-FOR ( d -- )  BEGIN 2DUP BIOS-TICKS D< 0= WHILE 1000 MS REPEAT 2DROP ;
"""


def measure(setup, run):
    m = rcl.open(screens=False)          # the board alone, with our own small layer
    m.evaluate(LAYER + setup)
    start = m.seconds
    t0, c0 = time.perf_counter(), time.process_time()
    m.evaluate(run)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return m.seconds - start, wall, cpu, m


def main():
    sim, wall, cpu, m = measure(DRIVING, "WAIT-100-S")
    print("(a) driving: %.1f simulated s in %.2f wall s = %.0f simulated s per wall s "
          "(%.0f per CPU s; %d ticks, %d overruns; target >= 100)"
          % (sim, wall, sim / wall, sim / cpu, m.sim.ticks, m.sim.overruns))
    day = 8 * 3600 * 36_000_000_000 // (36617 * 54_000)       # BIOS ticks in 8 h
    sim, wall, cpu, m = measure(IDLE, "%d. WAIT-FOR" % day)
    print("(b) idle: %.0f simulated s in %.3f wall s = %.0f simulated s per wall s "
          "(%.0f per CPU s; %d BIOS ticks; target >= 10,000)"
          % (sim, wall, sim / wall, sim / cpu, m.sim.bios_ticks))


if __name__ == "__main__":
    main()
