"""The board interface: all the Forth machine knows of a board.

    Forth machine --- out8/in8/out16/in16 (port I/O) ----> Board
                  --- far_fetch8/far_store8 (1 MiB space) ->
                  <-- due / service(machine) (interrupts) --
                  --- reads machine.clock (virtual time) --->

The machine calls `board.attach(machine)` once; from then on the board is
its interrupt source: `due` is the clock value (units of
primitives.CLOCK_HZ) at which the board next needs the CPU, or None, and
`service(machine)` runs then, with interrupts masked, on the handler's own
stacks (it may run Forth words with `machine.run_handler(xt)`).

Implementations: rcl.sim.board.SimBoard (the simulated R-E Robot board)
and, for a real board, rcl.hw's link. NullBoard below is what a bare
machine has: every port reads 0xFF (floating bus) and writes go nowhere.
"""

FORTH_CS = 0x1000      # the segment GET-CS returns: the Forth machine's 64 KiB


class Board:
    """Hooks every board provides (the base class says what each means).

    out8(port, byte)       8-bit OUT (PC!)
    in8(port) -> byte      8-bit IN (PC@), 0..255
    out16(port, word)      16-bit OUT (P!)
    in16(port) -> word     16-bit IN (P@)
    far_fetch8(seg, off) -> byte   a byte of the 80188's 1 MiB memory
    far_store8(seg, off, byte)
    attach(machine)        the machine plugs the board in
    due                    clock value of the next interrupt, or None
    service(machine)       handle what fell due (interrupts masked)
    stop_motors()          safe state, whatever happens (errors, Ctrl-C)
    tick_failed()          the interrupt handler failed: motors off, and no
                           more ticks until the software sets the timer again
    trace(file) -> rec     an observation hook: record each tick that changed
    """

    due = None
    machine = None

    def attach(self, machine):
        self.machine = machine
        machine.attach(self)

    def out8(self, port, byte):
        raise NotImplementedError

    def in8(self, port):
        raise NotImplementedError

    def out16(self, port, word):
        self.out8(port, word & 0xFF)
        self.out8((port + 1) & 0xFFFF, word >> 8)

    def in16(self, port):
        return self.in8(port) | (self.in8((port + 1) & 0xFFFF) << 8)

    def far_fetch8(self, seg, off):
        """Default: the Forth segment is the machine's memory; the rest floats."""
        if seg == FORTH_CS:
            return self.machine.mem[off]
        return 0xFF

    def far_store8(self, seg, off, byte):
        if seg == FORTH_CS:
            self.machine.memory.cstore(off, byte)

    def service(self, machine):
        pass

    def stop_motors(self):
        pass

    def tick_failed(self):
        self.stop_motors()

    def trace(self, file=None):
        """Start recording the board, a row per tick in which something
        changed (CSV to `file` if given); -> the recorder, with `rows`,
        `FIELDS` and `stop()` (rcl.track reads it), or None when this board
        keeps no trace."""
        return None


class NullBoard(Board):
    """No board at all: ports float, nothing interrupts."""

    def out8(self, port, byte):
        pass

    def in8(self, port):
        return 0xFF
