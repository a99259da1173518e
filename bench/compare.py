"""Compare the Forth benchmarks between two rcl trees, in CPU time.

    python3 bench/compare.py OLD_TREE NEW_TREE [--rounds N] [--only NAME]
    python3 bench/compare.py OLD_TREE NEW_TREE --board [--only mailbot]

Each round runs every program once in each tree, alternating which tree
goes first, each run in a fresh Python process (`time.process_time` around
`m.evaluate(source)` only: building the machine is not timed). Alternating
runs share the machine's load fairly between the two trees. Prints the
best and the median CPU seconds of each, their ratio, and checks that both
print the expected checksum and end on the same virtual clock.

With --board the programs are the board's (bench/mailbot.py's and
bench/board.py's): `mailbot`, the MAILBOT day from 8:00 to after the 4:30
trip, RCL loaded; `driving`, 100 simulated seconds with both wheels driven
and a Forth handler reading both 8253s every tick; `startup`, a whole
`rcl -e BYE` process (the child's CPU time from start to exit; run
`python3 -m compileall rcl` in both trees first, as pip does on install,
or both pay for compiling every module); `open`, twenty `rcl.open()` in
one process after a first (the start cache's copies, in memory). Both
trees must end with the same clock, BIOS ticks and wheel counts, and the same pose to the last bit (each board
brought up to the machine's clock first, so both are looked at at the same
instant); a pose that differs only in its last bits is reported with the
largest difference, in inches or degrees.
"""
import argparse
import json
import pathlib
import resource
import statistics
import subprocess
import sys

BENCH = pathlib.Path(__file__).resolve().parent
PROGRAMS = ['fib', 'sieve', 'loops', 'bubble']

ONE_RUN = r'''
import json, sys, time
sys.path.insert(0, sys.argv[1])
import rcl
source = open(sys.argv[2]).read()
m = rcl.Forth()
t0 = time.process_time()
out = m.evaluate(source)
t = time.process_time() - t0
print(json.dumps({"cpu": t, "out": out, "clock": m.clock}))
'''


BOARD_RUN = r'''
import json, pathlib, sys, time
sys.path.insert(0, sys.argv[1])
import rcl
if sys.argv[2] == "open":
    rcl.open()                                # the copy kept (or read from the cache file)
    t0 = time.process_time()
    for _ in range(20):
        m = rcl.open()
    t = time.process_time() - t0
    print(json.dumps({"cpu": t, "out": m.evaluate("HERE U."), "clock": m.clock,
                      "pose": m.sim.pose}))
    sys.exit(0)
if sys.argv[2] == "mailbot":
    m = rcl.open()
    m.include(str(pathlib.Path(rcl.SCREENS) / "examples" / "listing6.fs"))
    m.evaluate("8 AM TICKS!")
    run = "MAILBOT"
else:
    bench = pathlib.Path(sys.argv[1]) / "bench"
    sys.path.insert(0, str(bench))
    import board
    m = rcl.open(screens=False)
    m.evaluate(board.LAYER + board.DRIVING)
    run = "WAIT-100-S"
t0 = time.process_time()
out = m.evaluate(run)
t = time.process_time() - t0
m.sim.board.sync()
out += repr((m.sim.ticks, m.sim.bios_ticks, m.sim.wheel_counts))
print(json.dumps({"cpu": t, "out": out, "clock": m.clock, "pose": m.sim.pose}))
'''
BOARD_PROGRAMS = ['mailbot', 'driving', 'startup', 'open']


def run(tree, program, python):
    if program == 'startup':                  # the child's own CPU time, start to exit
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run([python, '-c', 'import sys; sys.path.insert(0, sys.argv[1]); '
                               'import rcl.cli; rcl.cli.main(["-e", "BYE"])', str(tree)],
                              capture_output=True, text=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        return {'cpu': cpu, 'out': proc.stdout, 'clock': proc.returncode}
    if program in BOARD_PROGRAMS:
        args = [python, '-c', BOARD_RUN, str(tree), program]
    else:
        args = [python, '-c', ONE_RUN, str(tree), str(BENCH / (program + '.fs'))]
    proc = subprocess.run(args, capture_output=True, text=True, check=True)
    return json.loads(proc.stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('old')
    ap.add_argument('new')
    ap.add_argument('--rounds', type=int, default=5)
    ap.add_argument('--only', choices=PROGRAMS + BOARD_PROGRAMS)
    ap.add_argument('--board', action='store_true', help="the board's programs")
    ap.add_argument('--python', default=sys.executable, help='the interpreter to run')
    args = ap.parse_args()
    print('| benchmark | old CPU s (best / median) | new CPU s (best / median) | speed-up |')
    print('|---|---:|---:|---:|')
    for name in [args.only] if args.only else BOARD_PROGRAMS if args.board else PROGRAMS:
        times = {args.old: [], args.new: []}
        results = {}
        for r in range(args.rounds):
            order = (args.old, args.new) if r % 2 == 0 else (args.new, args.old)
            for tree in order:
                res = run(tree, name, args.python)
                times[tree].append(res['cpu'])
                results.setdefault(tree, (res['out'], res['clock'], res.get('pose')))
        (old_out, old_clock, old_pose), (new_out, new_clock, new_pose) = results[args.old], results[args.new]
        same = (old_out, old_clock) == (new_out, new_clock)
        note = '' if same else ' (OUTPUT OR CLOCK DIFFER)'
        if same and old_pose != new_pose:
            note = ' (pose differs by up to %.1g)' % max(abs(a - b) for a, b in zip(old_pose, new_pose))
        old, new = times[args.old], times[args.new]
        print('| %s | %.2f / %.2f | %.2f / %.2f | %.2fx%s |' % (
            name, min(old), statistics.median(old), min(new), statistics.median(new),
            statistics.median(old) / statistics.median(new), note))


if __name__ == '__main__':
    sys.exit(main())
