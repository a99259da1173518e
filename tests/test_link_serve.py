"""rcl-board serves the simulated board behind a real pseudo-terminal and a
loopback TCP port; `rcl --port` drives it through pyserial exactly as it
would drive hardware. Each test starts its own rcl-board and stops it."""
import json
import os
import subprocess
import sys

import pytest

import rcl
from starved import Starved

LISTING1 = os.path.join(rcl.SCREENS, "examples", "listing1.fs")


class Served:
    """An rcl-board process; its first line of output says where it serves."""

    def __init__(self, tmp_path, *args):
        self.report = tmp_path / "board.json"
        self.proc = subprocess.Popen(
            [sys.executable, "-m", "rcl.hw.boardcli", *args, "--report", str(self.report)],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.where = self.proc.stdout.readline().strip()

    def stop(self):
        self.proc.terminate()
        self.proc.wait(10)
        return json.loads(self.report.read_text())


@pytest.fixture
def serve(tmp_path):
    boards = []

    def start(*args):
        boards.append(Served(tmp_path, *args))
        return boards[-1]
    yield start
    for b in boards:
        if b.proc.poll() is None:
            b.proc.kill()
            b.proc.wait(10)


def assert_no_watchdog_while_connected(report):
    """The board's watchdog never tripped while rcl drove it. Once rcl has
    left, the board hears nothing, and trips 250 ms later if the test's
    stop() comes later than that (a loaded host): that trip is after the
    host's last frame, in the board's own time."""
    trips = report["stats"]["watchdog"]
    assert trips == 0 or (trips == 1 and report["watchdog_at"] >= report["last_host_frame_at"])


def rcl_cli(*args, stdin=""):
    return subprocess.run([sys.executable, "-m", "rcl", *args], input=stdin,
                          capture_output=True, text=True, timeout=120)


# Counts are compared with the wheels at rest: a move ends while the braked
# wheels still run out a few counts, which the served board goes on doing
# after rcl has left, for as long as the test takes to stop it.
REST = "300 MS"


def finished(run):
    """Assert the rcl child ended well. One that ended with rcl's verdict
    that time ran out (Link lost, Host too slow: a board or a host not run
    for 250 ms beside CPU hogs) raises Starved, as that verdict does in
    this process (conftest.py runs the test again)."""
    if run.returncode != 0 and any(v in run.stderr for v in (": Link lost", ": Host too slow")):
        raise Starved(run.stderr.strip().splitlines()[0])
    assert run.returncode == 0, run.stderr


def listing1_counts():
    m = rcl.open()
    m.include(LISTING1)
    m.evaluate(REST)
    return m.sim.wheel_counts


def test_listing_1_over_a_pty_ends_as_over_rclsim_and_within_2_counts_of_the_simulation(serve):
    board = serve("--pty", "--rate", "8")
    assert board.where.startswith("/dev/")
    run = rcl_cli("--port", board.where, LISTING1, "-e", REST)
    finished(run)
    report = board.stop()
    m = rcl.open(port="rclsim://?rate=16")       # lockstep: the frames decide, not the line
    m.include(LISTING1)
    m.evaluate(REST)
    m.board.close()
    assert tuple(report["wheel_counts"]) == m.sim.wheel_counts == (3521, 6028)
    for got, want in zip(report["wheel_counts"], listing1_counts()):
        assert abs(got - want) <= 2                          # (3522, 6027)
    assert report["relays"][0] == 0
    assert_no_watchdog_while_connected(report)


def test_a_short_square_over_tcp_ends_where_the_simulation_ends(serve):
    board = serve("--tcp", "127.0.0.1:0", "--rate", "4")
    host_port = board.where.rsplit(" ", 1)[1]
    square = "RERB 3 INCHES FORWARD 90 DEGREES LEFT FORWARD LEFT FORWARD LEFT FORWARD LEFT"
    run = rcl_cli("--port", "socket://" + host_port, "-e", square + " " + REST)
    finished(run)
    report = board.stop()
    m = rcl.open()
    m.evaluate(square + " " + REST)
    for got, want in zip(report["wheel_counts"], m.sim.wheel_counts):
        assert abs(got - want) <= 2


def test_terminal_noise_on_the_pty_before_rcl_connects_is_skipped(serve):
    board = serve("--pty")
    fd = os.open(board.where, os.O_RDWR | os.O_NOCTTY)
    os.write(fd, b"ATZ\r\n+++ATH0\r\n\x1b[2J\xa5\xff\xa5\x40" + bytes(range(256)))
    os.close(fd)
    run = rcl_cli("--port", board.where, "-e", "HEX 8A PC@ . BYE")
    finished(run)
    assert run.stdout.split()[-1] == rcl.open().evaluate("HEX 8A PC@ .").split()[0]
    assert board.proc.poll() is None                 # the board did not crash
    assert board.stop()["rejected_frames"] > 0


def test_rcl_port_refuses_a_board_of_another_protocol_version(serve):
    board = serve("--pty", "--speak-version", "2")
    run = rcl_cli("--port", board.where, "-e", "BYE")
    assert run.returncode == 2
    assert "protocol version 2; this rcl speaks version 1" in run.stderr
    assert "Traceback" not in run.stderr


def test_rcl_port_says_plainly_when_there_is_no_such_port():
    run = rcl_cli("--port", "/dev/rcl-no-such-port", "-e", "BYE")
    assert run.returncode == 2
    assert "/dev/rcl-no-such-port: no such port" in run.stderr


def test_rcl_board_listens_on_loopback_only_unless_allowed():
    run = subprocess.run([sys.executable, "-m", "rcl.hw.boardcli", "--tcp", "0.0.0.0:0"],
                         capture_output=True, text=True, timeout=30)
    assert run.returncode != 0 and "--allow-remote" in run.stderr


def test_rcl_board_help_explains_every_option():
    run = subprocess.run([sys.executable, "-m", "rcl.hw.boardcli", "--help"],
                         capture_output=True, text=True, timeout=30)
    # ("optional arguments:" before Python 3.10, "options:" since)
    options = run.stdout[run.stdout.index("--help"):]
    # argparse puts an option with no help alone on its line, with no text after it
    for option in ("--corrupt RATE", "--seed SEED", "--cut-at S", "--cut-for S",
                   "--stall {left,right}", "--speak-version N", "--report FILE.json"):
        line = next(ln for ln in options.splitlines() if ln.strip().startswith(option))
        assert line.strip() != option, option


def test_rcl_usb_sim_drives_the_simulated_usb_board():
    run = rcl_cli("--usb", "sim", "-e", "RERB 2 INCHES FORWARD TICKS@ D. BYE")
    finished(run)


def test_rcl_list_ports_lists_and_never_fails():
    run = rcl_cli("--list-ports")
    assert run.returncode == 0 and run.stdout.strip() and "Traceback" not in run.stderr


def test_rcl_port_says_plainly_when_the_port_is_busy(serve):
    import serial
    board = serve("--pty")
    held = serial.Serial(board.where, exclusive=True)
    try:
        run = rcl_cli("--port", board.where, "-e", "BYE")
    finally:
        held.close()
    assert run.returncode == 2
    assert "port busy" in run.stderr and "Traceback" not in run.stderr


def test_a_wheel_stalled_on_the_served_board_is_a_following_error_at_the_host(serve):
    board = serve("--pty", "--stall", "left", "--rate", "8")
    run = rcl_cli("--port", board.where, "-e", "RERB 6 INCHES FORWARD")
    assert run.returncode == 1 and "Following error" in run.stderr
    report = board.stop()
    assert report["wheel_counts"][0] == 0 and report["relays"][0] == 0
