"""The board interface: all the Forth machine knows of a board, and all a
board knows of the machine.

    Forth machine --- out8/in8/out16/in16 (port I/O) ----> Board
                  --- far_fetch8/far_store8 (1 MiB space) ->
                  <-- due / service(machine) (interrupts) --
                  --- the time API below ------------------->

The machine calls `board.attach(machine)` once; from then on the board is
its interrupt source: `due` is the clock value (units of CLOCK_HZ) at which
the board next needs the CPU, or None, and `service(machine)` runs then,
with interrupts masked, on the handler's own stacks.

What a board may use of the machine (rcl.forth.inner.Inner documents each;
the machine owns its clock and no board assigns it):

    machine.clock            virtual time now, in units of CLOCK_HZ (read only)
    machine.waiting_until    while a waiting word skips ahead, where it stops
    machine.advance_to(t)    wait until t, servicing interrupts on the way
    machine.catch_up(t)      the board accounted for the time up to t itself
                             (its own clock, on a link): move to t
    machine.reschedule()     `due` changed: recompute the next deadline
    machine.run_handler(xt)  from service(): run the Forth word xt
    machine.request_stop(e)  raise error e at the foreground's next
                             primitive boundary (a lost link)
    machine.in_forth, .masked  Forth is running (a word, or a handler)
    machine.in_safe_state    the abort hooks run (after an error, Ctrl-C)
    machine.mem, machine.memory.cstore   the Forth segment's 64 KiB

Speed is not a board's business: a simulated board may also give its
machine a fast-forward for waits (machine.fast_forward, rcl/forth/inner.py),
which is rcl.sim's capability, not part of this interface.

Implementations: rcl.sim.board.SimBoard (the simulated R-E Robot board),
rcl.hw.link.LinkBoard (a board at the other end of a serial link) and
NullBoard below, what a bare machine has: every port reads 0xFF (floating
bus) and writes go nowhere.
"""

from rcl.errors import RclError
from rcl.i80188 import PER_DAY_ADDR, TICKS_ADDR

FORTH_CS = 0x1000      # the segment GET-CS returns: the Forth machine's 64 KiB
CLOCK_HZ = 36_000_000_000    # virtual clock units per second (1/36 ns each)
OUT8, IN8 = 0, 1             # the operations of port_script


class Board:
    """Every hook a board offers, each with a plain default; SimBoard,
    LinkBoard and NullBoard override what they have.

    Port I/O and memory
      out8(port, byte), in8(port) -> byte      8-bit OUT and IN (PC! PC@)
      out16(port, word), in16(port) -> word    16-bit (P! P@): two byte cycles
      far_fetch8(seg, off), far_store8(...)    the 80188's 1 MiB memory
      port_script(ops) -> reads                several as one (nothing between)
    Interrupts
      attach(machine), due, service(machine)
      ticks                timer-0 ticks serviced so far
      tick_reads(ops)      the port operations the tick handler starts with
                           (a port_script): a board over a link does them
                           at the tick and sends their results with it
    Safety
      stop_motors()        safe state, whatever happens (errors, Ctrl-C)
      tick_failed()        the tick handler failed: motors off, no more
                           ticks until the software sets the timer again
      reconnect()          a board on a link: connect again (RECONNECT)
      close()              leaving: a board on a link is left safe and quiet
                           (no tick) and its port closed
    Time of day
      time_of_day() -> (ticks, per_day)   the BIOS's count since midnight
      set_time_of_day(ticks)
    Observation
      trace(file) -> recorder, or None
      status() -> a line for the prompt's status, or ""
      pose() -> (x in, y in, heading deg) of the robot now, or None
      explain(error) -> the error to report (a cause the board knows)
    Faults (an optional capability: the simulated board has it)
      inject_fault(fault, wheel, value)   "stall", "load" or "encoder"
    """

    due = None
    machine = None
    ticks = 0

    def attach(self, machine):
        self.machine = machine
        machine.attach(self)

    # ------------------------------------------------------------ port I/O
    def out8(self, port, byte):
        raise NotImplementedError

    def in8(self, port):
        raise NotImplementedError

    def out16(self, port, word):
        self.out8(port, word & 0xFF)
        self.out8((port + 1) & 0xFFFF, word >> 8)

    def in16(self, port):
        return self.in8(port) | (self.in8((port + 1) & 0xFFFF) << 8)

    def port_script(self, ops):
        """Run port operations as one, nothing else touching the ports in
        between (as a CODE word's instructions run): ops are (OUT8, port,
        value) and (IN8, port, 0); -> the bytes read, in order. On a link
        it is one frame, so a tick cannot come between a latch and its read."""
        reads = []
        for op, port, value in ops:
            if op == OUT8:
                self.out8(port, value)
            else:
                reads.append(self.in8(port) & 0xFF)
        return reads

    def far_fetch8(self, seg, off):
        """Default: the Forth segment is the machine's memory; the rest floats."""
        if seg == FORTH_CS:
            return self.machine.mem[off]
        return 0xFF

    def far_store8(self, seg, off, byte):
        if seg == FORTH_CS:
            self.machine.memory.cstore(off, byte)

    # ---------------------------------------------------------- interrupts
    def service(self, machine):
        """What fell due at `due`; must move `due` on (None: nothing more)."""

    def tick_reads(self, ops):
        """The software says what its tick handler reads first, every tick
        (port_script's ops). A board that runs the handler itself has
        nothing to do with it."""

    # -------------------------------------------------------------- safety
    def stop_motors(self):
        """Every motor and relay off."""

    def close(self):
        """Leaving rcl: nothing to do for a board in this process."""

    def tick_failed(self):
        """The interrupt handler failed: motors off and, on a board that
        ticks, no more ticks until the software sets the timer again."""
        self.stop_motors()

    def explain(self, error):
        """-> the error to report for `error`: itself, unless the board
        knows its cause better (a link whose host answered ticks late)."""
        return error

    def reconnect(self):
        """Connect again to a board that was lost; -> a line saying what
        happened. A board without a link has nothing to reconnect."""
        return "No link to reconnect"

    # --------------------------------------------------------- time of day
    def time_of_day(self):
        """(BIOS ticks since midnight, ticks per day), read from the BIOS
        data area as the 80188 would; a board may answer from its own."""
        return self.far_fetch32(TICKS_ADDR), max(1, self.far_fetch32(PER_DAY_ADDR))

    def set_time_of_day(self, ticks):
        """Set the BIOS tick count (ticks since midnight, below per day)."""
        for i in range(4):
            self.far_store8(0, TICKS_ADDR + i, (ticks >> 8 * i) & 0xFF)

    def far_fetch32(self, off):
        """A 32-bit cell of segment 0, low byte first."""
        return sum(self.far_fetch8(0, off + i) << 8 * i for i in range(4))

    # --------------------------------------------------------- observation
    def trace(self, file=None):
        """Start recording the board, a row per tick in which something
        changed (CSV to `file` if given); -> the recorder, with `rows`,
        `FIELDS` and `stop()` (rcl.track reads it), or None when this board
        keeps no trace."""
        return None

    def status(self):
        """One line about the board for a status display, or ""."""
        return ""

    def pose(self):
        """Where the robot is now, (x, y, heading) in inches and degrees, if
        this board can see it (the simulated one); else None."""
        return None

    # --------------------------------------------------------------- faults
    def inject_fault(self, fault, wheel, value):
        """Put a fault on the board's hardware, for the prompt's fault words:
        `fault` "stall" (value true: the wheel is blocked), "load" (a drag,
        value in percent of the motor's torque, 0 to 100) or "encoder"
        (value false: the wheel's encoder stops counting), on `wheel`
        "left" or "right". A board that cannot (a real one: its faults are
        real) raises NoFaults."""
        raise NoFaults("Faults are injected on the simulated board only")


class NoFaults(RclError):
    """This board has no fault injection (Board.inject_fault)."""


class NullBoard(Board):
    """No board at all: ports float, nothing interrupts."""

    def out8(self, port, byte):
        pass

    def in8(self, port):
        return 0xFF
