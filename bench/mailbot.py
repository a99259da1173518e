"""RCL's figures: the control word's worst tick, and a whole MAILBOT day.

    python3 bench/mailbot.py

(1) The control loop must fit its 10 ms tick in virtual time with room to
    spare, as on the 80188: the worst INT 1Ch handler time while both
    wheels move (RERB 2 MPH 3.4 FEET FORWARD, then a 25.5 IPS square), as
    a share of the 10.0005 ms tick. Target: at most 50 %.
(2) MAILBOT (Listing 6) started at 8:00 of a simulated day, to the end of
    the 4:30 trip, in the fast clock: wall seconds and simulated seconds
    per wall second (and the CPU seconds, which a loaded machine does not
    inflate). Target: at most 20 wall seconds.
"""
import pathlib
import sys
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
import rcl  # noqa: E402

EXAMPLES = pathlib.Path(rcl.SCREENS) / "examples"
TICK = 6667 * 54_000


def worst_tick():
    m = rcl.open()
    board, costs = m.sim.board, []
    tick = board.bios_tick

    def timed(machine):
        start = machine.clock
        tick(machine)
        if machine.sim.board.drive.left.rate and machine.sim.board.drive.right.rate:
            costs.append(machine.clock - start)
    board.bios_tick = timed
    m.evaluate("RERB 2 MPH 3.4 FEET FORWARD")
    m.include(str(EXAMPLES / "listing1.fs"))
    return max(costs), len(costs)


def mailbot_day():
    m = rcl.open()
    m.include(str(EXAMPLES / "listing6.fs"))
    m.evaluate("8 AM TICKS!")
    start = m.sim.seconds
    t0, c0 = time.perf_counter(), time.process_time()
    m.evaluate("MAILBOT")
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return m.sim.seconds - start, wall, cpu, m.evaluate(".TIME")


def main():
    worst, n = worst_tick()
    print("(1) worst control tick with both wheels moving: %.2f ms of %.4f ms = %.1f %% "
          "(%d ticks; target <= 50 %%)" % (worst / 36e6, TICK / 36e6, 100 * worst / TICK, n))
    sim, wall, cpu, end = mailbot_day()
    print("(2) MAILBOT 8:00 to %s: %.0f simulated s in %.1f wall s (%.1f CPU s) = %.0f "
          "simulated s per wall s (target <= 20 wall s)" % (end.strip(), sim, wall, cpu, sim / wall))


if __name__ == "__main__":
    main()
