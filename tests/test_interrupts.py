"""The machine's time and interrupt hooks (DESIGN decisions 3 and 4),
tested with a periodic interrupt source of our own: the 80188 timer
arrives with the simulated board."""
import pytest

import rcl

PRIM = 1_000_000            # clock units of one primitive at 1000/36 us
MS = 36_000_000             # clock units in a millisecond


class Ticker:
    """Every `period` clock units, run the Forth word `xt` as a handler."""

    def __init__(self, period, xt):
        self.period, self.xt = period, xt
        self.due = period
        self.times = []
        self.depth = 0
        self.nested = False

    def service(self, m):
        self.times.append(m.clock)
        self.nested |= self.depth > 0
        self.depth += 1
        self.due += self.period
        m.run_handler(self.xt)
        self.depth -= 1


def machine(compiled=True):
    m = rcl.Forth()
    m.compiled = compiled
    m.evaluate("VARIABLE TICKS  : TICK  1 TICKS +! ;")
    return m


def ticker(m, period, word="TICK"):
    t = Ticker(period, m.dictionary.find(word)[0])
    m.attach(t)
    return t


def test_every_primitive_adds_the_default_cost_to_the_virtual_clock():
    # Listing 3's millisecond: LIT LIT (DO) and 33 (LOOP)s are 36 primitives.
    m = rcl.Forth()
    m.evaluate(": 1MS  33 0 DO LOOP ;")
    before = m.clock
    m.evaluate("1MS")
    assert m.clock - before == 36 * PRIM + 2 * PRIM    # + the call and EXIT
    assert 36 * PRIM == MS


def test_a_primitive_can_be_given_its_own_cost():
    m = rcl.Forth()
    m.set_cost("DUP", 100)                              # microseconds
    m.evaluate(": X  DUP DROP ;  1")
    before = m.clock
    m.evaluate("X")
    assert m.clock - before == 100 * 36_000 + 3 * PRIM   # DUP + call, DROP, EXIT


@pytest.mark.parametrize("compiled", [True, False])
def test_the_handler_runs_at_the_first_primitive_boundary_after_each_period(compiled):
    m = machine(compiled)
    t = ticker(m, 37 * PRIM + PRIM // 3)
    m.evaluate(": BUSY  2000 0 DO LOOP ;  BUSY")
    assert len(t.times) >= 50
    for i, when in enumerate(t.times):
        due = (i + 1) * t.period
        assert 0 <= when - due < PRIM
    assert m.evaluate("TICKS @ .") == "%d " % len(t.times)


def test_compiled_code_takes_interrupts_between_the_same_primitives_as_the_reference_loop():
    program = (": INNER  DUP 3 * 7 MOD + ;  DEFER VIA  ' INNER IS VIA"
               "  : WORK  0 500 0 DO I VIA DUP 1 AND IF 1+ THEN LOOP ;  WORK .")
    runs = []
    for compiled in (True, False):
        m = machine(compiled)
        t = ticker(m, 23 * PRIM + 12345)
        out = m.evaluate(program)
        runs.append((out, t.times, m.clock, m.evaluate("TICKS @ .")))
    assert runs[0] == runs[1]


def test_the_handler_runs_on_its_own_stacks_and_leaves_the_foregrounds_alone():
    m = rcl.Forth()
    m.evaluate("VARIABLE SEEN  -1 SEEN !  : NOISY  DEPTH SEEN !  1 2 3 99 ;")
    t = ticker(m, 50 * PRIM, "NOISY")
    m.evaluate(": SUM  0 1000 0 DO I + LOOP ;  5 6 7 SUM")
    assert t.times
    assert m.stack == [5, 6, 7, 499500 % 65536 - 65536]
    assert m.evaluate("SEEN @ .") == "0 "


def test_a_handler_longer_than_its_period_is_never_reentered():
    m = rcl.Forth()
    m.evaluate(": SLOW  300 0 DO LOOP ;")                # ~300 primitives
    t = ticker(m, 100 * PRIM, "SLOW")
    m.evaluate(": BUSY  3000 0 DO LOOP ;  BUSY")
    assert len(t.times) > 3
    assert not t.nested
    # Each service started after the previous handler had finished.
    assert all(b - a >= 300 * PRIM for a, b in zip(t.times, t.times[1:]))


def test_an_error_in_a_handler_aborts_the_foreground_cleanly():
    m = rcl.Forth()
    m.evaluate(": BAD  DROP ;")                          # underflows its empty stack
    ticker(m, 20 * PRIM, "BAD")
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("1 2 3 : BUSY  1000 0 DO LOOP ;  BUSY")
    assert e.value.message == ("Stack Underflow in the tick handler BAD; "
                               "tick stopped, INSTALL restarts it")
    m.irq = None
    m.reschedule()
    assert m.stack == []
    assert m.evaluate("2 3 + .") == "5 "


def test_waiting_skips_the_clock_forward_and_still_services_every_interrupt():
    m = machine()
    t = ticker(m, 10 * MS)
    m.evaluate("1000 MS")                               # F83's delay, virtual time
    assert len(t.times) == 100
    assert [w - (i + 1) * 10 * MS for i, w in enumerate(t.times)] == [0] * 100
    assert m.evaluate("TICKS @ .") == "100 "


@pytest.mark.parametrize("compiled", [True, False])
def test_words_that_play_with_return_addresses_work_compiled_and_in_the_reference_loop(compiled):
    m = rcl.Forth()
    m.compiled = compiled
    # R> DROP leaves the caller; R> 6 + >R skips the caller's next literal and word.
    assert m.evaluate(": INNER  R> DROP ;  : OUTER  1 . INNER 2 . ;  OUTER 3 .") == "1 3 "
    assert m.evaluate(": SKIP  R> 6 + >R ;  : T  SKIP 10 . 20 . 30 . ;  T") == "20 30 "
