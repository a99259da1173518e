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
import shutil
import signal
import struct
import subprocess
import time

import pytest
import serial

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIMAVR_DIR = os.path.join(ROOT, "firmware", "simavr")
HARNESS = os.path.join(SIMAVR_DIR, "build", "rcl-simavr")
PINS_TEST = os.path.join(SIMAVR_DIR, "build", "pins-test.elf")
INSTALL = ("apt-get install --no-install-recommends gcc-avr avr-libc binutils-avr "
           "libsimavr-dev")


def missing_toolchain():
    """What is missing to build the harness and AVR images, or None."""
    missing = [tool for tool in ("make", "cc", "avr-gcc") if shutil.which(tool) is None]
    if not os.path.exists("/usr/include/simavr/sim_avr.h"):
        missing.append("simavr's headers")
    return missing or None


@pytest.fixture(scope="module")
def harness_built():
    missing = missing_toolchain()
    if missing:
        pytest.skip("simavr tests need %s: %s" % (", ".join(missing), INSTALL))
    run = subprocess.run(["make", "-C", SIMAVR_DIR], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout + run.stderr
    return HARNESS


class Simavr:
    """An rcl-simavr process; its first line of output is its pty."""

    def __init__(self, tmp_path, elf, *args):
        self.stats_path = tmp_path / ("stats-%d.json" % id(self))
        self.proc = subprocess.Popen(
            [HARNESS, "--quiet", "--stats", str(self.stats_path), *args, elf],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True)
        self.pty = self.proc.stdout.readline().strip()

    def command(self, line):
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()

    def stats(self):
        """The harness's figures now (true edges, ticks, bytes each way)."""
        self.command("stats")
        return json.loads(self.proc.stdout.readline())

    def stop(self):
        """Stop it; -> its last figures."""
        if self.proc.poll() is None:
            self.proc.terminate()
            self.proc.wait(10)
        return json.loads(self.stats_path.read_text())


@pytest.fixture
def simavr(harness_built, tmp_path):
    started = []

    def start(elf, *args):
        started.append(Simavr(tmp_path, elf, *args))
        return started[-1]
    yield start
    for s in started:
        if s.proc.poll() is None:
            s.proc.kill()
            s.proc.wait(10)


# ------------------------------------------- the harness, on its own program
class PinsTest:
    """firmware/simavr/test/pins.c over the harness's pty."""

    def __init__(self, sim):
        self.sim = sim
        self.port = serial.Serial(sim.pty, 115200, timeout=5)

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


def test_the_harness_prints_its_pty_first_and_carries_bytes_both_ways(simavr):
    sim = simavr(PINS_TEST)
    assert sim.pty.startswith("/dev/pts/")
    board = PinsTest(sim)
    noise = bytes(b for b in range(256) if b not in b"mcts")
    board.port.write(noise)
    assert board.port.read(len(noise)) == noise
    figures = sim.stop()
    assert figures["bytes_to_board"] == figures["bytes_from_board"] == len(noise)
    assert figures["dropped_to_board"] == 0


def test_pwm_duty_and_the_l298n_inputs_set_each_models_drive(simavr):
    sim = simavr(PINS_TEST)
    board = PinsTest(sim)
    board.drive(63, -127)                       # OCR0B 127, OCR0A 255: fast PWM
    board.wait_ticks(1)
    assert sim.stats()["drive"] == [128 / 256, -1.0]
    board.drive(0, 0)                           # IN1 = IN2: no drive
    board.wait_ticks(1)
    assert sim.stats()["drive"] == [0.0, 0.0]


def test_every_edge_the_motor_model_makes_reaches_the_pin_change_interrupt(simavr):
    sim = simavr(PINS_TEST)
    board = PinsTest(sim)
    board.drive(127, -90)                       # left forward at full speed
    board.wait_ticks(50)                        # 0.5 s: 5,600 edges and more
    board.drive(0, 0)
    board.wait_ticks(50)                        # ten time constants: at rest
    while True:                                 # one reading between two equal ones
        before = board.edges()
        figures = sim.stats()
        if board.edges() == before:
            break
    left, right, errors = before
    assert errors == 0                          # no edge came too close to another
    assert [left, right] == figures["pin_edges"] == figures["edges"]
    assert left > 5000 and right < -3000        # A leads B forward; B leads A back


def test_a_held_limit_switch_reads_low_and_a_released_one_high(simavr):
    sim = simavr(PINS_TEST, "--hold", "jaw")
    board = PinsTest(sim)
    assert board.limits() == 0b01               # arm released (high), jaw held
    sim.command("hold arm")
    sim.command("release jaw")
    board.wait_ticks(1)
    assert board.limits() == 0b10
    assert sim.stats()["limits_held"] == [1, 0]


def test_simulated_time_never_runs_ahead_and_a_stall_is_not_caught_up(simavr):
    sim = simavr(PINS_TEST)
    board = PinsTest(sim)
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
    board = PinsTest(sim)
    board.wait_ticks(10)
    ticks = board.ticks()
    figures = sim.stats()
    assert figures["sim_s"] <= 0.5 * figures["wall_s"] + 0.001
    assert abs(ticks - figures["sim_s"] * 100) <= 1      # Timer1 runs on simulated time
