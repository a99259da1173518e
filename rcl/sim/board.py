"""The simulated R-E Robot control board: the one table that maps ports to
chips, the 80188's 1 MiB memory, the simulated BIOS, and the physics, all
driven by the Forth machine's virtual clock.

    port        chip                             (names in rcl/robot.py)
    0x80-0x83   I8253 #1: left speed ref, left fwd/rev encoder counts
    0x84-0x87   I8253 #2: right speed ref, right fwd/rev encoder counts
    0x88        MOTOR latch (write-only)   0x89 AUX latch (write-only)
    0x8A        STATUS (read-only)
    0xFF00-FF   80188 peripheral control block (timers, interrupt controller)
    other       floating bus: reads 0xFF, writes ignored

    linear memory (seg * 16 + off)
    0x00000     vector table (type 8 timer 0 at 0x20, 1Ch user tick at 0x70)
    0x00400     BIOS data area: tick count 0040:006C, midnight flag 0040:0070,
                ticks per day 0040:00F0 (our BIOS's switch, see below)
    0x10000     the Forth machine's 64 KiB (segment FORTH_CS = 0x1000)
    elsewhere   reads 0xFF

Time is lazy: each chip is brought up to `machine.clock` when it is
touched, and the physics when an interrupt is serviced or a port access
must see it or changes what it sees: a new speed reference, a relay, an
encoder counter latched or read unlatched, STATUS. A write that changes
nothing the physics sees (a count's first byte, the same count again, the
same relays) and a read of a latched counter cost no physics at all.
Physics runs in 1 ms sub-steps (10 per RCL tick) and jumps straight over
stretches in which nothing moves, or in which the wheels hold their rates
(their state a closed form of the time, motors.Stretch); so when it is
brought up changes no bit of it.

The simulated BIOS (Python, not Forth) is the type-8 handler: it adds one
to the 32-bit tick count, wraps it at the ticks-per-day value (1,573,040 at
power-on, 8,640,000 once RCL's INSTALL stores that at 0040:00F0: the "new
BIOS-level handler" of the article), runs INT 1Ch, and sends the EOI.
INT 1Ch pointing into the Forth segment runs that Forth word; anything
else is taken as the power-on IRET.
"""
import collections
import functools
import struct

from rcl.board import CLOCK_HZ, FORTH_CS, OUT8, Board
from rcl.i80188 import (BIOS_IRET, BIOS_SEG, BIOS_TIMER, EOI_REG, EOI_TIMER,
                         MIDNIGHT_ADDR, PER_DAY_ADDR, T0_CONTROL, TICKS_ADDR)
from rcl.sim import constants as C
from rcl.sim.i8253 import I8253
from rcl.sim.motors import Drive
from rcl.sim.timer80188 import (INH as INH_BIT, INT as INT_BIT, P as P_BIT, T0_CLOCK,
                                TIMER_CLOCK, Timer80188)

MS = CLOCK_HZ // 1000                     # clock units per physics sub-step
SKIP_CHUNK = CLOCK_HZ                     # skip_to_tick: physics and Ctrl-C each virtual second
LOW_RAM = 0x10000                         # segment 0's 64 KiB
DWORD = struct.Struct("<I")              # the BIOS's 32-bit counts
NO_MOTION = ((0, 0), (0, 0))             # no pulses from either wheel


def cut_wire(n):
    """An encoder's line cut (the "encoder" fault): its n pulses reach no counter."""


class SimBoard(Board):
    """The default board: everything a user's RCL program drives."""

    def __init__(self, port_log=False):
        self.clock = 0                    # the time chips and physics are at
        self.pcb = Timer80188.power_on(0)
        self._new_chips(0)
        self.drive = Drive()
        self.motor_latch = 0
        self.aux_latch = 0
        self.low = bytearray(LOW_RAM)
        self.physics_ms = 0
        self.ticks = 0                    # timer-0 interrupts serviced
        self.overruns = 0                 # handlers still running at the next tick
        # (clock, port, value) of the last 100,000 writes, only when asked
        # for (rcl-board's --report): nobody else reads it
        self.port_log = collections.deque(maxlen=100_000) if port_log else None
        self.beeps = []                   # [start, end] in clock units
        self.observers = []               # callables(board) after each tick
        self.pacer = None                 # real-time pacing, when set
        self.refs = (0.0, 0.0)            # the PLL reference frequencies, Hz
        self.quiet = False                # INT 1Ch skipped (skip_to_tick)
        self.handler_cost = None          # clock units the last INT 1Ch handler took
        self.due = None                   # the next interrupt (refresh_due)
        self._power_on_bios()

    def attach(self, machine):
        self.machine = machine
        self.due = self.pcb.next_interrupt(self.pcb_time())
        machine.fast_forward = self       # waits may count idle ticks out (below)
        machine.attach(self)

    def _power_on_bios(self):
        self.set_vector(C.VECTOR_TIMER0, BIOS_SEG, BIOS_TIMER)
        self.set_vector(C.VECTOR_USER_TICK, BIOS_SEG, BIOS_IRET)
        self.low_store32(PER_DAY_ADDR, C.TICKS_PER_DAY_BIOS)

    # ------------------------------------------------------------ memory
    def low_fetch32(self, a):
        return DWORD.unpack_from(self.low, a)[0]

    def low_store32(self, a, v):
        DWORD.pack_into(self.low, a, v & 0xFFFFFFFF)

    def time_of_day(self):
        return self.low_fetch32(TICKS_ADDR), max(1, self.low_fetch32(PER_DAY_ADDR))

    def set_time_of_day(self, ticks):
        self.low_store32(TICKS_ADDR, ticks)

    def set_vector(self, n, seg, off):
        self.low[4 * n:4 * n + 4] = off.to_bytes(2, "little") + seg.to_bytes(2, "little")

    def vector(self, n):
        """(seg, off) of interrupt type n."""
        v = self.low[4 * n:4 * n + 4]
        return v[2] | (v[3] << 8), v[0] | (v[1] << 8)

    def far_fetch8(self, seg, off):
        a = ((seg << 4) + off) & 0xFFFFF
        if a < LOW_RAM:
            return self.low[a]
        if a < 2 * LOW_RAM:
            return self.machine.mem[a - LOW_RAM]
        return 0xFF

    def far_store8(self, seg, off, byte):
        a = ((seg << 4) + off) & 0xFFFFF
        if a < LOW_RAM:
            self.low[a] = byte
        elif a < 2 * LOW_RAM:
            self.machine.memory.cstore(a - LOW_RAM, byte)

    # ------------------------------------------------------------- ports
    def _new_chips(self, now):
        """Both 8253s as at power-on, wired through the chip's own interface:
        the 125 kHz clock to each counter 0 (its pulses counted from now),
        each wheel's encoder to counters 1 and 2 (forward, reverse), the
        port map to their addresses."""
        self.chips = {C.LEFT_8253: I8253(), C.RIGHT_8253: I8253()}
        self.ref_clk = {base: chip.clk(0) for base, chip in self.chips.items()}
        self.clk0 = {base: now * C.F_8253_CLK // CLOCK_HZ for base in self.chips}   # pulses delivered
        self.encoders = tuple(self.chips[base].clk(i) for base in (C.LEFT_8253, C.RIGHT_8253)
                              for i in (1, 2))
        self.writers, self.readers = self._port_map()

    def _port_map(self):
        """The board's port decoding, once: port -> what a write of a byte
        does (byte, now) and what a read gives (now). The PCB's 256 ports
        are decoded apart; any other port floats."""
        writers, readers = {}, {}
        for base, chip in self.chips.items():
            write, read, acts = chip.port(0)
            writers[base] = functools.partial(self._write_reference, base, write, acts)
            writers[base + 3] = functools.partial(self._write_control, base)
            readers[base] = functools.partial(self._read_reference, base, read)
            readers[base + 3] = self._read_control
            for offset in (1, 2):
                write, read, _ = chip.port(offset)
                writers[base + offset] = functools.partial(self._write_encoder, write)
                readers[base + offset] = functools.partial(self._read_encoder, read)
        writers[C.MOTOR_PORT] = functools.partial(self._latch, C.MOTOR_PORT)
        writers[C.AUX_PORT] = functools.partial(self._latch, C.AUX_PORT)
        readers[C.STATUS_PORT] = self._read_status
        return writers, readers

    def out8(self, port, byte):
        write = self.writers.get(port) if self.port_log is None else None
        if write is not None:             # (straight to the port map: PC! runs often)
            write(byte, self.machine.clock)
        else:
            self._out8(port, byte, self.machine.clock)

    def _out8(self, port, byte, now):
        if self.port_log is not None:
            self.port_log.append((now, port, byte))
        write = self.writers.get(port)
        if write is not None:
            write(byte, now)
        elif port >= C.PCB_BASE:
            old = self.pcb.read16(port & 0xFE, self.pcb_time(now))
            word = (old & 0xFF00) | byte if not port & 1 else (old & 0xFF) | (byte << 8)
            self._pcb_write(port & 0xFE, word, now)

    def in8(self, port):
        read = self.readers.get(port)
        if read is not None:
            return read(self.machine.clock)
        return self._in8(port, self.machine.clock)

    def _in8(self, port, now):
        """A read of a port the port map does not hold."""
        if port >= C.PCB_BASE:
            word = self.pcb.read16(port & 0xFE, self.pcb_time(now))
            return word >> 8 if port & 1 else word & 0xFF
        return 0xFF                       # unused ports and write-only latches float

    def _write_reference(self, base, write, acts, byte, now):
        """Counter 0, the speed reference: a count's byte."""
        if not acts(byte):                  # CLK may catch up later, as if before
            write(byte)
            return
        self._clock_ref(base, now)
        if write(byte):
            self._new_references(now)

    def _write_control(self, base, byte, now):
        if not byte & 0xC0:                 # counter 0's mode: maybe a new reference
            self._clock_ref(base, now)
            self.chips[base].write_control(byte)
            self._new_references(now)
        else:                               # counters 1 and 2: their pulses up to now first
            self.sync_to(now)
            self.chips[base].write_control(byte)

    def _new_references(self, now):
        refs = self.references()
        if refs != self.refs:               # the physics up to now at the old speeds
            self.sync_to(now)
            self.refs = refs

    def _write_encoder(self, write, byte, now):
        self.sync_to(now)
        write(byte)

    def _read_reference(self, base, read, now):
        self._clock_ref(base, now)
        return read()

    def _read_control(self, now):
        return I8253.CONTROL_READ           # write-only

    def _read_encoder(self, read, now):
        # The pulses up to now (the tick's reads follow their latch at the
        # same instant, which brought the physics there already: no work)
        self.sync_to(now)
        return read()

    def _read_status(self, now):
        self.sync_to(now)
        return self.drive.status_byte(*self.refs)

    def out16(self, port, word):
        if port >= C.PCB_BASE:            # the PCB takes whole words
            now = self.machine.clock
            if self.port_log is not None:
                self.port_log.append((now, port, word))
            self._pcb_write(port & 0xFFFE, word, now)
        else:                             # external: two byte cycles
            super().out16(port, word)

    def in16(self, port):
        if port >= C.PCB_BASE:
            return self.pcb.read16(port & 0xFE, self.pcb_time(self.machine.clock))
        return super().in16(port)

    def port_script(self, ops):
        """The ops at one moment, each as out8/in8 would do it then (straight
        from the port map where it has the port and no log is kept)."""
        now, reads = self.machine.clock, []
        writers = self.writers if self.port_log is None else {}
        readers = self.readers
        for op, port, value in ops:
            if op == OUT8:
                write = writers.get(port)
                if write is not None:
                    write(value, now)
                else:
                    self._out8(port, value, now)
            else:
                read = readers.get(port)
                reads.append((read(now) if read is not None else self._in8(port, now)) & 0xFF)
        return reads

    def _pcb_write(self, offset, word, now):
        self.pcb.write16(offset & 0xFF, word, self.pcb_time(now))
        self.refresh_due()                # the next interrupt may have moved

    def _latch(self, port, byte, now):
        """The MOTOR or AUX latch (the beeper's times kept)."""
        if byte != (self.motor_latch if port == C.MOTOR_PORT else self.aux_latch):
            self.sync_to(now)                   # the physics up to now on the old relays
        if port == C.MOTOR_PORT:
            self.motor_latch = byte
        else:
            if (byte ^ self.aux_latch) & C.BEEPER:
                if byte & C.BEEPER:
                    self.beeps.append([now, None])
                elif self.beeps:
                    self.beeps[-1][1] = now
            self.aux_latch = byte

    def _clock_ref(self, base, now):
        """Bring counter 0 (the 125 kHz speed reference) up to now."""
        pulses = now * C.F_8253_CLK // CLOCK_HZ
        self.ref_clk[base](pulses - self.clk0[base])
        self.clk0[base] = pulses

    def references(self):
        """The two PLL reference frequencies, Hz (0 if not running)."""
        chips = self.chips
        return (chips[C.LEFT_8253].out_frequency(0, C.F_8253_CLK),
                chips[C.RIGHT_8253].out_frequency(0, C.F_8253_CLK))

    # ----------------------------------------------------------- physics
    def sync(self):
        """Bring the physics up to the machine's clock; -> the clock."""
        now = self.machine.clock
        self.sync_to(now)
        return now

    def sync_to(self, now):
        """Bring the physics up to clock `now` (the last whole millisecond)."""
        target = now // MS
        if self.physics_ms < target:      # else already there (most port accesses)
            self.physics_to(target)
        self.clock = now

    def physics_to(self, target):
        """Physics up to millisecond `target`: jumped over while nothing
        moves, else as Drive.advance makes it: 1 ms at a time while a rate
        changes, in closed form once the wheels hold their rates
        (motors.Stretch: the same bits however the stretch is cut). The
        milliseconds' pulses reach the 8253s together at the end: nothing
        reads a counter in between, and n CLKs at once count as n one at a
        time. So the moments at which the physics is brought up change
        nothing."""
        drive = self.drive
        if not (drive.left.rate or drive.right.rate) and self.still():   # a turning wheel never is
            self.physics_ms = target
            return
        pulses = drive.advance(target - self.physics_ms, self.motor_latch, self.aux_latch, *self.refs)
        self.physics_ms = target
        if pulses != NO_MOTION:
            self.deliver(pulses)

    def still(self):
        """The physics' own fact: nothing moves and nothing would start
        moving (no wheel turns, no motor is driven, arm, gripper and
        beeper off). Not RCL's idle rule (IDLE?, in the screens: the tick
        handler has nothing to do), which the machine asks; a tick's reads
        repeat only when both hold."""
        d, m = self.drive, self.motor_latch
        if d.left.rate or d.right.rate or self.aux_latch & (C.ARM_ON | C.GRIP_ON | C.BEEPER):
            return False
        f_left, f_right = self.refs
        return not ((m & C.M1_ON and m & C.M1_GO and f_left and not d.left.stalled)
                    or (m & C.M2_ON and m & C.M2_GO and f_right and not d.right.stalled))

    def deliver(self, pulses):
        (lf, lr), (rf, rr) = pulses
        left_fwd, left_rev, right_fwd, right_rev = self.encoders
        if lf:
            left_fwd(lf)
        if lr:
            left_rev(lr)
        if rf:
            right_fwd(rf)
        if rr:
            right_rev(rr)

    # -------------------------------------------------------- interrupts
    def refresh_due(self):
        """The next interrupt moves only when the PCB is written or serviced:
        compute it then, not on every look."""
        self.due = self.pcb.next_interrupt(self.pcb_time())
        if self.machine is not None:
            self.machine.reschedule()

    def pcb_time(self, now=None):
        """The clock to ask the PCB at: after batched ticks it may be ahead of
        the machine, and nothing happens in between."""
        if now is None:
            now = self.clock if self.machine is None else self.machine.clock
        c = self.pcb.clock
        return now if now > c else c

    def service(self, m):
        """An interrupt request: the simulated BIOS handles timer 0. The EOI
        and the next due time are restored whatever the handler does (a
        fault in it still ends the interrupt, as the BIOS's IRET would).
        The physics is not brought up here: the handler's own port accesses
        do it as far as they need, and the observers see it at the end."""
        at = self.pcb_time(m.clock)
        kind = self.pcb.acknowledge(at)
        if kind != C.VECTOR_TIMER0:
            if kind is not None:                # timers 1 and 2: nothing hangs there
                self.pcb.write16(EOI_REG, 0x8000, self.pcb_time(m.clock))
            self.due = self.pcb.next_interrupt(self.pcb_time(m.clock))
            return
        self.ticks += 1
        nxt = self.pcb.upcoming(at)                     # the next tick's time
        try:
            self.bios_tick(m)
        except BaseException:
            self.end_of_interrupt(m)
            raise
        self.pcb.write16(EOI_REG, EOI_TIMER, self.pcb_time(m.clock))
        if self.batch_idle_ticks(m):
            nxt = self.pcb.next_interrupt(self.pcb_time(m.clock))
        self.due = nxt
        if nxt is not None and nxt < m.clock:
            self.overruns += 1
        if self.observers:
            self.sync()                   # they see the robot at the handler's end
        for observe in self.observers:
            observe(self)
        if self.pacer is not None:
            self.pacer.wait(m.clock)

    def end_of_interrupt(self, m):
        """The EOI, and the next interrupt from there (after a handler
        failed: it may have left the timer anywhere)."""
        self.pcb.write16(EOI_REG, EOI_TIMER, self.pcb_time(m.clock))
        self.due = self.pcb.next_interrupt(self.pcb_time(m.clock))

    def batch_idle_ticks(self, m):
        """While the machine only waits and INT 1Ch does nothing, every tick
        up to the end of the wait would just count: count them at once.
        (Each would have run at its own time with the same result.)"""
        target = m.waiting_until
        if target is None or self.pacer is not None \
                or (self.vector(C.VECTOR_USER_TICK)[0] == FORTH_CS and not self.quiet) \
                or not self.observers_allow_batching():
            return False
        n = self.pcb.take_timer0_requests(target)
        self.ticks += n
        self.count_ticks(n)
        return n > 0

    def observers_allow_batching(self):
        """No observer needs to see each of the idle ticks about to be
        counted at once: a Trace (`changes_only`) needs only the ticks in
        which something changes, none while all is idle, so it is shown
        the idle state the stretch starts from, now."""
        if any(not getattr(o, "changes_only", False) for o in self.observers) \
                or (self.observers and not self.still()):
            return False
        for observe in self.observers:
            observe(self)
        return True

    def count_ticks(self, n):
        """Add n ticks to the BIOS time of day, wrapping at midnight (flag set)."""
        per_day = max(1, self.low_fetch32(PER_DAY_ADDR))
        count = self.low_fetch32(TICKS_ADDR) + n
        if count >= per_day:
            self.low[MIDNIGHT_ADDR] = 1
        self.low_store32(TICKS_ADDR, count % per_day)

    def tick_period(self):
        """Clock units between timer-0 ticks (prescaled by timer 2 or not)."""
        t0 = self.pcb.timers[0]
        return t0.limit() * (T0_CLOCK if t0.control & P_BIT else TIMER_CLOCK)

    def bios_tick(self, m):
        """Type 8: count the tick (midnight wrap), then INT 1Ch."""
        self.count_ticks(1)
        seg, off = self.vector(C.VECTOR_USER_TICK)
        if seg == FORTH_CS and not self.quiet:
            start = m.clock
            m.run_handler(off)
            self.handler_cost = m.clock - start

    # ------------------------------------------------------- fast-forward
    # What this board gives its machine as machine.fast_forward (rcl.sim's
    # capability, not the board interface's): waits that count idle ticks
    # in arithmetic, exactly as ticking through would leave everything.
    # The machine asks RCL's own rule (the screens' IDLE?) before it calls
    # repeat_idle_ticks, and hands it all it needs; this board adds only
    # its own facts (nothing moves, no observer or pacer needs each tick,
    # a handler timed in this wait).

    def skip_to_tick(self, target):
        """Let the time of day run until the BIOS count is one short of
        target, with INT 1Ch idle but for that last tick: for a program that only waits
        while nothing moves (its tick handler would find nothing to do).
        The count, the timer and the clock end where ticking through would
        have left them; only the handler's idle runs are not made."""
        m = self.machine
        per_day = max(1, self.low_fetch32(PER_DAY_ADDR))
        n = (target - self.low_fetch32(TICKS_ADDR)) % per_day
        if n < 2 or self.due is None:
            return
        # Stop one tick short, that tick run as usual: the waiting loop
        # takes the last one itself, exactly as it would have.
        period = self.tick_period()
        last = max(m.clock, self.due) + (n - 2) * period
        self.quiet = True
        try:
            # Every tick but the last, INT 1Ch idle; the physics brought up a
            # second at a time (a relay may be on: a day of it in one go took
            # minutes, deaf to Ctrl-C), which advance_to takes between ticks.
            while m.clock < last - 1:
                m.advance_to(min(last - 1, m.clock + SKIP_CHUNK))
                self.sync()
        finally:
            self.quiet = False
        m.advance_to(last)                    # the last one as usual
        self.sync()

    def repeat_idle_ticks(self, clock, n, c, limit):
        """The foreground spends n primitives of c clock units from `clock`
        while every tick's handler would take the same path and the same
        time as the last one (the machine asked RCL's IDLE?: the handler
        only reads; and nothing moves). Count it out tick by tick in
        arithmetic instead of running it, stopping before a handler would
        reach `limit` (the step budget): the same BIOS count and timer
        state, the physics up to there. -> (the clock reached, primitives
        left): (clock, n) when it cannot."""
        cost, d = self.handler_cost, self.due
        period = self.tick_period()
        if cost is None or d is None or cost >= period \
                or self.pacer is not None or not self.still() \
                or not self.observers_allow_batching():
            return clock, n
        clock, n, ticks, last = count_out(clock, n, c, d, period, cost, limit)
        if ticks:
            self.pcb.take_timer0_requests(last)
            self.pcb.acknowledge(last)
            self.pcb.write16(EOI_REG, EOI_TIMER, last)
            self.ticks += ticks
            self.count_ticks(ticks)
        self.due = self.pcb.next_interrupt(self.pcb_time(clock))
        self.sync_to(clock)
        return clock, n

    def wait_started(self):
        self.handler_cost = None          # trust only a tick timed in this wait

    def pose(self):
        self.sync()
        r = self.drive.robot
        return (r.x, r.y, r.heading)

    def trace(self, file=None):
        from rcl.sim.observe import Trace     # observe builds on this module
        return Trace(self, file, keep=True)

    def inject_fault(self, fault, wheel, value):
        """The prompt's fault words, as the Python API's (rcl.sim.observe.Sim)."""
        from rcl.sim.observe import Sim
        sim = Sim(self)
        if fault == "stall":
            sim.stall(wheel, bool(value))
        elif fault == "load":
            sim.load(wheel, value / 100)
        elif fault == "encoder":
            sim.encoder(wheel, bool(value))
        else:
            raise ValueError("no fault %r" % (fault,))

    def connect_encoder(self, side, counting):
        """Wheel `side` (0 left, 1 right): its encoder's pulses reach its
        8253's counters 1 and 2, or (counting false) no counter at all."""
        chip = self.chips[(C.LEFT_8253, C.RIGHT_8253)[side]]
        wires = list(self.encoders)
        wires[2 * side:2 * side + 2] = (chip.clk(1), chip.clk(2)) if counting \
            else (cut_wire, cut_wire)
        self.encoders = tuple(wires)

    def stop_motors(self):
        """Safe state: every relay open (wheels braked, arm and gripper off),
        from now: the physics runs up to now on the relays as they were."""
        if self.machine is not None:
            self.sync()
        self.motor_latch = 0
        self.aux_latch &= ~(C.ARM_ON | C.GRIP_ON | C.BEEPER)

    def power_on(self):
        """A reset, as a new session on a served board has it: the
        electronics as at power-on (relays open, the 80188's timers and
        interrupt controller as the BIOS leaves them, both 8253s unset, the
        vector table and BIOS data area new) from now, the physics brought
        up to now first; the robot itself stays where it stands."""
        now = self.pcb_time()
        self.stop_motors()
        self.aux_latch = 0
        self.pcb = Timer80188.power_on(now)
        self._new_chips(now)
        self.refs = (0.0, 0.0)
        self.low = bytearray(LOW_RAM)
        self._power_on_bios()
        self.ticks = 0
        self.quiet, self.handler_cost = False, None
        self.refresh_due()

    def tick_failed(self):
        """The INT 1Ch handler failed: relays open, and timer 0 no longer
        interrupts (its INT bit cleared, as INT-OFF does) until the software
        sets it up again."""
        self.stop_motors()
        now = self.pcb_time()
        control = self.pcb.read16(T0_CONTROL, now)
        self.pcb.write16(T0_CONTROL, (control & ~INT_BIT) | INH_BIT, now)
        self.pcb.drop_requests(0, now)
        self.refresh_due()


def count_out(clock, n, c, d, period, cost, limit):
    """n primitives of c clock units from `clock`, a tick due at d and every
    period after, each tick's handler taking `cost`, all before `limit`
    (a step budget): -> (clock, primitives left, ticks, the last one's due
    time or None). As the loop below would, primitive by primitive; once
    the ticks come at a steady rhythm, whole runs of them at once."""
    ticks, last, jumped = 0, None, False
    while n > 0:
        if ticks and not jumped and period - cost >= c and d > clock:
            jumped = True                         # each tick now comes after >= 1 primitive
            j, used = ticks_before(d - clock, n, c, period, cost, limit - clock)
            if j:
                clock += used * c + j * cost
                n -= used
                ticks, last, d = ticks + j, d + (j - 1) * period, d + j * period
                continue
        k = max(0, -(-(d - clock) // c))          # primitives until the tick
        if k >= n:
            return clock + n * c, 0, ticks, last
        if clock + k * c + cost >= limit:
            break
        clock += k * c + cost                     # run up to it, then the handler
        n -= k
        ticks, last, d = ticks + 1, d, d + period
    return clock, n, ticks, last


def ticks_before(r, n, c, period, cost, room):
    """How many ticks count_out's loop takes when the first is r > 0 clock
    units away and each next one comes period - cost after the last handler
    ends (at least c): the most j whose primitives K(j) are fewer than n
    and whose time K(j)*c + j*cost is within room; -> (j, K(j)).
    The primitive before tick i overshoots it by e_i = (-r_i) mod c, and
    r_(i+1) = period - cost - e_i, so e_i = (e_1 + (i-1)(cost - period))
    mod c and K(j) = (r + (j-1)(period - cost) + e_j) / c: searched by
    bisection."""
    e1 = -r % c

    def used(j):
        return (r + (j - 1) * (period - cost) + (e1 + (j - 1) * (cost - period)) % c) // c

    lo, hi = 0, n                                 # j = n needs at least n primitives
    while hi - lo > 1:
        mid = (lo + hi) // 2
        k = used(mid)
        if k < n and k * c + mid * cost < room:
            lo = mid
        else:
            hi = mid
    return lo, used(lo) if lo else 0
