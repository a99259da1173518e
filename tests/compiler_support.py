"""Helpers the compiler tests share: a machine run compiled and by the
reference loop `run_from` with an interrupt source beside it, the
interrupt periods that fall at every offset of a short loop body, and
reading the Python a word becomes."""
import rcl

PRIM = 1_000_000


class Ticker:
    """An interrupt every `period` clock units that counts in Forth;
    optionally asks for a break (as Ctrl-C does) at its `brk`-th service."""

    def __init__(self, m, period, brk=None):
        self.xt = m.dictionary.find("TICK")[0]
        self.period, self.due, self.times, self.brk = period, period, [], brk

    def service(self, m):
        self.times.append(m.clock)
        self.due += self.period
        m.run_handler(self.xt)
        if len(self.times) == self.brk:
            m.request_break()


def run(program, word, compiled, period, brk=None):
    m = rcl.Forth()
    m.compiled = compiled
    m.evaluate("VARIABLE TICKS  : TICK  1 TICKS +! ;")
    m.evaluate(program)
    t = Ticker(m, period, brk)
    m.attach(t)
    try:
        out = m.evaluate(word)
    except rcl.ForthError as e:
        out = "error: %s" % e.message
    rs, mem = list(m.rs), bytes(m.mem)
    return out, m.stack, m.clock, t.times, m.evaluate("TICKS @ ."), m, rs, mem


def same_both_ways(program, word, periods, brk=None):
    for period in periods:
        a, b = (run(program, word, c, period, brk) for c in (True, False))
        assert a[:5] == b[:5], (word, period)
        assert a[3], "the interrupt source fired"
    return a[5]


# Interrupt periods that fall at every offset of a short loop body.
PERIODS = [k * PRIM + PRIM // 3 for k in (3, 4, 5, 6, 7, 11)] + [29 * PRIM]

def near_overflow(program, line, depths):
    """What line does at each return-stack depth in depths (its output or
    error, the depth, the stack, the clock), compiled and by the reference
    loop; -> ([compiled, reference], the compiled run's machine)."""
    out, machines = [], []
    for compiled in (True, False):
        m = rcl.Forth()
        m.compiled = compiled
        m.evaluate(program)
        seen = []
        for depth in depths:
            m.rs.extend([0] * depth)
            try:
                m.evaluate(line)
                seen.append(("ok", len(m.rs), m.stack))
            except rcl.ForthError as e:
                seen.append((e.message, m.stack))
            del m.rs[:], m.s[:]
            seen.append(m.clock)
        out.append(seen)
        machines.append(m)
    return out, machines[0]


def code_lines(text):
    """Lines of Python without their comments, blank lines and elisions."""
    out = []
    for line in text.splitlines():
        line = line.split("  #")[0].rstrip()
        if line.strip() and line.strip() != "...":
            out.append(line)
    return out


def in_order(wanted, lines):
    it = iter(lines)
    return all(any(w == line for line in it) for w in wanted)
