"""Every board the project ships, for the conformance rules: one process
per board for all its rules (rules begin with HELLO and put back what they
changed), and the rule x board table at the end of the run.

    rcl-board        python -m rcl.hw.boardcli --pty (lockstep)
    rcl-board-free   ... --free-running (a real board's timing)
    native           firmware/build/native (the firmware's C on Linux)
    uno              firmware/build/uno.elf under rcl-simavr (the AVR image)

The firmware boards are built by the Makefile (tests/firmware_support.py);
without the toolchain they skip, or fail with RCL_REQUIRE_FIRMWARE=1.
"""
import os
import sys

import pytest

from firmware_support import BUILD, INSTALL, ROOT, BoardProcess, build, native_program
import wire

BOARDS = ["rcl-board", "rcl-board-free", "native", "uno"]
SIMAVR = ROOT / "firmware" / "simavr" / "build" / "rcl-simavr"


def board_argv(kind):
    if kind.startswith("rcl-board"):
        return [sys.executable, "-m", "rcl.hw.boardcli", "--pty"] + (
            ["--free-running"] if kind == "rcl-board-free" else [])
    if kind == "native":
        return [native_program()]
    if not os.path.exists("/usr/include/simavr/sim_avr.h"):
        why = "simavr's headers are missing (libsimavr-dev): " + INSTALL
        if os.environ.get("RCL_REQUIRE_FIRMWARE") == "1":
            pytest.fail(why)
        pytest.skip(why)
    build("uno")
    build("simavr")
    return [SIMAVR, "--quiet", BUILD / "uno.elf"]


class Board(BoardProcess):
    """A board process and what it had at power-on, to put back."""

    def __init__(self, kind):
        self.kind = kind
        super().__init__(board_argv(kind), startup=20.0)

    def __enter__(self):
        root = str(ROOT)
        os.environ["PYTHONPATH"] = os.pathsep.join(
            [root] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])
        super().__enter__()
        s = wire.Session(self.path)
        try:
            s.hello()
            self.power_on = {
                "vector": [s.fetch(0, 0x70 + i) for i in range(4)],
                "t0con": s.in16(0xFF56), "t0max": s.in16(0xFF52),
                "per_day": s.fetch32(0x40, 0xF0)}
        finally:
            s.close()
        return self

    def restore(self, s):
        """Put back what a rule may have changed: SAFE, no script, the
        vector, timer 0 and the day as they were at power-on."""
        s.drain()
        s.hello()
        p = self.power_on
        for i, byte in enumerate(p["vector"]):
            s.store(0, 0x70 + i, byte)
        s.request(wire.SNAPSHOT)
        s.request(wire.SAFE)
        s.out16(0xFF52, p["t0max"])
        s.out16(0xFF56, p["t0con"] | 0x4000)     # INH: EN written as it was
        s.store32(0x40, 0xF0, p["per_day"])
        s.drain()


# Module scope: pytest runs each board's rules together and stops its
# process before the next board's (session scope kept the last board, the
# Uno under simavr, burning CPU in real time for the rest of the run).
@pytest.fixture(scope="module", params=BOARDS)
def board(request):
    b = Board(request.param)
    b.__enter__()
    yield b
    b.close()


@pytest.fixture
def s(board):
    """A host session on the board, after HELLO; the board put back after."""
    session = wire.Session(board.path)
    session.kind = board.kind
    session.hello()
    yield session
    try:
        board.restore(session)
    finally:
        session.close()


# ------------------------------------------------------------ the table
_results = {}


def pytest_runtest_logreport(report):
    if "conformance" not in report.nodeid or "[" not in report.nodeid:
        return
    rule, _, kind = report.nodeid.rpartition("::")[2].partition("[")
    kind = kind.rstrip("]")
    if report.when == "call" or (report.when == "setup" and report.outcome != "passed"):
        word = {"passed": "pass", "failed": "FAIL", "skipped": "n/a"}[report.outcome]
        _results.setdefault(rule, {})[kind] = word


def pytest_terminal_summary(terminalreporter):
    if not _results:
        return
    kinds = [k for k in BOARDS if any(k in r for r in _results.values())]
    width = max(len(r) for r in _results) - len("test_")
    w = terminalreporter
    w.section("conformance: rule x board")
    w.line("%-*s  %s" % (width, "rule", "  ".join("%-14s" % k for k in kinds)))
    for rule, row in _results.items():
        w.line("%-*s  %s" % (width, rule[len("test_"):],
                             "  ".join("%-14s" % row.get(k, "-") for k in kinds)))
    for k in kinds:
        col = [row.get(k) for row in _results.values()]
        w.line("%s: %d pass, %d n/a, %d fail" % (k, col.count("pass"), col.count("n/a"),
                                                 col.count("FAIL")))
