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
    machine.budget_end       where the foreground's step budget ends
    machine.advance_to(t)    wait until t, servicing interrupts on the way
    machine.catch_up(t)      the board accounted for the time up to t itself
                             (idle ticks counted in arithmetic): move to t
    machine.reschedule()     `due` changed: recompute the next deadline
    machine.run_handler(xt)  from service(): run the Forth word xt
    machine.request_stop(e)  raise error e at the foreground's next
                             primitive boundary (a lost link)
    machine.in_forth, .masked  Forth is running (a word, or a handler)
    machine.in_safe_state    the abort hooks run (after an error, Ctrl-C)
    machine.mem, machine.memory.cstore   the Forth segment's 64 KiB

Implementations: rcl.sim.board.SimBoard (the simulated R-E Robot board),
rcl.hw.link.LinkBoard (a board at the other end of a serial link) and
NullBoard below, what a bare machine has: every port reads 0xFF (floating
bus) and writes go nowhere.
"""

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
    Safety
      stop_motors()        safe state, whatever happens (errors, Ctrl-C)
      tick_failed()        the tick handler failed: motors off, no more
                           ticks until the software sets the timer again
      reconnect()          a board on a link: connect again (RECONNECT)
    Time shortcuts (a board may decline each; the result is the same)
      wait_started()       a wait begins: forget handler timings from before
      repeat_idle_ticks(n, c) -> primitives left
      skip_to_tick(target) let the time of day run to a BIOS tick at once
    Observation
      trace(file) -> recorder, or None
      status() -> a line for the prompt's status, or ""
      explain(error) -> the error to report (a cause the board knows)
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

    # -------------------------------------------------------------- safety
    def stop_motors(self):
        """Every motor and relay off."""

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

    # ------------------------------------------------------ time shortcuts
    def wait_started(self):
        """A wait (MS) begins: timings learnt before it are not trusted."""

    def repeat_idle_ticks(self, n, c):
        """The foreground spends n primitives of c clock units while every
        tick's handler only reads (the caller checked). A board that can
        count such ticks in arithmetic does, and moves the clock with
        machine.catch_up; -> the primitives left (n: declined)."""
        return n

    def skip_to_tick(self, target):
        """Let the time of day run until one tick short of BIOS tick
        `target` at once, INT 1Ch idle (nothing moves). Declining is
        correct: the waiting loop then waits tick by tick."""

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


class NullBoard(Board):
    """No board at all: ports float, nothing interrupts."""

    def out8(self, port, byte):
        pass

    def in8(self, port):
        return 0xFF
