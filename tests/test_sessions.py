"""Sessions on a board that stays powered (docs/protocol.md, "Sessions"):
HELLO puts every board the project ships as at power-on before the host
hears IDENTIFY, so a host never runs what it did not install; a host that
goes (BYE, a closed connection, a pty hung up, silence) leaves the board
safe and quiet. The boards: rcl-board behind TCP and a pty, the native
firmware (firmware/build/native) and the Uno image under simavr.

Each session is a host of its own on one running board: RCL from a saved
image (as `rcl --image` starts; the board side is the same INSTALL as the
screens' load ends with), the first command, the wheels at rest, RCL's
counters read, the link closed as rcl leaves. A board reset to its
power-on state drives the same first move, but for one thing a reset
cannot undo: the robot stands where the last move left it, each wheel
somewhere within an encoder count, so a move's count may come out 1
higher or lower (the simulated board's wheel keeps its fraction of a
count, the motor model its quadrature edges). Without the reset the
sessions failed outright or read the last host's counts on top (29, 59,
89, ...).
Waits are bounded generously (a loaded machine) and assert nothing of the
wall clock. Each kind of board is started once for the module and every
test holds its own sessions on it, as on a robot left switched on: 20
sessions a board under CI, 5 otherwise (bench/sessions.py runs any
number, as `rcl --port` runs).
"""
import os
import random
import select
import socket
import subprocess
import sys
import threading
import time
import tty

import pytest

import rcl
from rcl.hw import protocol as P
from firmware_support import (UNO_PATIENCE, BoardProcess, harness_built, native_program,
                              uno_image)
from starved import TIME_RAN_OUT, Starved
from suite_size import scaled

SESSIONS = scaled(20, 5)
FIRST = "RERB 1 INCHES FORWARD"
READ = " 300 MS ?CNT1 D. ?CNT2 D."           # the wheels at rest, then RCL's counters


# ------------------------------------------------------------------ boards
class RclBoard:
    """rcl-board in its own process; `where` is what rcl's --port takes."""

    def __init__(self, *args):
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "rcl.hw.boardcli", *args], stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        line = self.proc.stdout.readline().strip()
        self.tcp = line.startswith("listening")
        self.address = line.rsplit(" ", 1)[1] if self.tcp else line
        self.where = "socket://" + self.address if self.tcp else line

    def raw(self):
        """A byte stream to the board, as a client of its own."""
        if self.tcp:
            host, port = self.address.rsplit(":", 1)
            return Raw(socket.create_connection((host, int(port)), timeout=10))
        return Raw(os.open(self.where, os.O_RDWR | os.O_NOCTTY))

    def close(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(10)


class Process(BoardProcess):
    """A firmware board: the native build or rcl-simavr (a pty each)."""

    def raw(self):
        return Raw(os.open(self.path, os.O_RDWR | os.O_NOCTTY))

    @property
    def where(self):
        return self.path


def start_board(kind):
    if kind == "tcp":
        return RclBoard("--tcp", "127.0.0.1:0", "--rate", "4")
    if kind == "pty":
        return RclBoard("--pty", "--rate", "4")
    if kind == "free":
        return RclBoard("--tcp", "127.0.0.1:0", "--free-running")
    if kind == "native":
        # real time: its watchdog counts board time, and at --rate 4 an idle
        # host's PING (every 100 ms) comes after 400 ms of it, too late
        return Process([native_program(), "--rate", "1"]).__enter__()
    if kind == "native-fast":
        return Process([native_program(), "--rate", "4"]).__enter__()
    return Process([harness_built(), "--quiet", uno_image()]).__enter__()


@pytest.fixture(scope="module")
def running():
    """-> get(kind): the module's board of that kind, started at its first
    use (again if it has died) and left running between tests."""
    boards = {}

    def get(kind):
        if kind not in boards or boards[kind].proc.poll() is not None:
            boards[kind] = start_board(kind)
        return boards[kind]
    yield get
    for b in boards.values():
        b.close()


@pytest.fixture
def board():
    started = []

    def start(kind):
        started.append(start_board(kind))
        return started[-1]
    yield start
    for b in started:
        b.close()


@pytest.fixture(scope="module")
def image(tmp_path_factory):
    """RCL saved once: each session starts from it in a fraction of a second."""
    from rcl.forth import image as images
    path = tmp_path_factory.mktemp("sessions") / "rcl.img"
    images.save(rcl.open(), str(path))
    return str(path)


STALLS_ALLOWED = 2                   # a session's, in a row


def session(where, image, command=FIRST):
    """One host: connect, the command, the counts at rest, leave; -> counts.
    A session that rcl ended with its verdict that time ran out (TIME_RAN_OUT:
    ` Host too slow `, this process not scheduled for 250 ms, or ` Link
    lost `, the board or we unheard for 250 ms, as on a machine with CPU
    hogs beside it) is a session the board rightly ended, motors off: the
    next host starts one again, as a user would, once the wheels stand
    still, and its counts are asserted as any session's. A third in a row
    raises Starved: the whole test runs again (conftest.py)."""
    for attempt in range(STALLS_ALLOWED + 1):
        m = rcl.open(port=where, image=image)
        try:
            left, right = (int(x) for x in m.evaluate(command + READ).split())
            return Counts(left, right, m.board.slowest_answer)
        except rcl.ForthError as e:   # say what the link saw (a loaded machine: Link lost)
            told = "%s; %s" % (e.message, m.board.status())
            if e.code not in TIME_RAN_OUT:
                e.message = told                  # the error itself, its code kept
                raise
            if attempt == STALLS_ALLOWED:
                # starved session after starved session: the test runs again
                raise Starved(told) from None
            print("\nsession again after: %s" % told)
        finally:
            m.board.close()
        at_rest(where, image)


def at_rest(where, image, sessions=10):
    """After a session its board's watchdog stopped mid-move, the wheels
    coast on a while (a session started at once read 35 and 36 counts for
    29); -> when one reads them still for 300 ms (up to `sessions`)."""
    for _ in range(sessions):
        m = rcl.open(port=where, image=image)
        try:
            if m.evaluate(READ).split() == ["0", "0"]:
                return
        except rcl.ForthError:
            pass
        finally:
            m.board.close()


class Counts(tuple):
    """A session's (left, right) counts, and its host's slowest answer to
    a tick (s): past the board's patience, the wheels ran on meanwhile."""
    def __new__(cls, left, right, slowest):
        counts = super().__new__(cls, (left, right))
        counts.slowest = slowest
        return counts


# How long each board waits for a host late with a tick's answer before it
# runs on: rcl-board holds its time (lockstep), the native board up to 1 s,
# the Uno harness UNO_PATIENCE (firmware_support.py).
PATIENCE = {"tcp": float("inf"), "pty": float("inf"), "native": 1.0, "uno": UNO_PATIENCE}


def same_move(kind, counts, reference, slack=1):
    """Assert the same move from rest (within_a_count)."""
    if not within_a_count(counts, reference, slack):
        off(kind, "%s then %s" % (reference, counts), max(counts.slowest, reference.slowest))


def one_inch(kind, counts):
    """Assert the first command's inch: 28.4 counts and the run-out, 29
    within 2 on each wheel."""
    if not all(abs(c - 29) <= 2 for c in counts):
        off(kind, "%s for 29 within 2" % (counts,), counts.slowest)


def off(kind, told, slowest):
    """Counts were off. After a host answered later than the board waits
    (this process not run, beside CPU hogs) that is the machine's doing:
    Starved, run again; else the assertion fails."""
    if slowest > PATIENCE[kind]:
        raise Starved("%s: a tick answered after %d ms, past the %s board's %d ms"
                      % (told, slowest * 1000, kind, PATIENCE[kind] * 1000))
    raise AssertionError("%s (the slowest answer %.1f ms)" % (told, slowest * 1000))


def within_a_count(counts, first, slack=1):
    """The same move from rest: each wheel within the count it stood in
    (slack 2 on a board in real time: the host's speed writes may land a
    tick's fraction late, as test_firmware_simavr's 1160 +- 2 allows).
    A session that ran what the last one left reads 30 counts on."""
    return all(abs(a - b) <= slack for a, b in zip(counts, first))


# ------------------------------------------------------------------- raw
class Raw:
    """Frames to and from a board over a pty or a socket, no rcl between."""

    def __init__(self, end):
        self.sock = end if isinstance(end, socket.socket) else None
        self.fd = end.fileno() if self.sock else end
        if self.sock is None:
            tty.setraw(self.fd)
        self.reader = P.FrameReader()
        self.later = []                  # frames read after the `until` one
        self.seq = 1
        self.last_sent = None            # monotonic time of our last write
        self.longest_gap = 0.0           # s between two of our writes, the longest

    def send(self, data):
        if self.sock:
            self.sock.sendall(data)
        else:
            os.write(self.fd, data)
        now = time.monotonic()
        if self.last_sent is not None:
            self.longest_gap = max(self.longest_gap, now - self.last_sent)
        self.last_sent = now

    def frames(self, seconds, until=None):
        """Every frame that comes within `seconds`, or up to the first for
        which until(frame) is true."""
        got, end = [], time.monotonic() + seconds
        while True:
            while self.later:                # (one read may hold several frames)
                got.append(self.later.pop(0))
                if until is not None and until(got[-1]):
                    return got
            if time.monotonic() >= end:
                return got
            if select.select([self.fd], [], [], 0.01)[0]:
                data = self.sock.recv(4096) if self.sock else os.read(self.fd, 4096)
                if not data:
                    return got
                self.later = self.reader.feed(data)

    def hello(self):
        """HELLO until IDENTIFY (a bound of 10 s, for a broken board); -> it."""
        for _ in range(100):
            self.send(P.frame(0, "HELLO", version=P.VERSION))
            got = self.frames(0.1, lambda f: f.name == "IDENTIFY")
            if got and got[-1].name == "IDENTIFY":
                self.seq = 1
                self.lockstep = bool(got[-1]["flags"] & P.FLAG_LOCKSTEP)
                return got[-1]
        raise AssertionError("no IDENTIFY")

    def ask(self, name, /, **values):
        """A sequenced frame, sent until its answer comes; -> the answer."""
        seq, self.seq = self.seq, P.following(self.seq)

        def answer(f):
            return "ack" in f.values and f["ack"] == seq
        for _ in range(100):
            self.send(P.frame(seq, name, **values))
            got = self.frames(0.1, answer)
            if got and answer(got[-1]):
                return got[-1]
        raise AssertionError("no answer to %s" % name)

    def ticks(self, seconds=5.0):
        """Frames up to the first TICK (a lockstep board's time runs only
        when the host WAITs for it; firmware ignores WAIT)."""
        got, end = [], time.monotonic() + seconds
        while time.monotonic() < end and not [f for f in got if f.name == "TICK"]:
            self.send(P.frame(0, "WAIT", tick=0xFFFF))
            got += self.frames(0.01, lambda f: f.name == "TICK")
        return got

    def rest(self, ms):
        """Let `ms` of board time pass (a lockstep board's by CLOCK, any
        other's read from its HEARTBEATs); -> the frames that came."""
        if self.lockstep:
            self.ask("CLOCK", us=ms * 1000)
            return self.frames(0.2)
        got, end = [], time.monotonic() + 10 + ms / 100
        beats = []
        while time.monotonic() < end:
            got += self.frames(0.05)
            beats = [f["time_us"] for f in got if f.name == "HEARTBEAT"]
            if beats and (beats[-1] - beats[0]) % 2**32 >= ms * 1000:
                break
        return got

    def close(self):
        if self.sock:
            self.sock.close()
        else:
            os.close(self.fd)


# What a hostile client can do with valid frames: the 80188's timer and
# interrupt registers, the 8253s, the latches, the vector table and BIOS
# data area, the per-tick script (one that switches the motors on).
# (Max counts from 2000, timer 2's 1 to 3: a tick no faster than 1 ms, so
# that the test's own frames still get through.)
PCB = {0xFF28: (0, 0x10000), 0xFF32: (0, 0x10000), 0xFF50: (0, 0x10000),
       0xFF52: (2000, 0x10000), 0xFF54: (2000, 0x10000), 0xFF56: (0, 0x10000),
       0xFF5E: (0, 0x10000), 0xFF62: (1, 4), 0xFF66: (0, 0x10000)}
MOTORS_ON = 0x35                               # both wheels on and going


def hostile(raw, seed, frames=120):
    """Seeded random valid frames, ending with the board ticking into the
    Forth segment, the motors on and a script that switches them on."""
    rnd = random.Random(seed)
    raw.hello()
    for _ in range(frames):
        kind = rnd.randrange(6)
        if kind == 0:
            port = rnd.choice(sorted(PCB))
            raw.ask("OUT16", port=port, value=rnd.randrange(*PCB[port]))
        elif kind == 1:
            raw.ask("OUT8", port=rnd.randrange(0x80, 0x8A), value=rnd.randrange(256))
        elif kind == 2:
            raw.ask("FAR_STORE", seg=0, off=rnd.randrange(0x80), value=rnd.randrange(256))
        elif kind == 3:
            raw.ask("FAR_STORE", seg=0x40, off=rnd.choice([0x6C, 0x6D, 0x6E, 0x70, 0xF0, 0xF2]),
                    value=rnd.randrange(256))
        elif kind == 4:
            raw.ask("SNAPSHOT", ops=[(rnd.randrange(2), rnd.randrange(0x80, 0x8B),
                                      rnd.randrange(256)) for _ in range(rnd.randrange(1, 16))])
        else:
            raw.ask("RUN", ops=[(0, rnd.randrange(0x80, 0x88), rnd.randrange(256))])
    for base in (0x80, 0x84):                   # both speed references at 2500 Hz
        raw.ask("OUT8", port=base + 3, value=0x36)
        raw.ask("OUT8", port=base, value=50)
        raw.ask("OUT8", port=base, value=0)
    for off, byte in zip(range(0x70, 0x74), (0x34, 0x12, 0x00, 0x10)):   # INT 1Ch -> 1000:1234
        raw.ask("FAR_STORE", seg=0, off=off, value=byte)
    raw.ask("SNAPSHOT", ops=[(0, 0x88, MOTORS_ON)])
    raw.ask("OUT16", port=0xFF32, value=0)                  # unmasked
    raw.ask("OUT16", port=0xFF62, value=3)                  # timer 2 prescales by 3
    raw.ask("OUT16", port=0xFF66, value=0xC001)
    raw.ask("OUT16", port=0xFF52, value=6667)
    raw.ask("OUT16", port=0xFF50, value=0)
    raw.ask("OUT16", port=0xFF56, value=0xE009)            # EN INH INT P CONT
    raw.ask("OUT8", port=0x88, value=MOTORS_ON)
    ticks = [f for f in raw.ticks() if f.name == "TICK"]
    assert ticks and ticks[-1]["off"] == 0x1234            # the board ran the hostile tick


# ------------------------------------------------------------------ tests


@pytest.mark.parametrize("kind", ["tcp", "pty", "native", "uno"])
def test_sessions_one_after_another_on_one_running_board_drive_the_first_commands_counts(
        kind, running, image):
    b = running(kind)
    first = session(b.where, image)
    one_inch(kind, first)
    slack = 2 if kind in ("native", "uno") else 1
    later = []
    for n in range(2, SESSIONS + 1):
        try:
            later.append(session(b.where, image))
        except (AssertionError, rcl.ForthError) as e:    # which session, and what came before
            told = "session %d of %d: %s (first %s, then %s)" % (n, SESSIONS, e, first, later)
            if isinstance(e, rcl.ForthError):
                e.message = told
                raise
            raise AssertionError(told) from None
    print("\n%s: first %s, then %s" % (kind, first, later))
    for counts in later:
        same_move(kind, counts, first, slack)


@pytest.mark.parametrize("kind", ["tcp", "native", "uno"])
def test_a_session_after_a_hostile_client_starts_clean_and_its_first_move_is_exact(
        kind, running, image):
    b = running(kind)
    clean = session(b.where, image)
    raw = b.raw()
    hostile(raw, seed=18)
    raw.close()                                   # gone, leaving the wheels running
    raw = b.raw()
    raw.hello()                                   # a new session: nothing of the last runs
    after = raw.rest(400)                         # (and the wheels come to rest)
    assert not [f for f in after if f.name == "TICK"]
    beats = [f for f in after if f.name == "HEARTBEAT"]
    assert beats and not any(f["ticking"] for f in beats)
    assert raw.ask("FAR_FETCH", seg=0, off=0x73)["value"] == 0xF0     # INT 1Ch: the BIOS's
    raw.close()
    after = session(b.where, image)
    print("\n%s: clean %s, after the hostile client %s" % (kind, clean, after))
    same_move(kind, after, clean)


def test_the_second_rcl_on_a_running_rcl_board_exits_0(running):
    # the issue's own case: `rcl --port socket://... -e BYE` twice, the
    # second had run the first one's tick handler while loading RCL
    b = running("tcp")
    for _ in range(2):
        run = subprocess.run([sys.executable, "-m", "rcl", "--port", b.where, "-e", "BYE"],
                             stdin=subprocess.DEVNULL, capture_output=True, text=True,
                             timeout=120)
        assert run.returncode == 0, run.stderr


def test_rcl_leaving_leaves_the_board_safe_and_its_tick_stopped():
    m = rcl.open(port="rclsim://")
    server = m.board.port.server
    m.evaluate("53 136 PC!  50 MS")                   # the motors on, the tick running
    assert server.ticking() and server.board.motor_latch == 53
    m.board.close()
    assert not server.ticking() and server.board.motor_latch == 0
    assert server.stats["watchdog"] == 0


def test_a_silent_host_leaves_rcl_board_and_the_native_firmware_quiet(running, board):
    for b in (running("tcp"), board("native-fast")):
        raw = b.raw()
        hostile(raw, seed=5)                          # ticking, motors on
        # silent: the watchdog's 250 ms pass (the native board first waits
        # up to 1 s for the answer to its TICK, not counting that time)
        quiet = raw.frames(2.5)
        beats = [f for f in quiet if f.name == "HEARTBEAT"]
        assert beats and not beats[-1]["ticking"]
        assert quiet[-1].name == "HEARTBEAT"         # no TICK after the watchdog
        raw.close()


# ------------------------------------------------------ one host at a time
def test_a_second_host_is_refused_naming_the_cause_and_rcl_says_so(running, image):
    b = running("tcp")
    m = rcl.open(port=b.where, image=image)
    try:
        run = subprocess.run([sys.executable, "-m", "rcl", "--port", b.where, "-e", "BYE"],
                             stdin=subprocess.DEVNULL, capture_output=True, text=True,
                             timeout=120)
        assert m.evaluate("1 .") == "1 "                      # the first host goes on
    finally:
        m.board.close()
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert run.stderr == ("rcl: The board on %s refused a session: busy: another host is "
                          "connected\n" % b.where)


def test_a_refused_host_that_emptied_its_input_as_it_opened_hears_the_refusal_at_its_hello(
        running, image):
    # pyserial's socket:// empties its input as it opens: a REFUSED sent
    # at the connection's accept alone could be gone before rcl looks, and
    # rcl said "No answer from a board" (seen once in a whole run)
    b = running("tcp")
    m = rcl.open(port=b.where, image=image)
    try:
        raw = b.raw()
        raw.frames(0.3)                                  # emptied, as pyserial does
        raw.send(P.frame(0, "HELLO", version=P.VERSION))
        got = raw.frames(2.0, lambda f: f.name == "REFUSED")
        assert [(f.name, f.seq, f["reason"]) for f in got] == \
            [("REFUSED", 0, "busy: another host is connected")]
        raw.close()
        assert m.evaluate("1 .") == "1 "                  # the first host goes on
    finally:
        m.board.close()


def test_a_start_that_fails_after_connecting_leaves_the_board_to_the_next_host(
        running, image, tmp_path):
    # rcl.open() connects, then loads RCL (here a damaged image; on a busy
    # machine, a Link lost during INSTALL): the link it opened must close
    # with the error, or it stays connected, the board's host for ever
    b = running("tcp")
    damaged = tmp_path / "damaged.img"
    damaged.write_bytes(b"not an image")
    with pytest.raises(Exception) as e:
        rcl.open(port=b.where, image=str(damaged))
    assert "busy" not in str(e.value)
    one_inch("tcp", session(b.where, image))


def test_a_port_closed_while_a_thread_still_waits_on_it_opens_again_at_once(running, image):
    # The link's reader thread, not run on a busy machine, may still be
    # inside select() on the port when rcl closes it: the file stays open,
    # and the exclusive lock with it, until that thread runs (a busy run's
    # next session found the port busy). A thread of the test waits on the
    # port the same way (for an event a pty never has); close gives the
    # lock up, and the next session opens the port at once.
    b = running("pty")
    m = rcl.open(port=b.where, image=image)
    fd = m.board.port.fd
    entered = threading.Event()

    def wait_on_port():
        entered.set()
        try:
            select.select([], [], [fd], 3.0)
        except OSError:                  # closed before the wait began: no premise, no harm
            pass
    waiter = threading.Thread(target=wait_on_port)
    waiter.start()
    entered.wait()
    m.board.close()
    try:
        one_inch("pty", session(b.where, image))
    finally:
        waiter.join()


def test_a_client_that_connects_and_says_nothing_is_dropped_when_a_host_asks(running, image):
    b = running("tcp")
    raw = b.raw()                                  # connects, sends nothing
    time.sleep(0.5)                                # (past the watchdog's 250 ms)
    assert within_a_count(session(b.where, image), session(b.where, image))
    raw.close()


def test_a_host_that_hangs_up_leaves_the_relays_open_at_once_not_by_the_watchdog(tmp_path):
    import json
    report = tmp_path / "board.json"
    b = RclBoard("--pty", "--report", str(report))
    try:
        raw = b.raw()
        raw.hello()
        raw.ask("OUT8", port=0x88, value=MOTORS_ON)
        raw.close()                                 # hung up mid-move
        silent = max(raw.longest_gap, time.monotonic() - raw.last_sent)
        time.sleep(1.0)
    finally:
        b.close()
    stats = json.loads(report.read_text())
    assert stats["relays"][0] == 0
    if stats["stats"]["watchdog"] and silent > P.WATCHDOG_MS / 1000:
        # this process, not run, was silent past the watchdog (between its
        # HELLO and its write, or before it hung up): the board rightly tripped
        raise Starved("this process sent nothing for %d ms (a busy machine)" % (silent * 1000))
    assert stats["stats"]["hangups"] == 1 and stats["stats"]["watchdog"] == 0


# ------------------------------------------------------------ reconnecting
def test_a_reconnect_is_a_new_session_and_rcl_sets_the_board_up_again():
    m = rcl.open(port="rclsim://")
    server = m.board.port.server
    try:
        m.evaluate(": LEG  RERB 3 INCHES FORWARD ;  LEG")
        server.cut_link()
        end = time.monotonic() + 10
        while not m.board.lost and time.monotonic() < end:
            time.sleep(0.01)
        server.cut_link(False)
        time.sleep(0.6)                                  # past RECONNECT_AFTER
        # the next command reconnects, and stops, saying the board was reset
        # (a move would stop at its check: " Control loop not running ")
        with pytest.raises(rcl.ForthError) as e:
            m.evaluate("138 PC@ .")
        assert e.value.screen() == " Link up again, the board reset: RECONNECT sets it up "
        assert server.stats["sessions"] == 2 and not server.ticking()
        assert m.evaluate("RECONNECT").startswith(" Link up")
        assert server.stats["sessions"] == 3 and server.ticking()     # INSTALL ran again
        moved = [int(x) for x in m.evaluate("LEG 300 MS ?CNT1 D. ?CNT2 D.").split()]
        # counted from 0 again: 3 inches, 85 counts, within a move's 2 counts
        # (test_link_serve) and the count the wheel stood in
        assert all(abs(c - 85) <= 3 for c in moved), moved
    finally:
        m.board.close()
