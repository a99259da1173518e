"""What a test, a notebook or the prompt sees of the simulated robot, in
inches, degrees and seconds, and the faults it can inject.

    m = rcl.open();  sim = m.sim
    sim.pose            (x, y, heading): inches, inches, degrees
    sim.wheel_counts    (left, right): encoder counts, forward minus reverse
    sim.arm, sim.jaw    lift height and jaw opening, inches
    sim.seconds         the virtual clock
    sim.stall("left")   a fault: the wheel is blocked
    sim.load("left", 0.5), sim.encoder("left", counting=False)   more faults
"""
import csv

from rcl.board import CLOCK_HZ
from rcl.sim import constants as C

WHEELS = ("left", "right")


class Sim:
    """The observation and fault-injection face of a SimBoard."""

    def __init__(self, board):
        self.board = board
        self.drive = board.drive

    def wheel(self, name):
        if name not in WHEELS:
            raise ValueError("a wheel is 'left' or 'right', not %r" % (name,))
        return getattr(self.drive, name)

    # ------------------------------------------------------- observation
    @property
    def seconds(self):
        return self.board.machine.clock / CLOCK_HZ

    @property
    def pose(self):
        self.board.sync()                 # the robot now, not at the last port access
        r = self.drive.robot
        return (r.x, r.y, r.heading)

    @property
    def wheel_counts(self):
        self.board.sync()
        return (self.drive.left.position, self.drive.right.position)

    @property
    def wheel_rates(self):
        """Encoder counts per second, signed."""
        self.board.sync()
        return (self.drive.left.rate, self.drive.right.rate)

    @property
    def references(self):
        """The PLL reference frequencies, Hz."""
        return self.board.refs

    @property
    def relays(self):
        return self.board.motor_latch, self.board.aux_latch

    @property
    def arm(self):
        self.board.sync()
        return self.drive.lift.position

    @property
    def jaw(self):
        self.board.sync()
        return self.drive.gripper.opening

    @property
    def beeps(self):
        """(start, end) seconds of each beep; end None while it sounds."""
        return [(s / CLOCK_HZ, None if e is None else e / CLOCK_HZ)
                for s, e in self.board.beeps]

    @property
    def ticks(self):
        return self.board.ticks

    @property
    def overruns(self):
        return self.board.overruns

    @property
    def bios_ticks(self):
        return self.board.time_of_day()[0]

    def counter(self, side, n):
        """The 8253 counter n (0 speed, 1 forward, 2 reverse) of a wheel."""
        base = C.LEFT_8253 if side == "left" else C.RIGHT_8253
        self.board.sync()
        return self.board.chips[base].counters[n]

    def run(self, seconds):
        """Let virtual time pass with the machine idle (interrupts still run)."""
        m = self.board.machine
        m.advance_to(m.clock + round(seconds * CLOCK_HZ))
        self.board.sync()

    # ------------------------------------------------------------ faults
    def stall(self, wheel, stalled=True):
        self.board.sync()
        self.wheel(wheel).stalled = stalled

    def load(self, wheel, fraction):
        """A drag, as a fraction of the motor's torque (0 none, 1 stuck)."""
        self.board.sync()
        self.wheel(wheel).load = fraction

    def encoder(self, wheel, counting=True):
        """counting False: the wheel turns as before, but its encoder's
        pulses no longer reach the 8253 (a cut wire); True mends it."""
        self.wheel(wheel)                 # a wheel's name, checked
        self.board.sync()                 # the pulses up to now still count
        self.board.connect_encoder(WHEELS.index(wheel), counting)

    def block_gripper(self, width):
        """An object between the jaws: they cannot close below `width` in."""
        self.board.sync()
        self.drive.gripper.object_width = width

    def charger(self, on=True):
        self.board.sync()
        self.drive.charger = on

    def place(self, x=0.0, y=0.0, heading=0.0):
        r = self.drive.robot
        r.x, r.y, r.heading = x, y, heading


class Trace:
    """One CSV row per tick in which something changed (so a whole day does
    not make gigabytes): time, pose, wheel counts, references, relays, arm,
    jaw, beeper. Attach with `Trace(board, file)`; rows go to `file` (any
    text stream) and to `rows` when `keep` is true (rcl.track reads them);
    `stop()` detaches it.

    It needs only the ticks in which something changes, so it does not
    stop the board from counting idle ticks in one go (`changes_only`)."""

    FIELDS = ["t", "x", "y", "heading", "left", "right", "ref_left", "ref_right",
              "motor", "aux", "arm", "jaw", "beeper"]
    changes_only = True

    def __init__(self, board, file=None, keep=False):
        self.board = board
        self.file = file
        self.writer = csv.writer(file) if file is not None else None
        if self.writer:
            self.writer.writerow(self.FIELDS)
        self.rows = [] if keep else None
        self.last = None
        board.sync()
        self(board)                       # where it starts
        board.observers.append(self)

    def state(self, board):
        # the beeper sounds exactly while its latch bit is set (the drive's
        # own flag is brought up to date only while something moves)
        d = board.drive
        ref = board.refs
        return (round(d.robot.x, 4), round(d.robot.y, 4), round(d.robot.heading, 4),
                d.left.position, d.right.position, round(ref[0], 3), round(ref[1], 3),
                board.motor_latch, board.aux_latch, round(d.lift.position, 4),
                round(d.gripper.opening, 4), int(bool(board.aux_latch & C.BEEPER)))

    def __call__(self, board):
        state = self.state(board)
        if state == self.last:
            return
        self.last = state
        row = (round(board.machine.clock / CLOCK_HZ, 6),) + state
        if self.writer:
            self.writer.writerow(row)
        if self.rows is not None:
            self.rows.append(row)

    tick = __call__

    def stop(self):
        """Detach from the board (the rows kept stay)."""
        if self in self.board.observers:
            self.board.observers.remove(self)
        if self.file is not None:
            self.file.flush()
