"""An RCL literal stores DPL and WIDE-NUMBER each time it runs; compiled
code stores them less often (deferred to where they can be observed, once
per loop while nothing changes them) and every point that can observe
memory still sees what the reference loop `run_from` shows: an interrupt
handler that reads DPL and WIDE-NUMBER and then changes them, falling at
every offset of the body; the clock, the stacks and the whole memory at
the end."""
import pytest

import rcl
from rcl.forth.compiler import source
from compiler_support import PRIM, Ticker

# The handler runs about 25 primitives: periods beyond that leave the loop
# fast iterations between interrupts, and these fall at every offset of
# a body up to 7 primitives long.
PERIODS = [k * PRIM + PRIM // 3 for k in range(40, 47)] + [97 * PRIM]

# Reads DPL and WIDE-NUMBER before any literal of its own, logs them in
# order, then leaves both changed (an interrupt that typed a number would).
HANDLER = ("VARIABLE TICKS  CREATE SEEN 256 ALLOT"
           "  : TICK  DPL @ WIDE-NUMBER @  TICKS @ 4 * SEEN +  2!"
           "  TICKS @ 1+ 63 AND TICKS !  TICKS @ 3 AND DPL !  DPL @ WIDE-NUMBER ! ;")


def run(program, word, compiled, period):
    m = rcl.Forth()
    m.compiled = compiled
    m.evaluate(HANDLER)
    m.evaluate(program)
    t = Ticker(m, period)
    m.attach(t)
    out = m.evaluate(word)
    return (out, m.stack, m.clock, t.times, bytes(m.mem)), m


PROGRAMS = {
    # a one-block DO loop: its literal's store is done once while nothing
    # changes DPL, again after each interrupt
    "SUM": ": SUM  0 200 0 DO  I 7 + +  LOOP ;",
    "READS": ": READS  0 200 0 DO  DPL @ + 5 +  WIDE-NUMBER @ +  LOOP ;",
    "WIDE": ": WIDE  0 200 0 DO  40000 +  LOOP ;",                  # (RWLIT)
    "NEST": ": NEST  0 10 0 DO  30 0 DO  I J * 3 + +  LOOP  LOOP ;",
    "TWO": ": TWO  0 200 0 DO  I 2 + 3 + +  LOOP ;",                 # two literals, one value
    # bodies where the store must be done every iteration: two values
    # stored (0 before DPL @, -1 at the end); and bodies where a store may
    # hit DPL: an address only known at run time (here DPL's), DPL itself
    "DOUBLE": ": DOUBLE  0 200 0 DO  1. DROP DPL @ + + 5 +  LOOP ;",
    "STORES": "VARIABLE P  DPL P !  : STORES  0 200 0 DO  P @ @ +  I P @ !  7 +  LOOP ;",
    "HITDPL": ": HITDPL  0 200 0 DO  DPL @ +  I 9 + DPL !  3 +  LOOP ;",
    # loops of several blocks: a store through a run-time address in one
    # branch, a store into DPL in one branch
    "SIEVE": "CREATE F 64 ALLOT  : SIEVE  0 60 0 DO  I 3 MOD IF  0 F I + C! 1+"
             "  ELSE  DPL @ + 7 +  THEN  LOOP ;",
    "HITS": ": HITS  0 100 0 DO  I 7 AND IF  5 +  ELSE  I DPL !  THEN  DPL @ + 3 +  LOOP ;",
}


@pytest.mark.parametrize("word", sorted(PROGRAMS))
def test_every_observer_of_dpl_sees_what_the_reference_loop_shows(word):
    for period in PERIODS:
        (a, m), (b, _) = (run(PROGRAMS[word], word, c, period) for c in (True, False))
        assert a[:4] == b[:4], (word, period)
        assert a[4] == b[4], (word, period, "memory differs")
        assert a[3], "the interrupt source fired"
    assert "while True:\n" in source(m, word).split("while True:", 1)[1]
    assert "if _d:" in source(m, word) or word == "DOUBLE"


def test_a_loop_whose_literals_leave_one_dpl_stores_it_once_until_the_slow_path_runs():
    m = rcl.Forth()
    m.evaluate(PROGRAMS["SUM"])
    src = source(m, "SUM")
    assert "_d = 1\n" in src and "if _d:" in src
    body = src.split("_d = 1\n", 1)[1].split("break", 1)[0]   # the DO loop's while
    assert body.count("mem[%d] = 255" % m.a_dpl) == 1


def test_a_loop_whose_literals_leave_two_dpls_stores_them_every_iteration():
    m = rcl.Forth()
    m.evaluate(PROGRAMS["DOUBLE"])
    assert "if _d:" not in source(m, "DOUBLE")


def test_a_store_that_may_hit_dpl_makes_the_next_literal_store_it_again():
    m = rcl.Forth()
    m.evaluate(PROGRAMS["STORES"] + "  " + PROGRAMS["HITDPL"] + "  " + PROGRAMS["SIEVE"])
    lo, hi = min(m.a_dpl, m.a_wide) - 3, max(m.a_dpl, m.a_wide) + 1
    assert "if %d <= t" % lo in source(m, "STORES")             # an address known at run time
    assert "if %d <= t" % lo in source(m, "SIEVE")              # (a loop of several blocks)
    hit = source(m, "HITDPL")                                   # DPL's own address
    assert "if _d:" in hit and "_d = 1\n" in hit.split("m.watched(%d)" % m.a_dpl)[1]
    assert lo <= m.a_dpl <= hi


def test_the_handler_saw_the_loops_dpl_and_its_own():
    # The proof above is only worth something if the handler's log holds
    # both the literal's DPL (-1) and values it left itself (0..3).
    (out, stack, clock, times, mem), m = run(PROGRAMS["SUM"], "SUM", True, 7 * PRIM + PRIM // 3)
    seen = {int(m.evaluate("SEEN %d + @ U." % (4 * k + 2))) for k in range(len(times))}
    assert 0xFFFF in seen and seen & {1, 2, 3}


def test_outside_a_python_loop_every_observer_of_dpl_sees_what_the_reference_loop_shows():
    # B1 (branches, a recursive call, literals in three blocks), H and W (a
    # store into DPL or into WIDE-NUMBER alone, then a literal) run outside
    # any Python while loop
    program = (": B1  DUP 3 < IF 7 + EXIT THEN  1- RECURSE  2 + ;"
               "  : H  DPL @ + 1+ DPL !  3 ;  : W  WIDE-NUMBER @ 1+ WIDE-NUMBER !  4 ;"
               "  : CALLS  0 40 0 DO  I 9 MOD B1 +  I H +  W +  DPL @ +  LOOP ;")
    for period in PERIODS:
        (a, _), (b, _) = (run(program, "CALLS", c, period) for c in (True, False))
        assert a[:4] == b[:4], period
        assert a[4] == b[4], (period, "memory differs")
