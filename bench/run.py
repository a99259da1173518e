"""Time the Forth benchmarks on rcl and on gforth, and check their checksums.

    python3 bench/run.py [--only NAME] [--repeat K] [--acmeforth DIR]

What is measured, for each bench/*.fs program (best time of K runs,
default 3):

* rcl: in-process, a fresh `rcl.Forth()` per run; only `m.evaluate(source)`
  is timed, in CPU time (building the machine is not). To compare two
  trees (before and after a change), use bench/compare.py: alternating
  runs, each in a fresh process.  The machine's virtual clock after
  the run (`m.seconds`, the time the program would take on the 1986 board)
  is shown as well when the machine has one.
* gforth: `gforth FILE -e bye` as a subprocess, minus gforth's own start-up
  time (`gforth -e bye`, also best of K), so both columns are the time spent
  running the program.
* acmeforth (with --acmeforth DIR, a checkout of the Python Forth
  jkotlinski/acmeforth, whose `acmeforth` script interprets Forth files on
  the host): `python3 DIR/acmeforth FILE` as a subprocess, the child's CPU
  time, minus the same for an empty file (its own start-up), best of K.

Each program prints `CHECKSUM n`; both systems must print the number in
bench/expected.txt (gforth runs on 64-bit cells, rcl on 16-bit cells; the
programs are written so the result is the same on both).

Reading the table: "ratio" = rcl time / gforth time (how many times slower
rcl is than gforth).  "Mwords/s" = the primitives rcl executed (every cell of
threaded code run, counted exactly by its virtual clock: clock / cost of one
primitive, all costs being the default here) / rcl time.  The target
is rcl >= 6 M words/s (5x a plain Python Forth at ~1.2 M words/s), which is
roughly a ratio of 50-125 against gforth 0.7.3 on these programs.
"""
import argparse
import pathlib
import re
import resource
import shutil
import subprocess
import sys
import time

BENCH = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(BENCH.parent))      # the rcl in this tree, not installed
PROGRAMS = ['fib', 'sieve', 'loops', 'bubble']
TARGET_MWORDS = 6.0


def checksum(output):
    """The number after CHECKSUM in a program's output, or None."""
    m = re.search(r'CHECKSUM\s+(-?\d+)', output)
    return int(m.group(1)) if m else None


def best_of(k, run, clock=time.perf_counter):
    """Run `run()` k times; return (best seconds by `clock`, result of the
    last run)."""
    best, result = float('inf'), None
    for _ in range(k):
        t0 = clock()
        result = run()
        best = min(best, clock() - t0)
    return best, result


def time_rcl(source, k):
    """(seconds, checksum, virtual seconds, primitives executed) or raise."""
    import rcl
    from rcl.forth.primitives import DEFAULT_COST
    best, out = float('inf'), ''
    for _ in range(k):
        m = rcl.Forth()
        start = m.clock
        t0 = time.process_time()
        out = m.evaluate(source)
        best = min(best, time.process_time() - t0)
    return best, checksum(out), m.seconds, (m.clock - start) // DEFAULT_COST


def time_gforth(path, k, startup):
    cmd = ['gforth', str(path), '-e', 'bye']
    run = lambda: subprocess.run(cmd, capture_output=True, text=True,
                                 timeout=300)
    best, proc = best_of(k, run)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr.strip().splitlines()[-1:] or
                           f'exit {proc.returncode}')
    return max(best - startup, 1e-6), checksum(proc.stdout)


def child_cpu(cmd):
    """Run cmd; -> (its CPU seconds, user + system, CompletedProcess)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return cpu, proc


def time_acmeforth(acme, path, k, startup):
    """(CPU seconds less start-up, checksum): the best of k runs."""
    runs = [child_cpu([sys.executable, str(acme / 'acmeforth'), str(path)])
            for _ in range(k)]
    return max(min(cpu for cpu, _ in runs) - startup, 1e-6), checksum(runs[-1][1].stdout)


def acmeforth_startup(acme, k):
    empty = BENCH / 'results' / 'empty.fs'
    empty.parent.mkdir(exist_ok=True)
    empty.write_text('')
    return min(child_cpu([sys.executable, str(acme / 'acmeforth'), str(empty)])[0]
               for _ in range(k))


def ok(got, want):
    return 'n/a' if got is None and want is None else (
        'yes' if got == want else f'NO ({got})')


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--only', choices=PROGRAMS, help='run one program')
    ap.add_argument('--repeat', type=int, default=3, metavar='K',
                    help='best of K runs (default 3)')
    ap.add_argument('--acmeforth', type=pathlib.Path, metavar='DIR',
                    help='also time the Python Forth acmeforth checked out in DIR')
    args = ap.parse_args()

    expected = dict(line.split() for line in
                    (BENCH / 'expected.txt').read_text().splitlines()
                    if line.strip())
    gforth = shutil.which('gforth')
    startup = 0.0
    if gforth:
        startup, _ = best_of(args.repeat, lambda: subprocess.run(
            ['gforth', '-e', 'bye'], capture_output=True))

    acme = args.acmeforth
    acme_startup = acmeforth_startup(acme, args.repeat) if acme else 0.0

    print('| benchmark | rcl s | gforth s | ratio rcl/gforth | rcl Mwords/s '
          '| rcl virtual s | checksum ok (rcl / gforth) |'
          + (' acmeforth s | acmeforth/rcl | acmeforth ok |' if acme else ''))
    print('|---|---:|---:|---:|---:|---:|---|' + ('---:|---:|---|' if acme else ''))
    for name in [args.only] if args.only else PROGRAMS:
        path = BENCH / f'{name}.fs'
        source = path.read_text()
        want = int(expected[path.name])

        try:
            rcl_s, rcl_sum, virtual, words = time_rcl(source, args.repeat)
            rcl_col, rcl_ok = f'{rcl_s:.2f}', ok(rcl_sum, want)
            mwords = f'{words / rcl_s / 1e6:.2f}'
            virt = '-' if virtual is None else f'{virtual:.1f}'
        except Exception as e:                     # rcl missing or failing
            rcl_s, rcl_ok, mwords, virt = None, 'n/a', '-', '-'
            rcl_col = f'error: {type(e).__name__}: {e}'.replace('|', '/')

        if gforth:
            try:
                g_s, g_sum = time_gforth(path, args.repeat, startup)
                g_col, g_ok = f'{g_s:.3f}', ok(g_sum, want)
            except Exception as e:
                g_s, g_ok, g_col = None, 'n/a', f'error: {e}'
        else:
            g_s, g_ok, g_col = None, 'n/a', 'not installed'

        ratio = f'{rcl_s / g_s:.0f}x' if rcl_s and g_s else '-'
        row = (f'| {name} | {rcl_col} | {g_col} | {ratio} | {mwords} | {virt} '
               f'| {rcl_ok} / {g_ok} |')
        if acme:
            a_s, a_sum = time_acmeforth(acme, path, args.repeat, acme_startup)
            speedup = f'{a_s / rcl_s:.1f}x' if rcl_s else '-'
            row += f' {a_s:.2f} | {speedup} | {ok(a_sum, want)} |'
        print(row)

    print(f'\nwords: primitives executed, counted by rcl\'s virtual clock; '
          f'target >= {TARGET_MWORDS:g} M words/s.')
    if gforth:
        print(f'gforth start-up ({startup * 1000:.1f} ms) subtracted from the '
              f'gforth times.')
    if acme:
        print(f'acmeforth start-up ({acme_startup * 1000:.0f} ms of CPU) subtracted '
              f'from the acmeforth times.')


if __name__ == '__main__':
    sys.exit(main())
