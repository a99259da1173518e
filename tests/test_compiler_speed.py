"""The compiler's speed-ups keep virtual time exact: the same clock and the
same interrupts at the same primitive boundaries as the reference loop
`run_from`, with the interrupt falling at every offset of a loop's body."""
import pytest

import rcl
from rcl.forth.compiler import source
from compiler_support import PERIODS, PRIM, near_overflow, run, same_both_ways

LOOPS = {
    "SUM": ": SUM  0 300 0 DO  I +  LOOP ;",                       # top of stack carried
    "STEP": ": STEP  0 0 200 DO  I +  -3 +LOOP ;",                  # +LOOP, negative
    "SQUARES": ": SQUARES  200 0 DO  I DUP * DROP  LOOP ;",          # no stack carried
    "FILL": "CREATE BUF 100 ALLOT  : FILL  BUF 100 + BUF DO  I 7 AND I C!  LOOP  BUF 99 + C@ ;",
    "NEST": ": NEST  0 10 0 DO  20 0 DO  I J * +  LOOP  LOOP ;",
    "WRAP": ": WRAP  0 -32700 32700 DO  1+  LOOP ;",                 # crosses 32767
}


def test_a_loop_whose_body_is_one_block_becomes_a_python_while_loop():
    m = rcl.Forth()
    m.evaluate(LOOPS["SUM"])
    src = source(m, "SUM")
    assert src.count("while True:") == 2                # the block loop and the DO loop
    assert "_c = s.pop()" in src and "(_i + _lim)" in src


@pytest.mark.parametrize("word", sorted(LOOPS))
def test_python_while_loops_take_interrupts_between_the_reference_loops_primitives(word):
    m = same_both_ways(LOOPS[word], word, PERIODS)
    assert "while True:\n" in source(m, word).split("while True:", 1)[1]


def test_a_break_request_stops_a_python_while_loop_where_the_reference_loop_stops():
    program = LOOPS["SUM"].replace("300", "3000")
    same_both_ways(program, "SUM", [7 * PRIM + 5, 13 * PRIM + 77], brk=5)
    out = run(program, "SUM", True, 7 * PRIM + 5, brk=5)[0]
    assert out == "error: Interrupted"


CALLS = {
    "ADDRS": "CREATE ITEMS 40 ALLOT  2 CONSTANT CELL  : ITEM  CELL * ITEMS + ;"
             "  : ADDRS  0 20 0 DO  I ITEM  I OVER !  @ +  LOOP ;",
    "NESTED": ": SQ  DUP * ;  : SQ+  SQ 1+ ;  : NESTED  0 30 0 DO  I SQ+ +  LOOP ;",
    "BRANCHY": ": SQ  DUP * ;  : BRANCHY  0 30 0 DO  I 3 MOD IF I SQ + ELSE 1+ THEN LOOP ;",
}


def test_a_small_colon_definition_is_pasted_into_its_caller():
    m = rcl.Forth()
    m.evaluate(CALLS["NESTED"])
    src = source(m, "NESTED")
    assert "FN(" not in src                        # no call left: SQ+ and SQ inlined
    assert "while True:\n" in src.split("while True:", 1)[1]   # and the loop is a while


@pytest.mark.parametrize("word", sorted(CALLS))
def test_inlined_calls_take_interrupts_between_the_reference_loops_primitives(word):
    same_both_ways(CALLS[word], word, PERIODS)


def test_an_inlined_call_overflows_the_return_stack_where_the_real_call_does():
    program = (": SQ  DUP * ;  : DEEP  DUP 0= IF EXIT THEN  1- 5 SQ DROP  RECURSE ;")
    for depth in (997, 998, 999, 1000):
        a, b = (run(program, "%d DEEP" % depth, c, 50 * PRIM) for c in (True, False))
        assert a[:5] == b[:5], depth


def test_a_store_into_an_inlined_word_is_seen_by_its_callers():
    m = rcl.Forth()
    m.evaluate(": ONE  1 ;  : TWO  2 ;  : USE  ONE ONE + ;  USE .")
    assert "FN(" not in source(m, "USE")
    m.evaluate("' TWO >BODY @  ' ONE >BODY !")     # ONE now runs 2's literal... as TWO
    assert m.evaluate("USE .") == m.evaluate("ONE ONE + .")


def test_a_block_that_runs_into_the_next_checks_for_interrupts_once_at_that_boundary():
    # A handler (5 primitives) longer than its period: an interrupt is due at
    # every boundary, so a second check at one boundary would take a second
    # interrupt there (the compiler did, before a block that begins at BEGIN
    # or after THEN).
    for program in (": W  0 BEGIN 1+ DUP 30 = UNTIL ;",
                    ": W  0 IF 1 ELSE 2 THEN  0 IF 1 ELSE 2 THEN  3 ;"):
        same_both_ways(program, "W", [3 * PRIM + PRIM // 3, 4 * PRIM + 1])


def test_a_constant_is_compiled_in_and_a_store_into_it_is_still_seen():
    m = rcl.Forth()
    m.evaluate("2 CONSTANT CELL  5 VALUE V  : W  CELL 3 * V + ;")
    assert m.evaluate("W .") == "11 "
    src = source(m, "W")
    assert "(6 + t1)" in src                             # CELL 3 * folded: 6
    assert "t1 = (mem[" in src                           # V read where it lives
    m.evaluate("7 ' CELL >BODY !  9 TO V")
    assert m.evaluate("W .") == "30 "


def test_i_used_twice_in_a_block_is_computed_once():
    m = rcl.Forth()
    m.evaluate("CREATE A 20 ALLOT  : W  10 0 DO  I I + I 2* A + !  I 5 = IF LEAVE THEN  LOOP ;")
    src = source(m, "W")
    assert src.count("rs[-1] + rs[-2]") == 1             # four I's in one block
    same_both_ways("CREATE A 20 ALLOT  : W  10 0 DO  I I + I 2* A + !  "
                   "I 5 = IF LEAVE THEN  LOOP  A 8 + @ ;", "W", PERIODS[:3])


def test_a_python_primitive_sees_the_clock_the_reference_loop_shows_it(monkeypatch):
    # Compiled code keeps the clock in a local; a primitive written in Python
    # (here DEPTH) must still read m.clock exactly.
    from rcl.forth.primitives import BY_NAME
    depth = BY_NAME["DEPTH"]
    seen = []

    def spy(m, fn=depth.fn):
        seen.append(m.clock)
        fn(m)
    monkeypatch.setattr(depth, "fn", spy)
    program = ": SQ  DUP * ;  : W  0 20 0 DO  I SQ +  DEPTH DROP  I 3 MOD IF DEPTH + THEN  LOOP ;"
    runs = []
    for compiled in (True, False):
        seen.clear()
        runs.append((run(program, "W", compiled, 9 * PRIM + 7)[:5], list(seen)))
    assert runs[0] == runs[1] and len(runs[0][1]) > 30


def test_an_error_inside_compiled_code_leaves_the_clock_where_the_block_put_it():
    m = rcl.Forth()
    m.evaluate(": W  100 0 DO  I 50 = IF  DROP DROP  THEN  LOOP ;")
    before = m.clock
    with pytest.raises(rcl.ForthError):
        m.evaluate("W")
    assert m.clock > before + 50 * 3 * PRIM          # the loop's time up to the error is kept


def test_an_inlined_call_after_code_that_grows_the_return_stack_overflows_where_the_real_call_does():
    # >R (a template), N>R (Python code) and a locals frame before SQ's
    # inlined call, at every return-stack depth near the limit
    program = (": SQ  DUP * ;  : A  1 2 >R 5 SQ R> ;  : B  1 2 3 3 N>R 7 SQ NR> ;"
               "  : C  4 {: a b :} a SQ b ;")
    for word in ("A", "B", "C"):
        out, _ = near_overflow(program, "9 8 " + word, range(990, 1000))
        assert out[0] == out[1], word
        assert "Return Stack Overflow" in str(out[0]) and "ok" in str(out[0]), word


def test_a_branch_on_a_comparison_tests_it_and_a_flag_used_again_is_still_made():
    program = (": ONCE  0 40 0 DO  I 7 MOD 3 < IF 1+ ELSE 2 + THEN  LOOP ;"
               "  : TWICE  0 40 0 DO  I 7 MOD 3 < DUP IF - ELSE + THEN  LOOP ;"
               "  : SMALL?  ( n -- n' )  DUP 3 < IF 1+ THEN ;"
               "  : LOOPED  0 40 0 DO  I SMALL? +  LOOP ;")
    m = rcl.Forth()
    m.evaluate(program)
    # a loop of several blocks names the comparison _f; a block tests it
    assert "0xFFFF if" not in source(m, "ONCE") and "_f = ((" in source(m, "ONCE")
    assert "0xFFFF if" not in source(m, "SMALL?") and "if not ((" in source(m, "SMALL?")
    assert "0xFFFF if" in source(m, "TWICE")
    for word in ("ONCE", "TWICE", "LOOPED"):
        same_both_ways(program, word, PERIODS)
