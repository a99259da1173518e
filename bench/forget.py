"""What forgetting costs: a line `HOT MK MARKER MK` (run a hot word,
forget back to a marker, set the marker again) against `HOT` alone, in
CPU time, for one or two rcl trees side by side (each round runs every
tree once, in a fresh process, alternating which goes first).

    python3 bench/forget.py TREE [TREE2] [--rounds N] [--full]

--full loads RCL first (rcl.open()): its name tables are larger. The ratio
is the point: HOT alone is the unit.
"""
import argparse
import json
import statistics
import subprocess
import sys

ONE_RUN = r'''
import json, sys, time
sys.path.insert(0, sys.argv[1])
import rcl
m = rcl.open() if sys.argv[2] == "full" else rcl.Forth()
m.evaluate(": SQ DUP * ;  : HOT  0 100 0 DO I SQ + LOOP DROP ;  MARKER MK")


def per_line(line, n=200):
    m.evaluate(line)
    t0 = time.process_time()
    for _ in range(n):
        m.evaluate(line)
    return (time.process_time() - t0) / n


hot = per_line("HOT")
print(json.dumps({"hot": hot, "forget": per_line("HOT MK MARKER MK")}))
'''


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("trees", nargs="+")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--full", action="store_true", help="RCL loaded")
    args = ap.parse_args()
    ratios = {t: [] for t in args.trees}
    for r in range(args.rounds):
        order = args.trees if r % 2 == 0 else args.trees[::-1]
        for tree in order:
            out = subprocess.run([sys.executable, "-c", ONE_RUN, tree,
                                  "full" if args.full else "bare"],
                                 capture_output=True, text=True, check=True).stdout
            d = json.loads(out)
            ratios[tree].append(d["forget"] / d["hot"])
    print("| tree | `HOT MK MARKER MK` / `HOT` (median of %d) |" % args.rounds)
    print("|---|---:|")
    for tree in args.trees:
        print("| %s | %.1fx |" % (tree, statistics.median(ratios[tree])))


if __name__ == "__main__":
    main()
