"""Support for the firmware tests (tests/test_firmware_*.py): build the
firmware once per test session, run a board program that prints its
pseudo-terminal's path on its first line (the native build, or the simavr
harness with the Uno image), connect rcl to it, and a fault relay for the
link's fault cases.

    build("native")                  -> firmware/build (make, once per session)
    native_program(), uno_image(), harness_built()   -> the programs, built
    native_board (fixture)           start("--rate", 2) -> a native board process
    simavr (fixture)                 start(elf, *options) -> a Simavr, figures()
    with BoardProcess([exe, ...]) as board:
        m = connect(board.path)      # rcl.open(port=path)
        board.notes                  # the native build's event lines, parsed
    with FaultRelay(board.path, seed=1) as relay:
        m = connect(relay.path)      # rcl talks to the relay's pty
        relay.corrupt = 0.01; relay.drop = 0.01; relay.cut(); relay.mend()
        relay.flood(b"...")          # garbage into the board's line

Without the toolchain the tests skip and say what to install (or fail,
with RCL_REQUIRE_FIRMWARE=1, as CI wants).
"""
import collections
import json
import os
import pathlib
import random
import re
import select
import shutil
import signal
import subprocess
import threading
import time
import tty

import pytest

import rcl
from rcl.hw.protocol import WATCHDOG_MS
from starved import Starved

ROOT = pathlib.Path(__file__).resolve().parent.parent
FIRMWARE = ROOT / "firmware"
BUILD = FIRMWARE / "build"
INSTALL = ("apt-get install --no-install-recommends "
           "gcc-avr avr-libc binutils-avr libsimavr-dev")
SIMAVR_BUILD = FIRMWARE / "simavr" / "build"
HARNESS = SIMAVR_BUILD / "rcl-simavr"
PINS_TEST = SIMAVR_BUILD / "pins-test.elf"
NATIVE_TOOLS = ("make", "cc")
AVR_TOOLS = ("make", "avr-gcc", "avr-objcopy", "avr-size")

_built = {}
_lock = threading.Lock()


def missing_tools(tools):
    return [t for t in tools if shutil.which(t) is None]


def missing(why):
    """Skip the test, saying what to install; a failure instead where the
    firmware tests must run (CI sets RCL_REQUIRE_FIRMWARE=1 after
    installing the toolchain)."""
    if os.environ.get("RCL_REQUIRE_FIRMWARE") == "1":
        pytest.fail(why)
    pytest.skip(why)


def require_tools(tools):
    gone = missing_tools(tools)
    if gone:
        missing("firmware toolchain missing (%s): %s" % (", ".join(gone), INSTALL))


def build(*targets, **make_vars):
    """`make -C firmware TARGETS VAR=value` once per session and set of
    arguments; -> the build directory. A failed build fails the test with
    make's output (a build error is a defect, not a skip)."""
    need = NATIVE_TOOLS if set(targets) <= {"native"} else AVR_TOOLS + ("cc",)
    require_tools(need)
    key = (targets, tuple(sorted(make_vars.items())))
    with _lock:
        if key not in _built:
            cmd = ["make", "-C", str(FIRMWARE), *targets,
                   *("%s=%s" % kv for kv in sorted(make_vars.items()))]
            done = subprocess.run(cmd, capture_output=True, text=True)
            _built[key] = done
        done = _built[key]
    if done.returncode:
        pytest.fail("firmware build failed:\n%s%s" % (done.stdout, done.stderr))
    return BUILD


def native_program(version=1):
    """The native build's program (another protocol version: its own build)."""
    if version == 1:
        build("native")
        return BUILD / "native"
    build("native", VERSION=version)
    return BUILD / ("native-v%d" % version)


def uno_image(version=1):
    """The Uno image (another protocol version: its own build)."""
    build("uno", **({"VERSION": version} if version != 1 else {}))
    return BUILD / ("uno%s.elf" % ("" if version == 1 else "-v%d" % version))


def harness_built():
    """rcl-simavr and its test program, built; -> the harness."""
    if not os.path.exists("/usr/include/simavr/sim_avr.h"):
        missing("simavr's headers are missing (libsimavr-dev): " + INSTALL)
    build("simavr")
    return HARNESS


NOTE = re.compile(r"(\w+) (.*)")


def parse_note(line):
    """'motor us=138000 tick=7 value=53 left=0 right=0' -> a dict."""
    m = NOTE.match(line.strip())
    if not m:
        return None
    note = {"event": m.group(1)}
    for field in m.group(2).split():
        key, _, value = field.partition("=")
        try:
            note[key] = int(value)
        except ValueError:
            note[key] = value
    return note


def raise_the_uno(proc):
    """The Uno image under simavr stands for a board with a CPU of its own
    and needs most of a core to keep real time: its process runs at nice
    -10 where the tests may set that (root). Only it, and one at a time
    (conftest.py's "boards" group): a raised process may take one core, never
    both, or the kernel's pty workers (normal priority) wait, and every pty
    stands still (docs/testing.md)."""
    try:
        os.setpriority(os.PRIO_PROCESS, proc.pid, -10)
    except OSError:
        pass


class BoardProcess:
    """A board program: its first stdout line is its pty's path; later
    lines are event notes, kept (parsed) in `notes`."""

    def __init__(self, argv, startup=10.0):
        self.argv = [str(a) for a in argv]
        self.startup = startup
        self.notes = []
        self.lines = []
        self.proc = None

    def __enter__(self):
        self.proc = subprocess.Popen(
            self.argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
            text=True, bufsize=1)                            # never the terminal's input
        if pathlib.Path(self.argv[0]).name == "rcl-simavr":
            raise_the_uno(self.proc)
        ready, _, _ = select.select([self.proc.stdout], [], [], self.startup)
        if not ready:
            self.close()
            pytest.fail("%s printed no pty path within %.0f s" % (self.argv[0], self.startup))
        self.path = self.proc.stdout.readline().strip()
        if not self.path.startswith("/dev/"):
            self.close()
            pytest.fail("%s printed %r, not a pty path" % (self.argv[0], self.path))
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()
        return self

    def _read(self):
        for line in self.proc.stdout:
            self.lines.append(line)
            note = parse_note(line)
            if note is not None:
                self.notes.append(note)

    def events(self, name):
        return [n for n in list(self.notes) if n["event"] == name]

    def wait_for(self, condition, seconds=5.0):
        """Wait (a bounded wall time, only so a broken board cannot hang the
        run) until condition() is true; -> its last value."""
        end = time.monotonic() + seconds
        while not condition() and time.monotonic() < end:
            time.sleep(0.01)
        return condition()

    def close(self):
        if self.proc is not None and self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()

    def __exit__(self, *exc):
        self.close()


class Simavr(BoardProcess):
    """rcl-simavr running an image: a board process whose figures (true
    edges, TICK period, bytes each way) come from its stats file."""

    def __init__(self, tmp_path, elf, *options):
        self.stats_path = pathlib.Path(tmp_path) / ("simavr-%d.json" % id(self))
        super().__init__([harness_built(), "--quiet", "--stats", self.stats_path,
                          *options, elf])

    def figures(self):
        """The harness's figures now (SIGUSR1 asks for a fresh stats file)."""
        seen = self._report()
        os.kill(self.proc.pid, signal.SIGUSR1)
        self.wait_for(lambda: self._report() > seen)
        return json.loads(self.stats_path.read_text())

    def _report(self):
        try:
            return json.loads(self.stats_path.read_text())["report"]
        except (OSError, ValueError):
            return 0

    def stop(self):
        """Stop it; -> its last figures (written as it exits)."""
        self.close()
        return json.loads(self.stats_path.read_text())


# Fixtures for the test modules that import them: each board started is
# closed after its test.
@pytest.fixture
def native_board():
    """-> start(*options, version=1): the native build (or another
    protocol version's) with its options, e.g. start("--rate", 2)."""
    started = []

    def start(*options, version=1):
        started.append(BoardProcess([native_program(version), *options]))
        return started[-1].__enter__()
    yield start
    for b in started:
        b.close()


@pytest.fixture
def simavr(tmp_path):
    """-> start(elf, *options): rcl-simavr running an image."""
    started = []

    def start(elf, *options):
        started.append(Simavr(tmp_path, elf, *options).__enter__())
        return started[-1]
    yield start
    for b in started:
        b.close()


def connect(path):
    """rcl on the board at `path` (RCL loaded, the link up)."""
    return rcl.open(port=path)


# How late an answer to a TICK the Uno harness waits for: 50 ms past its
# 5 ms slack (rcl-simavr: a held AVR sends no HEARTBEAT, and the host must
# hear from it within 250 ms). A later answer, and the wheels ran on.
UNO_PATIENCE = 0.055

# A relay not run this long held the line past the board's watchdog.
LINE_STALL = WATCHDOG_MS / 1000


class FaultRelay:
    """A pty pair between rcl and the board: bytes are copied both ways,
    and can be corrupted (a random bit flipped), dropped (with a seeded
    random choice per byte), cut off altogether, or joined by garbage."""

    def __init__(self, board_path, seed=1, corrupt=0.0, drop=0.0):
        self.board_path = board_path
        self.random = random.Random(seed)
        self.corrupt, self.drop = corrupt, drop
        self.cutting = False
        self.stats = {"to_board": 0, "to_host": 0, "corrupted": 0, "dropped": 0}
        self.stopping = threading.Event()
        self.longest_stall = 0.0        # s between two turns of the copying loop, the longest

    def __enter__(self):
        self.board = os.open(self.board_path, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self.board)
        self.master, slave = os.openpty()
        tty.setraw(slave)
        self.path = os.ttyname(slave)
        self.slave = slave             # held open: the master never reads EIO between hosts
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()
        return self

    def cut(self):
        """Silence both ways (bytes in flight are lost), as a pulled cable."""
        self.cutting = True

    def mend(self):
        self.cutting = False

    def flood(self, data, to_host=False):
        """Garbage into the board's line (or the host's)."""
        os.write(self.master if to_host else self.board, data)

    def _garble(self, data):
        out = bytearray()
        for byte in data:
            if self.drop and self.random.random() < self.drop:
                self.stats["dropped"] += 1
                continue
            if self.corrupt and self.random.random() < self.corrupt:
                byte ^= 1 << self.random.randrange(8)
                self.stats["corrupted"] += 1
            out.append(byte)
        return bytes(out)

    def _run(self):
        ends = {self.master: (self.board, "to_board"), self.board: (self.master, "to_host")}
        turned = time.monotonic()
        while not self.stopping.is_set():
            ready, _, _ = select.select(list(ends), [], [], 0.05)
            now = time.monotonic()
            self.longest_stall = max(self.longest_stall, now - turned)
            turned = now
            for fd in ready:
                try:
                    data = os.read(fd, 4096)
                except OSError:
                    continue
                if not data or self.cutting:
                    continue
                other, count = ends[fd]
                data = self._garble(data)
                self.stats[count] += len(data)
                try:
                    os.write(other, data)
                except OSError:
                    pass

    def close(self):
        self.stopping.set()
        self.thread.join(2)
        for fd in (self.master, self.slave, self.board):
            try:
                os.close(fd)
            except OSError:
                pass

    def __exit__(self, kind, error, trace):
        self.close()
        if isinstance(error, rcl.ForthError) and self.longest_stall > LINE_STALL:
            # rcl's verdict on a line that stood still: this relay, a thread
            # of the test's process, was not run (the premise is a line that
            # carries bytes as they come)
            raise Starved("the relay copied nothing for %d ms (a busy machine): %s"
                          % (self.longest_stall * 1000, error)) from error


class RawLink:
    """Frames straight to a board's pty, without rcl: for the protocol's
    own rules (repeats, NAK, bad payloads, the watchdog's silence)."""

    def __init__(self, path):
        from rcl.hw import protocol
        self.P = protocol
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self.fd)
        self.reader = protocol.FrameReader()
        self.raw = bytearray()          # every byte received, for byte-for-byte checks
        self.later = collections.deque()    # frames read after the one returned
        self.last_sent = None
        self.longest_silence = 0.0      # s between two of our writes, the longest (tests reset it)

    def send(self, data):
        now = time.monotonic()
        if self.last_sent is not None:
            self.longest_silence = max(self.longest_silence, now - self.last_sent)
        os.write(self.fd, data)
        self.last_sent = now

    def frame(self, seq, name, /, **values):
        data = self.P.frame(seq, name, **values)
        self.send(data)
        return data

    def hello(self):
        """HELLO until IDENTIFY (a host gives a board that is starting
        3 s); -> the IDENTIFY."""
        for _ in range(3):
            self.frame(0, "HELLO", version=self.P.VERSION)
            ident = self.receive("IDENTIFY", seconds=1.0)
            if ident is not None:
                return ident
        pytest.fail("no IDENTIFY")

    def ask(self, seq, name, /, **values):
        """A sequenced frame, sent again every 100 ms until its answer
        comes (a repeat is answered again, not acted on twice: section
        3); -> the answer. The 10 s bound is for a broken board."""
        for _ in range(100):
            self.frame(seq, name, **values)
            end = time.monotonic() + 0.1
            while time.monotonic() < end:
                f = self.receive(seconds=0.02)
                if f is not None and "ack" in f.values and f["ack"] == seq:
                    return f
        pytest.fail("no answer to %s" % name)

    def receive(self, want=None, seconds=2.0):
        """Frames until one named `want` (or any, if None) comes; -> it, or
        None after `seconds` (a bound for a broken board, not a measure)."""
        end = time.monotonic() + seconds
        while True:
            # one read may hold several frames (two TICKs, on a busy
            # machine): those after the one returned wait for the next call
            while self.later:
                f = self.later.popleft()
                if want is None or f.name == want:
                    return f
            if time.monotonic() >= end:
                return None
            ready, _, _ = select.select([self.fd], [], [], 0.05)
            if ready:
                data = os.read(self.fd, 4096)
                self.raw += data
                self.later.extend(self.reader.feed(data))

    def answer(self, seq, name, /, **values):
        """Send a sequenced frame; -> its answer (ACK, VALUE, RESULTS or
        REFUSED carrying `ack` = seq), skipping TICKs and HEARTBEATs."""
        self.frame(seq, name, **values)
        end = time.monotonic() + 2.0
        while time.monotonic() < end:
            f = self.receive()
            if f is not None and "ack" in f.values and f["ack"] == seq:
                return f
        return None

    def close(self):
        os.close(self.fd)


# ----------------------------------------- what the firmware tests drive
EXAMPLES = pathlib.Path(rcl.SCREENS) / "examples"
FIRST_COMMAND = "RERB 2 MPH 3.4 FEET FORWARD"
LEGS = "RERB 6 INCHES FORWARD 90 DEGREES LEFT 6 INCHES FORWARD"
PER_MOVE = 2                     # counts: see tests/test_firmware_native.py's docstring
REST = "300 MS"                  # the braked wheels at rest (6 braking constants)


def counts(m):
    """Both wheels' positions as RCL reads its counters, at rest."""
    out = m.evaluate(REST + " ?CNT1 D. ?CNT2 D.")
    left, right = (int(x) for x in out.split())
    return left, right


def simulated(program=None, listing=None):
    m = rcl.open()
    if listing:
        m.include(EXAMPLES / listing)
    else:
        m.evaluate(program)
    return counts(m)


def skipped_before_the_word(m):
    """The ticks rcl was away from before a word runs (opening the link,
    compiling RCL ahead, the prompt): more than 25 queued, the older are
    counted skipped by design (docs/protocol.md). A trivial word takes
    them; -> the count a test of the word's own ticks starts from."""
    m.evaluate("10 MS")
    return m.board.skipped


def leg_after_reconnect(m):
    """The link mended: RECONNECT finds it up and LEG, defined before the
    cut, drives; -> the counts each wheel moved."""
    assert m.evaluate("RECONNECT").startswith(" Link up")
    before = counts(m)
    m.evaluate("LEG")                               # the definition survived
    return [a - b for a, b in zip(counts(m), before)]


def within(a, b, tolerance):
    return all(abs(x - y) <= tolerance for x, y in zip(a, b))


def uno_moved(moved, expected, tolerance, figures, aways_before=0):
    """Assert that a move on the Uno image ended within `tolerance` counts
    of `expected`. The harness holds the board for the host's answer to
    each tick, at most 50 ms (UNO_PATIENCE); one it gave up on while a
    wheel was driven let the wheels run on without the host's next writes
    (`aways_moving`, counted since `aways_before`): a host process not run
    in time, the machine's doing, which conftest.py runs again."""
    away = figures["aways_moving"] - aways_before
    if away and not within(moved, expected, tolerance):
        raise Starved("moved %s for %s: the harness gave up waiting for the host %d time(s)"
                      " while a wheel was driven (a busy machine)" % (list(moved), list(expected), away))
    assert within(moved, expected, tolerance), (list(moved), list(expected), tolerance)
