"""rcl-board: the simulated R-E Robot board, paced to the wall clock,
serving the frame protocol behind a pseudo-terminal or a TCP port, so that
`rcl --port` drives it exactly as it would drive a real board.

    rcl-board --pty                   prints the device path, e.g. /dev/pts/7
    rcl-board --tcp 127.0.0.1:7000    prints "listening on 127.0.0.1:7000"
    rcl-board --tcp 127.0.0.1:0       any free port (the line names it)

--rate R runs board time R times the wall clock; --free-running never
holds board time for the host (see rcl.hw.server). Fault options:
--corrupt RATE (flip a bit in that fraction of the bytes,
both directions), --cut-at S --cut-for S (the link goes silent at board
time S, for S seconds or for good; on TCP the connection is closed and
new ones wait until the cut ends), --stall left|right, --speak-version N
(answer HELLO with another protocol version). --report FILE writes, at
exit, a JSON of the board's wheel counts, pose, counters and port log.
SIGTERM or SIGINT stops it (exit 0). It serves one host at a time: over
TCP another is refused `busy` unless the one served has been silent for
the watchdog's 250 ms (docs/protocol.md, section 6).
"""
import argparse
import json
import os
import select
import signal
import socket
import sys
import time
import tty

from rcl.hw import protocol as P
from rcl.hw.server import BoardServer
from rcl.sim.observe import Sim
from rcl.status import heading_text, tenths


def parse_args(argv):
    p = argparse.ArgumentParser(prog="rcl-board", description=__doc__.split("\n\n")[0])
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--pty", action="store_true", help="serve on a new pseudo-terminal")
    where.add_argument("--tcp", metavar="HOST:PORT", help="serve on a TCP port")
    p.add_argument("--allow-remote", action="store_true",
                   help="let --tcp listen on an address other than loopback")
    p.add_argument("--corrupt", type=float, default=0.0, metavar="RATE",
                   help="flip a bit in this fraction of the bytes, both directions "
                        "(0.02 is 2 %%; default 0)")
    p.add_argument("--seed", type=int, default=1,
                   help="seed of --corrupt's choices, for a repeatable run (default 1)")
    p.add_argument("--cut-at", type=float, metavar="S",
                   help="the link goes silent at board time S seconds (on TCP the "
                        "connection closes and new ones wait until the cut ends)")
    p.add_argument("--cut-for", type=float, metavar="S",
                   help="the cut of --cut-at lasts S seconds (default: for good)")
    p.add_argument("--stall", choices=("left", "right"),
                   help="that wheel is stalled from the start: its motor turns no more")
    p.add_argument("--speak-version", type=int, default=P.VERSION, metavar="N",
                   help="answer HELLO with protocol version N (default %d)" % P.VERSION)
    p.add_argument("--rate", type=float, default=1.0, metavar="R",
                   help="board time runs R times the wall clock (default 1)")
    p.add_argument("--free-running", action="store_true",
                   help="never wait for the host's TICK_DONE (as a real board)")
    p.add_argument("--report", metavar="FILE.json",
                   help="at exit, write the wheel counts, pose, counters and port log "
                        "as JSON")
    p.add_argument("--status", action="store_true",
                   help="a status line on stderr (the default on a terminal)")
    return p.parse_args(argv)


def tcp_address(text, allow_remote):
    host, _, port = text.rpartition(":")
    host = host.strip("[]") or "127.0.0.1"
    if not port.isdigit():
        raise SystemExit("rcl-board: --tcp wants HOST:PORT, not %r" % text)
    if not allow_remote and host not in ("127.0.0.1", "localhost", "::1"):
        raise SystemExit("rcl-board: %s is not loopback; --allow-remote lets it listen there"
                         % host)
    return host, int(port)


class Status:
    """The status line: ticks, pose, link state, twice a second."""

    def __init__(self, server, show):
        self.server, self.show, self.next = server, show, 0.0

    def __call__(self, link):
        if not self.show or time.monotonic() < self.next:
            return
        self.next = time.monotonic() + 0.5
        s, sim = self.server, Sim(self.server.board)
        x, y, h = sim.pose
        sys.stderr.write("\rticks %d  pose %s in %s in %s deg  link %s  watchdog %d  "
                         % (s.board.ticks, tenths(x), tenths(y), heading_text(h), link,
                            s.stats["watchdog"]))
        sys.stderr.flush()


def serve_pty(server, stop, status):
    master, slave = os.openpty()
    tty.setraw(slave)                 # (kept while the master is open)
    print(os.ttyname(slave), flush=True)
    os.close(slave)                   # so that a host's hang-up reads EIO at once
    while not stop():
        server.serve_fd(master, lambda: stop() or status("pty") or False)


BUSY = "busy: another host is connected"
REFUSED = P.frame(0, "REFUSED", ack=0, reason=BUSY)


def serve_tcp(server, address, stop, status):
    """One host at a time. Another that connects meanwhile is refused
    (REFUSED with SEQ 0, BUSY, then the connection closed), unless the
    one served has sent nothing for the watchdog's 250 ms: that one is
    dropped and the newcomer served."""
    family = socket.AF_INET6 if ":" in address[0] else socket.AF_INET
    listener = socket.socket(family, socket.SOCK_STREAM)
    listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    listener.bind(address)
    listener.listen(4)
    print("listening on %s:%d" % listener.getsockname()[:2], flush=True)
    conn = None
    while not stop():
        if conn is None:
            status("waiting")
            server.run_until(server.clock.now())
            server.watchdog(time.monotonic())
            server.take_output()                  # nobody to hear it
            if server.cut() or not select.select([listener], [], [], 0.005)[0]:
                continue
            conn = accept(listener)
        served = Served(conn)
        newcomer = []
        server.serve_fd(conn.fileno(), lambda: stop() or status("connected")
                        or served.replaced_by(listener, server, newcomer), on_idle="close")
        if newcomer:
            server.hang_up()                      # the silent host is dropped
        for sock, _, _ in served.refused:
            sock.close()
        conn.close()
        conn = newcomer[0] if newcomer else None
    listener.close()


def accept(listener):
    conn, _ = listener.accept()
    conn.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return conn


class Served:
    """The connection being served, and what to do with another."""

    LINGER = 3.0          # seconds a refused connection is heard before it is closed

    def __init__(self, conn):
        self.conn, self.since = conn, time.monotonic()
        self.refused = []          # (socket, when to close it, its FrameReader)

    def replaced_by(self, listener, server, newcomer):
        """True when a new connection should take this one's place (put in
        newcomer); a newcomer refused is told why, then closed a little
        later (closed with its HELLO unread, it could get a reset instead
        of the reason)."""
        self.linger()
        if not select.select([listener], [], [], 0)[0]:
            return False
        if select.select([self.conn], [], [], 0)[0] and not self.gone():
            return False                  # what the host served sent, read first
        other = accept(listener)
        heard = max(self.since, server.last_valid or 0.0)
        if self.gone() or time.monotonic() - heard > P.WATCHDOG_MS / 1000:
            newcomer.append(other)
            return True
        try:
            other.sendall(REFUSED)
            other.setblocking(False)
        except OSError:
            pass
        reader = P.FrameReader(P.received_by(P.BOARD))
        self.refused.append((other, time.monotonic() + self.LINGER, reader))
        return False

    def gone(self):
        """The host served has closed its end (its EOF not read yet)."""
        try:
            return self.conn.recv(1, socket.MSG_PEEK | socket.MSG_DONTWAIT) == b""
        except (BlockingIOError, InterruptedError):
            return False
        except OSError:
            return True

    def linger(self):
        keep = []
        for sock, until, reader in self.refused:
            try:
                while True:
                    data = sock.recv(4096)
                    if not data:
                        break
                    # each HELLO gets the refusal again: a host's port may
                    # drop what came before it looked (pyserial's socket://
                    # empties its input as it opens)
                    if any(f.name == "HELLO" for f in reader.feed(data, time.monotonic())):
                        sock.sendall(REFUSED)
                gone = True                 # the newcomer closed its end
            except (BlockingIOError, InterruptedError):
                gone = False
            except OSError:
                gone = True
            if gone or time.monotonic() > until:
                sock.close()
            else:
                keep.append((sock, until, reader))
        self.refused = keep


def report(server, path):
    sim = Sim(server.board)
    log = {}
    for _, port, value in server.board.port_log:
        log.setdefault("%d" % port, []).append(value)
    data = {"wheel_counts": sim.wheel_counts, "pose": sim.pose, "ticks": server.board.ticks,
            "relays": sim.relays, "stats": server.stats, "port_writes": log,
            "rejected_frames": server.reader.bad,
            # board times (CLOCK_HZ units) of the watchdog's trip and of the
            # host's last good frame: a trip after that frame came after the host left
            "watchdog_at": server.watchdog_at, "last_host_frame_at": server.last_valid_clock,
            "late_ms": [round(x * 1000, 3) for x in server.lateness if x > 0.002]}
    with open(path, "w") as f:
        json.dump(data, f)


def main(argv=None):
    args = parse_args(argv)
    address = tcp_address(args.tcp, args.allow_remote) if args.tcp else None
    server = BoardServer(corrupt=args.corrupt, seed=args.seed, cut_at=args.cut_at,
                         cut_for=args.cut_for, version=args.speak_version,
                         lockstep=not args.free_running, rate=args.rate)
    if args.stall:
        Sim(server.board).stall(args.stall)
    stopping = []
    for name in ("SIGTERM", "SIGINT"):
        signal.signal(getattr(signal, name), lambda *a: stopping.append(True))
    status = Status(server, args.status or sys.stderr.isatty())
    try:
        if args.pty:
            serve_pty(server, lambda: bool(stopping), status)
        else:
            serve_tcp(server, address, lambda: bool(stopping), status)
    except OSError as e:
        sys.stderr.write("rcl-board: %s\n" % e)
        return 1
    finally:
        if args.report:
            report(server, args.report)
    return 0


if __name__ == "__main__":
    sys.exit(main())
