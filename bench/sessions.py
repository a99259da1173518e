"""Sessions on a board that stays powered: N runs of `rcl --port` one after
another on one running board, each the user's first command and BYE, as a
user who connects, drives and leaves would. A session fails when rcl exits
with an error or reads counts more than 1 away from the first session's
(the wheel stands somewhere within a count where the last move left it).

    python3 bench/sessions.py [-n 20] [--boards tcp,pty,free,native,uno]
                              [--native PROGRAM] [--uno IMAGE.elf]

tcp, pty: rcl-board (lockstep) behind TCP or a pty; free: rcl-board
--free-running behind TCP; native: firmware/build/native; uno: the Uno
image under firmware/simavr's rcl-simavr. `make -C firmware native uno
simavr` builds the last two. The rcl run is the one on PYTHONPATH.
"""
import argparse
import os
import pathlib
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
COMMAND = "RERB 1 INCHES FORWARD 300 MS ?CNT1 D. ?CNT2 D. BYE"


def start_board(kind, native, uno):
    """-> (process, the --port argument)."""
    py = [sys.executable, "-m", "rcl.hw.boardcli"]
    argv = {"tcp": py + ["--tcp", "127.0.0.1:0"], "pty": py + ["--pty"],
            "free": py + ["--tcp", "127.0.0.1:0", "--free-running"],
            "native": [str(native)],
            "uno": [str(ROOT / "firmware/simavr/build/rcl-simavr"), "--quiet", str(uno)]}[kind]
    proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL, text=True)
    line = proc.stdout.readline().strip()
    where = "socket://" + line.rsplit(" ", 1)[1] if line.startswith("listening") else line
    return proc, where


def session(where):
    run = subprocess.run([sys.executable, "-m", "rcl", "--port", where, "-e", COMMAND],
                         stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=120)
    return run.returncode, run.stdout.split()[-2:], run.stderr.strip().splitlines()[-1:]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("-n", type=int, default=20)
    p.add_argument("--boards", default="tcp,pty,free,native,uno")
    p.add_argument("--native", default=ROOT / "firmware/build/native")
    p.add_argument("--uno", default=ROOT / "firmware/build/uno.elf")
    args = p.parse_args()
    print("load %.1f; %d sessions of: rcl --port P -e %r" % (os.getloadavg()[0], args.n, COMMAND))
    for kind in args.boards.split(","):
        proc, where = start_board(kind, args.native, args.uno)
        first, failed, why, within = None, 0, {}, [0]
        t0 = time.monotonic()
        try:
            for _ in range(args.n):
                rc, got, err = session(where)
                first = first if first is not None else (got if rc == 0 else None)
                off = rc == 0 and first is not None and max(
                    abs(int(a) - int(b)) for a, b in zip(got, first))
                if rc != 0 or off > 1:          # (1: the count a wheel stood in)
                    failed += 1
                    key = err[0][:100] if rc and err else "counts %s, first %s" % (got, first)
                    why[key] = why.get(key, 0) + 1
                elif off:
                    within[0] += 1
        finally:
            proc.terminate()
            proc.wait(10)
        print("%-6s tried %d failed %d  (first counts %s; %d within 1 of them; %.0f s)" % (
            kind, args.n, failed, first, within[0], time.monotonic() - t0))
        for text, n in why.items():
            print("         %2d x %s" % (n, text))


if __name__ == "__main__":
    main()
