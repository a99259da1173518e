"""Where the board programs' CPU time goes, by sampling (not cProfile).

    python3 bench/sample.py mailbot      # or: driving

cProfile charges every Python call an overhead of its own, which inflates
the board's many small calls several times over. This samples instead: a
SIGPROF every 0.5 ms of CPU time, and at each the Python stack is counted,
every function on it once ("inclusive": the share of the run spent in it
or in what it called) and the innermost one ("self"). The programs are
compare.py's: `mailbot` is the MAILBOT day from 8:00, `driving` 100
simulated seconds of bench/board.py's case (a). Unix only (SIGPROF).
"""
import collections
import pathlib
import signal
import sys

BENCH = pathlib.Path(__file__).resolve().parent
sys.path[:0] = [str(BENCH), str(BENCH.parent)]
import rcl  # noqa: E402

INTERVAL = 0.0005                       # CPU seconds between samples


def machine(program):
    """A machine ready to run `program`, and the line that runs it."""
    if program == "mailbot":
        m = rcl.open()
        m.include(str(pathlib.Path(rcl.SCREENS) / "examples" / "listing6.fs"))
        m.evaluate("8 AM TICKS!")
        return m, "MAILBOT"
    import board
    m = rcl.open(screens=False)
    m.evaluate(board.LAYER + board.DRIVING)
    return m, "WAIT-100-S"


def sample(m, line):
    """Run line on m under the sampler; -> (samples, inclusive, self) counts."""
    inclusive, innermost, total = collections.Counter(), collections.Counter(), [0]

    def take(signum, frame):
        total[0] += 1
        seen = set()
        innermost[name(frame.f_code)] += 1
        while frame is not None:
            seen.add(name(frame.f_code))
            frame = frame.f_back
        inclusive.update(seen)

    signal.signal(signal.SIGPROF, take)
    signal.setitimer(signal.ITIMER_PROF, INTERVAL, INTERVAL)
    try:
        m.evaluate(line)
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0, 0)
    return total[0], inclusive, innermost


def name(code):
    return "%s:%s" % (pathlib.Path(code.co_filename).name, code.co_name)


def main():
    program = sys.argv[1] if len(sys.argv) > 1 else "mailbot"
    n, inclusive, innermost = sample(*machine(program))
    print("%d samples of %.1f ms CPU" % (n, INTERVAL * 1000))
    for title, counts, rows in (("inclusive", inclusive, 40), ("self", innermost, 25)):
        print("--- " + title)
        for key, k in counts.most_common(rows):
            print("%5.1f %%  %s" % (100 * k / n, key))


if __name__ == "__main__":
    main()
