"""How soon the served board opens its relays when its host goes: after a
cut (the line goes silent: the watchdog's 250 ms) and after a close (a TCP
connection closed, a pty hung up: at once), over TCP and a pty.

    python3 bench/relays_off.py [--runs 10]

rcl-board's BoardServer serves a socket pair or a pty in a thread of this
process; a client here says HELLO, switches both motors on, then goes
silent (after its last frame) or closes its end. The figure is the wall
time from its last frame (a cut) or the close to the moment this process
sees the MOTOR latch at 0, polled every 0.5 ms (so it works on any version
of the board: a copy of this file outside the tree, with PYTHONPATH set to
another tree, measures that one's; a board that does not see a TCP close
shows the 5 s this waits, where rcl-board's own loop would trip its
watchdog at 250 ms).
"""
import argparse
import os
import pathlib
import socket
import statistics
import sys
import threading
import time
import tty

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent))
from rcl.hw import protocol as P  # noqa: E402
from rcl.hw.server import BoardServer  # noqa: E402


def one(transport, how):
    """-> milliseconds from the cut or close to relays off."""
    server = BoardServer()
    done = threading.Event()
    if transport == "tcp":
        ours, theirs = socket.socketpair()
        board_fd, send, close = theirs.fileno(), ours.sendall, ours.close
    else:
        master, slave = os.openpty()
        tty.setraw(slave)
        path = os.ttyname(slave)
        os.close(slave)
        board_fd = master
        client = os.open(path, os.O_RDWR | os.O_NOCTTY)
        send, close = (lambda data: os.write(client, data)), (lambda: os.close(client))
    thread = threading.Thread(target=server.serve_fd, args=(board_fd, done.is_set), daemon=True)
    thread.start()
    send(P.frame(0, "HELLO", version=P.VERSION) + P.frame(1, "OUT8", port=0x88, value=0x35))
    end = time.monotonic() + 5
    while server.board.motor_latch != 0x35 and time.monotonic() < end:
        time.sleep(0.001)
    for _ in range(5):                                 # a live host: PINGs for 50 ms
        time.sleep(0.01)
        send(P.frame(0, "PING"))
        t0 = time.monotonic()
    if how == "close":
        close()
        t0 = time.monotonic()
    while server.board.motor_latch and time.monotonic() < t0 + 5:
        time.sleep(0.0005)
    ms = (time.monotonic() - t0) * 1000
    done.set()
    thread.join(2)
    if how == "cut":
        close()
    if transport == "pty":
        os.close(master)
    return ms


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--runs", type=int, default=10)
    args = p.parse_args()
    print("load %.1f; relays off after the host goes, ms (%d runs each)"
          % (os.getloadavg()[0], args.runs))
    for transport in ("tcp", "pty"):
        for how in ("cut", "close"):
            ms = [one(transport, how) for _ in range(args.runs)]
            print("%-3s %-5s min %6.1f  median %6.1f  max %6.1f   %s" % (
                transport, how, min(ms), statistics.median(ms), max(ms),
                " ".join("%.0f" % x for x in ms)))


if __name__ == "__main__":
    main()
