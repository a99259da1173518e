"""The CODE words of RCL: what the article wrote in 80188 assembly because
it runs inside the 10 ms interrupt (the position counters), plus the
delays ((MS), WAIT-UNTIL's skip): primitives that take the virtual time
their Forth loops would (docs/ARCHITECTURE.md, "Time").

They stay out of the dictionary until an RCL screen binds them with
`CODE name ... END-CODE`, as the original screens did.

Counter state lives in memory, in the screen's `CNT-STATE` (12 bytes per
wheel): previous forward and reverse counter values, then the 32-bit
forward and reverse totals (high cell first, as 2! keeps them).

How the primitives find RCL's variables without looking names up: a
table is itself a CODE word. `CODE CNT-STATE ... END-CODE 24 ALLOT`
binds the name to a primitive that pushes its body's address, as CREATE
would, and CODE records the word's xt in `m.xt_of` (kept by SAVE-SYSTEM),
so a primitive finds the body from the xt: one dictionary lookup of
Python's, at no virtual-time cost, and nothing added to MS or the tick.
Layer 9's `IDLE-CELLS` is such a table: its first cell is IDLE?'s xt,
laid down by the screen at load time (`' IDLE? , ...`), so (MS) asks the
screens' own idle rule (RCL's, whatever a user defines as IDLE? later),
and no copy of it is kept here.

The tick script: INIT-COUNTERS (INSTALL's on a board not yet set up) and
every check that the tick runs tell the board what RCL's handler reads
first, ?CNT1's and ?CNT2's latches and reads (board.tick_reads: a board
over a link does them at the tick and sends the bytes with it). So the
script, its ports and its order live here, beside the words that read.
"""
import struct

from rcl.board import FORTH_CS, IN8, OUT8
from rcl.errors import ForthError
from rcl.forth.memory import MASK
from rcl.forth.primitives import CALL, prim
from rcl.i80188 import (EN, INT, PCB_BASE, T0_CONTROL, TIMER_CONTROL_REG, TIMER_MASK,
                        VECTOR_USER_TICK, vector_address)

BASES = (0x80, 0x84)            # left and right 8253 (rcl/robot.py's port map)
CODE_COST = 60 * 36_000         # 60 us: latch and read two counters on the 80188


def table(m, name):
    """The body of the CODE table `name` (its xt recorded when CODE bound it)."""
    xt = m.xt_of.get(name)
    if xt is None:
        raise ForthError(-13, "?", name)
    return (xt + 2) & MASK


def code_table(name, effect):
    """Declare a table primitive: CODE name ... END-CODE, then its cells."""
    @prim(name, effect, hidden=True)
    def push_body(m):
        m.s.append(table(m, name))
    return push_body


code_table("CNT-STATE", "( -- addr ) per wheel: previous counts, 32-bit totals")
code_table("IDLE-CELLS", "( -- addr ) IDLE?'s xt, the idle rule (MS) asks; then "
           "the three variables IDLE? reads")


def state_addr(m):
    return table(m, "CNT-STATE")


@prim("INIT-COUNTERS", "( -- ) program both 8253s (0 mode 3, 1 and 2 mode 2), zero the totals",
      hidden=True, cost=CODE_COST)
def init_counters(m):
    b = m.board
    tell_tick_reads(m)
    for base in BASES:
        for control, counter in ((0x36, 0), (0x74, 1), (0xB4, 2)):
            b.out8(base + 3, control)
            b.out8(base + counter, 0)
            b.out8(base + counter, 0)
    m.memory.write(state_addr(m), bytes(24))


COUNTER_READS = tuple(((OUT8, base + 3, 0x40), (OUT8, base + 3, 0x80),   # latch 1, latch 2
                       (IN8, base + 1, 0), (IN8, base + 1, 0),         # counter 1 LSB MSB
                       (IN8, base + 2, 0), (IN8, base + 2, 0))         # counter 2 LSB MSB
                      for base in BASES)
TICK_READS = COUNTER_READS[0] + COUNTER_READS[1]


def tell_tick_reads(m):
    """The board learns what RCL's tick handler reads first (a board that
    runs the handler itself ignores it; a link sends it once a session)."""
    m.board.tick_reads(TICK_READS)


STATE = struct.Struct("<HHHHHH")    # prev fwd, prev rev, fwd total hi lo, rev total hi lo


def read_position(m, wheel):
    """Latch and read one wheel's counters, add the pulses since the last
    read to the 32-bit totals (fewer than 32,768 a read: 13 s at the top
    speed, and the tick reads every 10 ms); -> forward minus reverse, as a
    32-bit value."""
    r = m.board.port_script(COUNTER_READS[wheel])
    fwd, rev = r[0] | (r[1] << 8), r[2] | (r[3] << 8)
    a = state_addr(m) + 12 * wheel
    mem = m.memory
    prev_f, prev_r, fhi, flo, rhi, rlo = STATE.unpack(mem.read(a, 12))
    total_f = (((fhi << 16) | flo) + counted(prev_f, fwd)) & 0xFFFFFFFF
    total_r = (((rhi << 16) | rlo) + counted(prev_r, rev)) & 0xFFFFFFFF
    if fwd != prev_f or rev != prev_r:   # else the state stays byte for byte
        mem.write(a, STATE.pack(fwd, rev, total_f >> 16, total_f & MASK,
                                total_r >> 16, total_r & MASK))
    return (total_f - total_r) & 0xFFFFFFFF


def counted(prev, now):
    """Pulses a down-counter counted from prev to now, signed: over a link
    to a free-running board a tick's script reads can reach the handler
    after a later foreground read; such an older value takes those counts
    back rather than adding 65536."""
    return ((prev - now + 0x8000) & MASK) - 0x8000


@prim("?CNT1", "( -- d ) motor 1 (left) position in encoder counts, + forward",
      hidden=True, cost=CODE_COST)
def q_cnt1(m):
    d = read_position(m, 0)
    m.s.extend((d & MASK, d >> 16))


@prim("?CNT2", "( -- d ) motor 2 (right) position in encoder counts, + forward",
      hidden=True, cost=CODE_COST)
def q_cnt2(m):
    d = read_position(m, 1)
    m.s.extend((d & MASK, d >> 16))


# ------------------------------------------------------------ the tick
PCB_T0_CONTROL = PCB_BASE + T0_CONTROL
PCB_TIMER_MASK = PCB_BASE + TIMER_CONTROL_REG
USER_TICK_VECTOR = vector_address(VECTOR_USER_TICK)     # INT 1Ch in segment 0


def user_tick(m):
    """(seg, off) of the INT 1Ch vector, read as the 80188 would."""
    b = m.board
    v = [b.far_fetch8(0, USER_TICK_VECTOR + i) for i in range(4)]
    return v[2] | (v[3] << 8), v[0] | (v[1] << 8)


def check_ticking(m):
    """Abort unless timer 0 runs and interrupts, unmasked, and INT 1Ch is a
    Forth word: unless something can run every tick."""
    b = m.board
    tell_tick_reads(m)
    control, mask = b.in16(PCB_T0_CONTROL), b.in16(PCB_TIMER_MASK)
    if (control & (EN | INT)) != EN | INT or mask & TIMER_MASK \
            or user_tick(m)[0] != FORTH_CS:
        raise ForthError(-2, "Control loop not running (INSTALL starts it)")


@prim("?TICKING", "( -- ) abort unless timer 0 interrupts, unmasked, into a "
      "Forth word on INT 1Ch (a wait could not end otherwise)", hidden=True, cost=CODE_COST)
def q_ticking(m):
    check_ticking(m)


def idle_rule(m):
    """The xt of RCL's IDLE? (IDLE-CELLS' first cell): the one rule, in the
    screens, of when every tick's handler would only read."""
    return m.memory.fetch(table(m, "IDLE-CELLS"))


@prim("(MS)", "( n -- ) Listing 3's MS in virtual time: 37 primitives a "
      "millisecond, interrupts stealing time as they would", hidden=True, kind=CALL)
def paren_ms(m):
    # : MS  0 ?DO 33 0 DO LOOP LOOP ;  costs 4 + 37n primitives; `: MS (MS) ;`
    # already spent 3 (the call, (MS) itself, EXIT), so spend the rest.
    n = 1 + 37 * m.s.pop()
    check_ticking(m)
    m.spend_waiting(n, idle_rule(m))


@prim("(SKIP-TO-TICK)", "( d -- ) let the time of day run to BIOS tick d at once, "
      "INT 1Ch idle (only when nothing moves)", hidden=True, kind=CALL)
def skip_to_tick(m):
    hi, lo = m.s.pop(), m.s.pop()
    if m.fast_forward is not None:    # else the waiting loop waits tick by tick
        m.fast_forward.skip_to_tick((hi << 16) | lo)
