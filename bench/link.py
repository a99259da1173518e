"""Figures of the link (docs/performance.md, The link): bytes per tick each
way, ticks late or missed, and the host's CPU share, while both wheels move.

    python3 bench/link.py [--seconds 600]

rcl-board --pty --free-running serves the simulated board in real time
(as a real board runs: it never waits for the host), in its own process;
this process is the host, driving it through pyserial as `rcl --port` does.
The move: laps of 3 feet forward and back at 25.5 in/s, for --seconds.

Figures:
  bytes per tick, host to board and board to host, against a 115200-baud
      line's 115 bytes per 10 ms (target: at most a quarter, 28.8);
  ticks late: handled by the host more than 2 ms after the TICK came,
      and ticks the host never ran (target 0), and the board's own ticks
      serviced more than 2 ms late;
  host CPU: this process's CPU time over the wall time of the move.
"""
import argparse
import json
import pathlib
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
import rcl  # noqa: E402


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--seconds", type=float, default=30.0)
    args = p.parse_args()
    report = pathlib.Path(tempfile.mkdtemp()) / "board.json"
    board = subprocess.Popen([sys.executable, "-m", "rcl.hw.boardcli", "--pty",
                              "--free-running", "--report", str(report)],
                             stdout=subprocess.PIPE, text=True)
    try:
        pty = board.stdout.readline().strip()
        m = rcl.open(port=pty)
        link = m.board
        laps = max(1, round(args.seconds / 3.2))
        m.evaluate(": LAPS  0 DO  3 FEET FORWARD  3 FEET BACKWARD  LOOP ;  RERB 25.5 IPS")
        out0, in0, ticks0, late0 = link.bytes_out, link.bytes_in, link.ticks, link.late
        wall0, cpu0 = time.monotonic(), time.process_time()
        m.evaluate("%d LAPS" % laps)
        wall, cpu = time.monotonic() - wall0, time.process_time() - cpu0
        ticks = link.ticks - ticks0
        print("moved %.1f s, %d ticks run, %d skipped" % (wall, ticks, link.skipped))
        print("bytes per tick: host->board %.1f, board->host %.1f (a quarter of 115200 "
              "baud: 28.8)" % ((link.bytes_out - out0) / ticks, (link.bytes_in - in0) / ticks))
        print("ticks run more than 2 ms after they came: %d" % (link.late - late0))
        print("host CPU: %.0f %% of one core" % (100 * cpu / wall))
        link.close()
    finally:
        board.terminate()
        board.wait(10)
    data = json.loads(report.read_text())
    print("board: %d ticks serviced more than 2 ms late (%s), watchdog %d" % (
        data["stats"]["late"], ", ".join("%.1f ms" % x for x in data["late_ms"][:5]),
        data["stats"]["watchdog"]))


if __name__ == "__main__":
    main()
