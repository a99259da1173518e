"""The 80188's three timers and the interrupt-controller registers they use.

One chip of the simulated board, as Intel's 80186/80188 data sheet has it:
the timer unit of the peripheral control block (PCB, I/O 0xFF00-0xFFFF)
and the part of the interrupt controller that handles the shared timer
request. Registers are 16-bit and addressed by their offset from the PCB
base; every access carries the virtual clock, and the chip brings itself
up to that clock by arithmetic (division per access, no loop per clock or
per expiry), so a long idle wait costs the same as a short one.

    offset  register                 offset  register
    0x50    timer 0 count            0x22    EOI (write 0x8000 or 0x0008)
    0x52    timer 0 max count A      0x28    interrupt mask (bit 0 = timers)
    0x54    timer 0 max count B      0x2C    in-service (bit 0 = timers)
    0x56    timer 0 control          0x2E    request (bit 0 = timers)
    0x58..0x5E  timer 1, the same    0x30    interrupt status (bits 2-0 =
    0x60    timer 2 count                    timer 2/1/0 request latched)
    0x62    timer 2 max count        0x32    timer interrupt control
    0x66    timer 2 control                  (bit 3 mask, bits 2-0 priority)

Timer control register (timer 2 has only EN, INH, INT, MC and CONT):

     15   14   13   12   11 .. 6   5    4    3    2    1    0
    +----+----+----+----+--------+----+----+----+----+----+----+
    | EN |INH |INT |RIU |   -    | MC |RTG | P  |EXT |ALT |CONT|
    +----+----+----+----+--------+----+----+----+----+----+----+
      |    |    |    |             |    |    |    |    |    +- restart after max count
      |    |    |    |             |    |    |    |    +------ alternate max count A / B
      |    |    |    |             |    |    |    +----------- count the external pin
      |    |    |    |             |    |    +---------------- count timer 2 expiries
      |    |    |    |             |    +--------------------- retrigger (pin, unused)
      |    |    |    |             +-------------------------- set at max count
      |    |    |    +---------------------------------------- read-only: B in use
      |    |    +--------------------------------------------- request an interrupt
      |    +-------------------------------------------------- write EN only if 1; reads 0
      +------------------------------------------------------- counting enabled

Datasheet facts modelled [INTEL]:
  * counts UP from 0 on each input clock; when the count equals the max
    count in use (0 = 65,536) the timer expires: MC is set, a request is
    latched if INT = 1, the count restarts at 0; the period is exactly
    "max count" input clocks. A count already past the max wraps at 0xFFFF.
  * input clock: CPU/4 = 2 MHz (timer 2 always; timers 0/1 with P = EXT = 0),
    or timer 2 expirations (P = 1, EXT = 0), or the external pin (EXT = 1).
  * ALT alternates max count A and B, RIU shows which one is in use;
    without CONT the timer stops (EN cleared) after one expiry, or after
    the A-then-B pair when ALT = 1.
  * EN changes only in a write that also has INH = 1; INH reads 0.
  * the three timers share one request line, one mask bit (0x28 bit 0 is
    0x32 bit 3), one in-service bit and one EOI type (8); acknowledge
    serves timer 0 before 1 before 2 and gives type 8, 18 or 19.
  * an EOI, non-specific (0x8000) or specific with type 8 (0x0008),
    clears the in-service bit; until then no further timer interrupt.
  * reset state: timers stopped and zero, timer interrupt masked
    (0x32 = 0x000F, 0x28 = 0x00FD).

NOTES (not modelled):
  * the timer input and output pins: EXT timers never count; the input pin
    is taken as held high, so RTG's gate and retrigger never act; no output
    waveforms.
  * the one- to four-clock synchronisation delays of the real part: a
    change takes effect at the next 2 MHz edge.
  * the other interrupt sources (DMA 0/1, INT0-INT3), priority resolution
    between them, the priority-mask and poll registers, special fully
    nested and slave modes; writes to the request, in-service and status
    registers (they are read-only here).
  * DMA, chip selects, PCB relocation (the offsets are fixed from 0xFF00).
  * a request latched while masked or in service stays latched; all the
    requests of one timer since its last acknowledge make one interrupt,
    and the extra ones are counted in `missed`.
"""
from rcl.errors import RclError
from rcl.board import CLOCK_HZ
from rcl.i80188 import (ALT, CONT, EN, EOI_NONSPECIFIC, EOI_REG, EOI_TIMER, EXT,  # noqa: F401
                        IN_SERVICE_REG, INH, INT, MASK_REG, MC, P, PCB_BASE, REQUEST_REG,
                        RIU, RTG, STATUS_REG, TIMER_CONTROL_REG, TIMER_MASK, TIMER_TYPES,
                        TMR_BIT)

# ---------------------------------------------------------------------------
# CONSTANTS (tags as in rcl/sim/constants.py)
# ---------------------------------------------------------------------------

CPU_HZ = 8_000_000                  # 80188 clock [PROPOSAL]
TIMER_HZ = CPU_HZ // 4              # internal timer clock, 2 MHz [INTEL]
TIMER_CLOCK = CLOCK_HZ // TIMER_HZ  # 18,000 units = 0.5 us per timer clock
T2_PRESCALE = 3                     # timer 2 max count: 2 MHz / 3 [PROPOSAL]
T0_CLOCK = TIMER_CLOCK * T2_PRESCALE  # 54,000 units = 1.5 us [ARTICLE]
T0_BIOS_COUNT = 36_617              # power-on max count, 54.9255 ms [PROPOSAL]
T0_RCL_COUNT = 6667                 # RCL's max count, 10.0005 ms [ARTICLE]
COUNT_RANGE = 0x10000               # a max count of 0 means 65,536

T01_BITS = INT | MC | RTG | P | EXT | ALT | CONT   # writable besides EN
T2_BITS = INT | MC | CONT

T0_RUNNING = EN | INH | INT | P | CONT   # 0xE009, RCL's INT-ON
T0_INT_OFF = EN | INH | P | CONT         # 0xC009, RCL's INT-OFF: keeps counting
T2_RUNNING = EN | INH | CONT             # 0xC001, the prescaler

# Interrupt controller values (the registers are rcl/i80188.py's)
PRIORITY_BITS = 0x0007
RESET_TIMER_CONTROL = 0x000F        # masked, priority 7
RESET_MASK = 0x00FD                 # every source masked

TIMER_REGISTERS = {                 # offset -> (timer, Timer attribute)
    0x50: (0, "count"), 0x52: (0, "max_a"), 0x54: (0, "max_b"), 0x56: (0, "control"),
    0x58: (1, "count"), 0x5A: (1, "max_a"), 0x5C: (1, "max_b"), 0x5E: (1, "control"),
    0x60: (2, "count"), 0x62: (2, "max_a"), 0x66: (2, "control"),
}

# Input clock sources
INTERNAL, PRESCALED, EXTERNAL = "internal", "prescaled", "external"


def clocks_to_expiry(count, limit):
    """Input clocks from `count` until it next equals the max count `limit`
    (a count past the max wraps at 0xFFFF)."""
    return (limit - count) % COUNT_RANGE or COUNT_RANGE


class error(RclError):
    """A misuse of the timer chip (time running backwards)."""


# ---------------------------------------------------------------------------
# ONE TIMER: counting in input clocks, no notion of time
# ---------------------------------------------------------------------------

class Timer:
    """One 16-bit timer; `advance(n)` counts n input clocks at once."""

    def __init__(self, number):
        self.number = number
        self.bits = T2_BITS if number == 2 else T01_BITS
        self.count = 0
        self.max_a = 0
        self.max_b = 0
        self.control = 0            # EN, RIU and the `bits`; never INH
        self.expiries = 0           # every expiry since reset
        self.requests = 0           # expiries with INT since the last acknowledge
        self.pending_at = None      # clock of the oldest unacknowledged request

    def has(self, bit):
        return bool(self.control & bit)

    def source(self):
        if self.number == 2 or not (self.control & (EXT | P)):
            return INTERNAL
        return EXTERNAL if (self.control & (EXT)) else PRESCALED

    def write_control(self, word):
        """EN only along with INH; RIU is read-only and stays only under ALT."""
        writable = self.bits | (EN if word & INH else 0)
        kept = (self.control & ~writable) & (EN | (RIU if word & ALT else 0))
        self.control = kept | (word & writable)

    def limit(self, use_b=None):
        """The max count in use (or A/B if asked), 0 read as 65,536."""
        use_b = (self.control & (RIU)) if use_b is None else use_b
        return (self.max_b if use_b else self.max_a) or COUNT_RANGE

    def steps_to_expiry(self, limit=None):
        """Input clocks until the count next equals the max count (`limit`
        if the caller has it)."""
        return clocks_to_expiry(self.count, limit or self.limit())

    def advance(self, n):
        """Count n input clocks; return (expiries, input clock of the first)."""
        if not n or not (self.control & (EN)):
            return 0, None
        limit = self.limit()
        d, first, total = self.steps_to_expiry(limit), None, 0
        if n < d:                   # most calls: no expiry on the way
            self.count = (self.count + n) & 0xFFFF
            return 0, None
        if self.control & (CONT | ALT) == CONT:
            # One max count, restarting (every tick's timers): the loop
            # below in closed form, the expiry at d, then whole periods.
            periods, self.count = divmod(n - d, limit)
            self.expiries += 1 + periods
            self.control |= MC
            return 1 + periods, d
        while (self.control & (EN)) and n >= d:
            n -= d
            first = first or d
            total += 1
            self.expire()
            n, skipped = self.skip_periods(n)
            total += skipped
            d = self.steps_to_expiry()
        if (self.control & (EN)):
            self.count = (self.count + n) & 0xFFFF
        return total, first

    def expire(self):
        """The count reached the max count: restart, set MC, maybe stop."""
        self.count = 0
        self.expiries += 1
        self.control |= MC
        if (self.control & (ALT)):
            self.control ^= RIU
        if not (self.control & (CONT)) and not (self.control & (RIU)):
            self.control &= ~EN

    def skip_periods(self, n):
        """From count 0, skip whole periods of n clocks: (n left, expiries)."""
        if not (self.control & (CONT)):
            return n, 0
        per_cycle = 2 if (self.control & (ALT)) else 1
        cycle = self.limit(False) + self.limit(True) if (self.control & (ALT)) else self.limit()
        k = n // cycle
        self.expiries += k * per_cycle
        return n - k * cycle, k * per_cycle


# ---------------------------------------------------------------------------
# THE CHIP: timers on the virtual clock, plus the interrupt controller
# ---------------------------------------------------------------------------

class Timer80188:
    """The PCB timers and timer interrupt plumbing; offsets from 0xFF00.

    read16(offset, now) -> word     write16(offset, word, now)
    next_interrupt(now) -> clock of the next timer interrupt request, or None
    acknowledge(now) -> interrupt type (8, 18, 19), or None if none pending
    timer0_expiries, missed         counters for tests
    """

    def __init__(self, now=0):
        self.clock = now            # the chip is up to date at this clock
        self.timers = [Timer(0), Timer(1), Timer(2)]
        self.timer_control = RESET_TIMER_CONTROL
        self.other_masks = RESET_MASK & ~TMR_BIT
        self.in_service = False
        self.missed = 0

    @classmethod
    def power_on(cls, now=0):
        """The chip as the board BIOS leaves it (docs/protocol.md section 6,
        "Sessions": timer 2 prescaling by 3, timer 0 at 36,617 counts)."""
        chip = cls(now)
        chip.write16(0x62, T2_PRESCALE, now)
        chip.write16(0x66, T2_RUNNING, now)
        chip.write16(0x52, T0_BIOS_COUNT, now)
        chip.write16(0x56, T0_RUNNING, now)
        chip.write16(TIMER_CONTROL_REG, 0x0000, now)
        return chip

    @property
    def timer0_expiries(self):
        return self.timers[0].expiries

    @property
    def masked(self):
        return bool(self.timer_control & TIMER_MASK)

    # -- register access ---------------------------------------------------

    def read16(self, offset, now):
        self.catch_up(now)
        timer, field = self.decode_timer(offset)
        if timer is not None:
            return getattr(timer, field)
        return self.read_controller(offset)

    def write16(self, offset, word, now):
        word &= 0xFFFF
        timer, field = self.decode_timer(offset)
        if timer is None:
            # The interrupt controller: requests are latched lazily with their
            # own times, so the timers need not be brought up to now.
            self.write_controller(offset, word)
            return
        self.catch_up(now)
        if field == "control":
            timer.write_control(word)
        elif timer is not None:
            setattr(timer, field, word)
        else:
            self.write_controller(offset, word)

    def decode_timer(self, offset):
        """(timer, attribute) for a timer register offset, else (None, None)."""
        if offset not in TIMER_REGISTERS:
            return None, None
        number, field = TIMER_REGISTERS[offset]
        return self.timers[number], field

    def read_controller(self, offset):
        pending = [t.pending_at is not None for t in self.timers]
        values = {
            MASK_REG: self.other_masks | (TMR_BIT if self.masked else 0),
            IN_SERVICE_REG: TMR_BIT if self.in_service else 0,
            REQUEST_REG: TMR_BIT if any(pending) else 0,
            STATUS_REG: sum(1 << i for i, p in enumerate(pending) if p),
            TIMER_CONTROL_REG: self.timer_control,
        }
        return values.get(offset, 0)

    def write_controller(self, offset, word):
        if offset == EOI_REG and word in (EOI_NONSPECIFIC, EOI_TIMER):
            self.in_service = False
        elif offset == MASK_REG:
            self.other_masks = word & 0x00FF & ~TMR_BIT
            self.set_mask(word & TMR_BIT)
        elif offset == TIMER_CONTROL_REG:
            self.timer_control = word & (TIMER_MASK | PRIORITY_BITS)

    def set_mask(self, on):
        self.timer_control = (self.timer_control & ~TIMER_MASK) | (TIMER_MASK if on else 0)

    # -- interrupts --------------------------------------------------------

    def next_interrupt(self, now):
        """Clock of the next timer interrupt request (maybe already past)."""
        self.catch_up(now)
        if self.masked or self.in_service:
            return None
        return self.next_request()

    def upcoming(self, now):
        """Clock of the next timer request, in service or not (as
        next_interrupt would give once the EOI is sent)."""
        self.catch_up(now)
        return None if self.masked else self.next_request()

    def next_request(self):
        """The clock of the first latched request, else of the soonest
        expiry that will request (None if none will): the chip is up to
        date and neither masked nor in service."""
        first = None                # a latched request comes first
        for t in self.timers:
            at = t.pending_at
            if at is not None and (first is None or at < first):
                first = at
        if first is not None:
            return first
        prescaler = None
        for t in self.timers:       # else the soonest expiry that requests
            if t.control & EN and t.control & INT:
                if prescaler is None:
                    prescaler = self.prescaler()
                at = self.next_expiry(t, prescaler)
                if at is not None and (first is None or at < first):
                    first = at
        return first

    def acknowledge(self, now):
        """The CPU takes the timer interrupt: return its type, set in-service."""
        self.catch_up(now)
        for timer in self.timers:           # timer 0 before 1 before 2
            if timer.pending_at is not None:
                break
        else:
            return None
        self.missed += max(0, timer.requests - 1)
        timer.requests, timer.pending_at = 0, None
        self.in_service = True
        return TIMER_TYPES[timer.number]

    def drop_requests(self, number, now):
        """Forget timer `number`'s latched requests (a safe state that must
        not run the failed handler once more for a tick already past)."""
        self.catch_up(now)
        timer = self.timers[number]
        timer.requests, timer.pending_at = 0, None

    def take_timer0_requests(self, now):
        """Catch up to now and take all but the latest timer-0 request as
        handled (for a board that has nothing to do on them); -> how many.
        The latest stays pending, to be acknowledged as usual."""
        self.catch_up(now)
        t0 = self.timers[0]
        n = max(0, t0.requests - 1)
        t0.requests -= n
        return n

    def next_expiry(self, timer, prescaler=None):
        """Clock of the timer's next expiry from the present state, or None."""
        edge = self.input_edge(timer, timer.steps_to_expiry(), prescaler or self.prescaler())
        return None if edge is None else (self.clock // TIMER_CLOCK + edge) * TIMER_CLOCK

    # -- lazy time ---------------------------------------------------------

    def prescaler(self, state=None):
        """Timer 2 as a clock source: (on, first expiry edge, period,
        continuous), from its (count, control) now or as given."""
        t2 = self.timers[2]
        count, control = (t2.count, t2.control) if state is None else state
        period = t2.limit()                 # timer 2 has no max count B
        return control & EN, clocks_to_expiry(count, period), period, control & CONT

    def input_edge(self, timer, k, prescaler):
        """2 MHz edge (1 = the next one) of the timer's k-th input clock, or None."""
        source = timer.source()
        if source == INTERNAL:
            return k
        on, first, period, cont = prescaler
        if source == PRESCALED and on and (k == 1 or cont):
            return first + (k - 1) * period
        return None

    def catch_up(self, now):
        """Bring every timer from self.clock up to `now` in O(1)."""
        if now == self.clock:
            return
        if now < self.clock:
            raise error("timer read at %d, before its clock %d" % (now, self.clock))
        base = self.clock // TIMER_CLOCK
        edges = now // TIMER_CLOCK - base
        if not edges:               # no 2 MHz edge in between: nothing counts
            self.clock = now
            return
        t0, t1, t2 = self.timers
        t2_before = t2.count, t2.control    # what a timer it prescales (P) counted
        ticks2, first2 = t2.advance(edges)
        if ticks2 and t2.control & INT:
            self.latch(t2, ticks2, first2, base)
        for timer in (t0, t1):
            if not timer.control & EN:      # a stopped timer neither counts nor requests
                continue
            source = timer.source()
            if source == EXTERNAL:          # the pin never counts here
                continue
            n = edges if source == INTERNAL else ticks2
            if not n:
                continue
            expired, first = timer.advance(n)
            if expired and timer.control & INT:
                prescaler = self.prescaler(t2_before) if source == PRESCALED else None
                self.latch(timer, expired, self.input_edge(timer, first, prescaler), base)
        self.clock = now

    def latch(self, timer, expired, first_edge, base):
        """Record the interrupt requests of `expired` expiries of `timer`
        (one with INT set: the caller checked)."""
        timer.requests += expired
        if timer.pending_at is None:
            timer.pending_at = (base + first_edge) * TIMER_CLOCK
