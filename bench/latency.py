"""The host's tick latency (docs/protocol.md, section 5: what a host needs):
from a TICK's arrival (the moment the link's reader thread read its bytes)
to the host's final TICK_DONE for it sent, over one long move against a
free-running board, on an idle machine and with CPU hogs beside it.

    python3 bench/latency.py [--seconds 120] [--hogs 0,2] [--board rcl-board,uno]
                             [--nice N] [--profile FILE]

Boards: `rcl-board --pty --free-running` (the simulated board in real
time, never waiting for the host, as a real board) and, with `uno`, the
firmware's Uno image under rcl-simavr --free-running (its 115200-baud
line, in real time). Each run: `RERB 1 MPH n FEET FORWARD`, n giving a
move of --seconds (17.6 in/s); a move that fails (Host too slow, ...) is
counted and followed by one for the time left. A hog is `python3 -c 'while 1: pass'`,
started before the move and killed after it.

Figures, per board and number of hogs: the latency's p50, p90, p99 and
max in ms; ticks run, skipped (the host was over 25 ticks behind) and
late by over 50 ms; the host's CPU time per tick (this process: the
Forth handler, the reader thread, the waits) and the handler's own; and
the moves that failed, with why the first did. --profile writes a cProfile of the main thread's
part of the last run (what the host does per tick) to FILE. --nice N
runs the host and the board N steps of niceness above the hogs; under
`chrt -f 10` both run with a real-time priority and the hogs without
(docs/protocol.md advises either for a computer on the robot; they need
the right to raise priority, root or CAP_SYS_NICE).
"""
import argparse
import cProfile
import os
import pathlib
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
import rcl  # noqa: E402

IPS = 17.6                       # 1 MPH in inches per second
SIMAVR = ROOT / "firmware" / "simavr" / "build" / "rcl-simavr"
UNO = ROOT / "firmware" / "build" / "uno.elf"


def start_board(kind):
    """-> (process, pty path) of a free-running board."""
    if kind == "uno":
        if not (SIMAVR.exists() and UNO.exists()):
            subprocess.run(["make", "-C", str(ROOT / "firmware"), "uno", "simavr"],
                           check=True, capture_output=True)
        argv = [str(SIMAVR), "--quiet", "--free-running", str(UNO)]
    else:
        argv = [sys.executable, "-m", "rcl.hw.boardcli", "--pty", "--free-running"]
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.Popen(argv, stdout=subprocess.PIPE, stdin=subprocess.DEVNULL,
                            text=True, env=env)
    return proc, proc.stdout.readline().strip()


def start(kind, tries=3):
    """-> (board process, rcl on it, RCL loaded); both anew if the link is
    lost while loading (a loaded machine can starve the board 250 ms)."""
    for i in range(tries):
        board, path = start_board(kind)
        try:
            return board, rcl.open(port=path)
        except rcl.RclError as e:
            board.terminate()
            board.wait(10)
            print("(loading RCL failed: %s%s)" % (e, "; again" if i + 1 < tries else ""))
            if i + 1 == tries:
                raise


def ordinary():
    """In a hog, before it runs: none of the priority the host was given
    (--nice, or a real-time policy from `chrt -f 10 python3 bench/...`)."""
    if os.sched_getscheduler(0) != os.SCHED_OTHER:
        os.sched_setscheduler(0, os.SCHED_OTHER, os.sched_param(0))
    if os.nice(0) < 0:
        os.nice(-os.nice(0))


def percentile(sorted_values, p):
    if not sorted_values:
        return float("nan")
    return sorted_values[min(len(sorted_values) - 1, int(p / 100 * len(sorted_values)))]


def measure(kind, hogs, seconds, profile=None):
    """One long move; -> a dict of figures."""
    board, m = start(kind)
    hog_procs = []
    try:
        link = m.board
        delays, handler_cpu = [], [0.0]
        run_tick = link.run_tick

        def timed(machine, tick):
            t0 = time.thread_time()
            run_tick(machine, tick)
            delays.append(time.monotonic() - tick.arrived)
            handler_cpu[0] += time.thread_time() - t0
        link.run_tick = timed
        hog_procs = [subprocess.Popen(["python3", "-c", "while 1: pass"], preexec_fn=ordinary)
                     for _ in range(hogs)]
        ticks0, skipped0 = link.ticks, link.skipped
        wall0, cpu0 = time.monotonic(), time.process_time()
        prof = cProfile.Profile() if profile else None
        if prof:
            prof.enable()
        errors = []
        while True:             # a move that fails is counted, and the rest of the time moved
            left = seconds - (time.monotonic() - wall0)
            if left < 1:
                break
            try:
                m.evaluate("RERB 1 MPH %.1f FEET FORWARD" % (left * IPS / 12))
            except rcl.ForthError as e:
                errors.append(e.screen().strip())
                time.sleep(0.6)             # (a lost link is tried again after 0.5 s)
        ended = "%d failed%s" % (len(errors), (": " + errors[0]) if errors else "")
        if prof:
            prof.disable()
            prof.dump_stats(profile)
        wall, cpu = time.monotonic() - wall0, time.process_time() - cpu0
        ticks = link.ticks - ticks0
        link.close()
    finally:
        for h in hog_procs:
            h.kill()
            h.wait()
        board.terminate()
        board.wait(10)
    ms = sorted(d * 1000 for d in delays)
    return {"board": kind, "hogs": hogs, "wall": wall, "ticks": ticks,
            "skipped": link.skipped - skipped0, "over_50": sum(d > 50 for d in ms),
            "p50": percentile(ms, 50), "p90": percentile(ms, 90), "p99": percentile(ms, 99),
            "max": ms[-1] if ms else float("nan"),
            "cpu_per_tick_ms": 1000 * cpu / max(1, ticks),
            "handler_per_tick_ms": 1000 * handler_cpu[0] / max(1, len(delays)),
            "ended": ended}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seconds", type=float, default=120.0, help="the move's length (120)")
    p.add_argument("--hogs", default="0,2", help="hog counts to run, in order (0,2)")
    p.add_argument("--board", default="rcl-board", help="rcl-board and/or uno (rcl-board)")
    p.add_argument("--profile", metavar="FILE", help="cProfile the last run's main thread")
    p.add_argument("--nice", type=int, default=0, metavar="N",
                   help="host and board N niceness steps above the hogs (needs privilege)")
    args = p.parse_args()
    if args.nice:
        os.nice(-args.nice)
    runs = [(b, int(h)) for b in args.board.split(",") for h in args.hogs.split(",")]
    print("tick latency: TICK read -> final TICK_DONE sent, one %.0f s move at 1 MPH, "
          "on %d cores (load %.1f), Python %s, niceness %d%s" % (
              args.seconds, os.cpu_count(), os.getloadavg()[0], sys.version.split()[0],
              os.nice(0), ", real-time" if os.sched_getscheduler(0) != os.SCHED_OTHER else ""))
    print("%-10s %4s %7s %7s %7s %8s %6s %5s %6s %9s %9s  %s" % (
        "board", "hogs", "p50 ms", "p90 ms", "p99 ms", "max ms", "ticks", "skip", ">50ms",
        "cpu/tick", "handler", "ended"))
    for i, (kind, hogs) in enumerate(runs):
        r = measure(kind, hogs, args.seconds,
                    args.profile if i == len(runs) - 1 else None)
        print("%-10s %4d %7.2f %7.2f %7.2f %8.1f %6d %5d %6d %7.3fms %7.3fms  %s" % (
            r["board"], r["hogs"], r["p50"], r["p90"], r["p99"], r["max"], r["ticks"],
            r["skipped"], r["over_50"], r["cpu_per_tick_ms"], r["handler_per_tick_ms"],
            r["ended"]), flush=True)


if __name__ == "__main__":
    main()
