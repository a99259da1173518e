"""The firmware's real Uno image (ATmega328P, 16 MHz) under simavr, through
rcl-simavr (firmware/simavr): UART0 on a pseudo-terminal at 115200 baud's
pace, the PWM and L298N pins driving firmware/model's gearmotors, whose
quadrature edges come back on the encoder pins.

The first tests check the harness itself with its own small AVR program
(firmware/simavr/test/pins.c, the same pin map); the rest drive the Uno
image through rcl. Assertions count the board's ticks, never wall time:
simulated time follows real time but never runs ahead of it, so a stalled
machine only slows the board down."""
import json
import os
import signal
import struct
import subprocess
import time

import pytest
import serial

from firmware_support import BUILD, INSTALL, ROOT, BoardProcess, build

SIMAVR_BUILD = ROOT / "firmware" / "simavr" / "build"
HARNESS = SIMAVR_BUILD / "rcl-simavr"
PINS_TEST = SIMAVR_BUILD / "pins-test.elf"


def harness_built():
    """Build rcl-simavr and its test program (skip, saying what to install,
    without the toolchain or simavr's headers)."""
    if not os.path.exists("/usr/include/simavr/sim_avr.h"):
        pytest.skip("simavr's headers are missing (libsimavr-dev): " + INSTALL)
    build("simavr")
    return HARNESS


class Simavr(BoardProcess):
    """rcl-simavr running an image: a board process whose figures (true
    edges, TICK period, bytes each way) come from its stats file."""

    def __init__(self, tmp_path, elf, *options):
        self.stats_path = tmp_path / ("simavr-%s.json" % os.path.basename(str(elf)))
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


@pytest.fixture
def simavr(tmp_path):
    started = []

    def start(elf, *options):
        started.append(Simavr(tmp_path, elf, *options).__enter__())
        return started[-1]
    yield start
    for board in started:
        board.close()


# ------------------------------------------- the harness, on its own program
class PinsTest:
    """firmware/simavr/test/pins.c over the harness's pty."""

    def __init__(self, path):
        self.port = serial.Serial(path, 115200, timeout=5)

    def ask(self, request, reply_len):
        self.port.write(request)
        reply = self.port.read(reply_len)
        assert len(reply) == reply_len and reply[:1] == request[:1]
        return reply[1:]

    def drive(self, left, right):
        self.port.write(b"m" + struct.pack("bb", left, right))

    def edges(self):
        """(left, right, decode errors) as the pin-change ISR counted them."""
        return struct.unpack("<iiB", self.ask(b"c", 10))

    def ticks(self):
        return struct.unpack("<H", self.ask(b"t", 3))[0]

    def limits(self):
        return self.ask(b"s", 2)[0]

    def wait_ticks(self, n):
        """n of the board's 10 ms Timer1 ticks, however long they take."""
        start = self.ticks()
        while (self.ticks() - start) % 65536 < n:
            pass


def test_the_harness_prints_its_pty_first_takes_commands_and_carries_bytes_both_ways(tmp_path):
    stats = tmp_path / "stats.json"
    proc = subprocess.Popen([harness_built(), "--quiet", "--stats", stats, PINS_TEST],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        path = proc.stdout.readline().strip()
        assert path.startswith("/dev/pts/")
        board = PinsTest(path)
        noise = bytes(b for b in range(256) if b not in b"mcts")
        board.port.write(noise)
        assert board.port.read(len(noise)) == noise
        assert board.limits() == 0b11                   # both switches open: pulled up
        proc.stdin.write("hold arm\nstats\n")
        proc.stdin.flush()
        figures = json.loads(proc.stdout.readline())
        assert figures["limits_held"] == [1, 0] and board.limits() == 0b10
        assert figures["bytes_to_board"] == len(noise) + 1
        assert figures["bytes_from_board"] == len(noise) + 2
        proc.stdin.write("quit\n")
        proc.stdin.flush()
        assert proc.wait(10) == 0
        assert json.loads(stats.read_text())["dropped_to_board"] == 0
    finally:
        proc.kill()
        proc.wait()


def test_pwm_duty_and_the_l298n_inputs_set_each_models_drive(simavr):
    sim = simavr(PINS_TEST)
    board = PinsTest(sim.path)
    board.drive(63, -127)                       # OCR0B 127, OCR0A 255: fast PWM
    board.wait_ticks(1)
    assert sim.figures()["drive"] == [128 / 256, -1.0]
    board.drive(0, 0)                           # IN1 = IN2: no drive
    board.wait_ticks(1)
    assert sim.figures()["drive"] == [0.0, 0.0]


def test_every_edge_the_motor_model_makes_reaches_the_pin_change_interrupt(simavr):
    sim = simavr(PINS_TEST)
    board = PinsTest(sim.path)
    board.drive(127, -90)                       # left forward at full speed
    board.wait_ticks(50)                        # 0.5 s: 5,600 edges and more
    board.drive(0, 0)
    board.wait_ticks(50)                        # ten time constants: at rest
    while True:                                 # one reading between two equal ones
        before = board.edges()
        figures = sim.figures()
        if board.edges() == before:
            break
    left, right, errors = before
    assert errors == 0                          # no edge came too close to another
    assert [left, right] == figures["pin_edges"] == figures["edges"]
    assert left > 5000 and right < -3000        # A leads B forward; B leads A back


def test_a_limit_switch_held_from_the_start_reads_low(simavr):
    sim = simavr(PINS_TEST, "--hold", "jaw")
    board = PinsTest(sim.path)
    assert board.limits() == 0b01               # arm open (pulled up), jaw held
    assert sim.figures()["limits_held"] == [0, 1]


def test_simulated_time_never_runs_ahead_and_a_stall_is_not_caught_up(simavr):
    sim = simavr(PINS_TEST)
    board = PinsTest(sim.path)
    board.wait_ticks(5)
    os.kill(sim.proc.pid, signal.SIGSTOP)       # the machine stalls half a second
    time.sleep(0.5)
    os.kill(sim.proc.pid, signal.SIGCONT)
    board.wait_ticks(5)
    figures = sim.stop()
    assert figures["sim_s"] <= figures["wall_s"] + 0.001
    # The half second was not run through later: the board lost it.
    assert figures["wall_s"] - figures["sim_s"] >= 0.45
    assert figures["rebases"] >= 1 and figures["lag_max_us"] >= 450000


def test_at_half_rate_the_board_runs_half_as_fast_as_the_wall_clock(simavr):
    sim = simavr(PINS_TEST, "--rate", "0.5")
    board = PinsTest(sim.path)
    board.wait_ticks(10)
    ticks = board.ticks()
    figures = sim.figures()
    assert figures["sim_s"] <= 0.5 * figures["wall_s"] + 0.001
    assert abs(ticks - figures["sim_s"] * 100) <= 1      # Timer1 runs on simulated time
