"""Robustness figures of the whole system (docs/performance.md, Robustness).

    python3 bench/robustness.py [--lines N] [--trials N] [--seed S]

(a) fuzz: N random lines of the RCL dictionary, hostile ones included
    (tests/robot_fuzz.py, the generator the test suite runs), each with a
    0.25 s virtual budget: how each line ended, by kind, and the lines
    that broke a check (a Python exception, an internal error, a motor
    left on, a dead canary). Target: 0 broken.
(b) Ctrl-C: N trials of a real SIGINT sent to this process by a timer
    thread at a random wall-clock moment of a long move (through the same
    handler the console installs), each followed by the checks of a live
    robot: `.TIME 1000 MS .TIME` differs, a 1 FEET move completes with the
    counters reading what the wheels did. Target: 0 dead ticks.
"""
import argparse
import collections
import os
import pathlib
import random
import signal
import sys
import tempfile
import threading
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
import rcl  # noqa: E402
import robot_fuzz  # noqa: E402


def fuzz(n, seed):
    m = robot_fuzz.machine()
    words = robot_fuzz.dictionary_words(m)
    kinds, broken = collections.Counter(), []
    start = time.process_time()
    for text in robot_fuzz.lines(n, seed, words):
        try:
            kinds[robot_fuzz.run_line(m, text)] += 1
        except Exception as e:             # a check failed, or worse
            broken.append("%s: %s" % (type(e).__name__, e))
            m = robot_fuzz.machine()
    return kinds, broken, time.process_time() - start


def alive(m):
    """The tick runs and a move completes with the counters reading true."""
    before = m.evaluate(".TIME")
    m.evaluate("1000 MS")
    if m.evaluate(".TIME") == before:
        return False
    start = [int(v) for v in m.evaluate("?CNT1 D. ?CNT2 D.").split()]
    m.evaluate("RERB 2 MPH 1 FEET FORWARD")
    m.sim.run(1.0)
    end = [int(v) for v in m.evaluate("?CNT1 D. ?CNT2 D.").split()]
    return tuple(end) == m.sim.wheel_counts and all(
        abs(e - s - 341) <= 4 for s, e in zip(start, end))


def ctrl_c(trials, seed):
    rng = random.Random(seed)
    dead, interrupted = 0, 0
    for _ in range(trials):
        m = rcl.open()
        timer = threading.Timer(rng.uniform(0.01, 0.3), os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        try:
            m.evaluate("RERB 1 MPH 1000 FEET FORWARD")
        except rcl.ForthError as e:
            interrupted += e.message == "Interrupted"
        timer.join()
        m.step_limit = 36_000 * 10           # 10 virtual seconds: a dead tick hangs a move
        try:
            dead += not alive(m)
        except Exception:                      # an error is a dead robot too
            dead += 1
    return interrupted, dead


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--lines", type=int, default=10_000)
    p.add_argument("--trials", type=int, default=100)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    os.chdir(tempfile.mkdtemp(prefix="rcl-fuzz-"))      # whatever a line writes
    kinds, broken, cpu = fuzz(args.lines, args.seed)
    print("fuzz: %d lines in %.1f CPU s, %d broke a check" % (args.lines, cpu, len(broken)))
    for text in broken[:10]:
        print("  broken: %s" % text)
    for kind, count in kinds.most_common(15):
        print("  %6d  %s" % (count, kind or "(ABORT)"))
    rest = sum(kinds.values()) - sum(c for _, c in kinds.most_common(15))
    print("  %6d  other errors (%d kinds)" % (rest, max(0, len(kinds) - 15)))
    interrupted, dead = ctrl_c(args.trials, args.seed)
    print("Ctrl-C: %d trials, %d interrupted mid-move, %d left a dead tick or a wrong count"
          % (args.trials, interrupted, dead))


if __name__ == "__main__":
    main()
