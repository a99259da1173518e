"""A DO loop whose body is several blocks (IF ... ELSE ... THEN, BEGIN ...
WHILE ... REPEAT inside it) runs as one Python while with the index and the
stack cells it works on in locals (compile_loops.py), and stays exact: an
interrupt falling at every offset of the body, a break asked for from a
handler, a short stack, and loop bodies made up by hypothesis all give the
reference loop's clock, stacks, output, interrupt times and memory."""
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import rcl
from rcl.forth.compiler import source
from compiler_support import PRIM
from compiler_support import near_overflow, run as speed_run

# Periods longer than the handler (about 5 primitives) that fall at every
# offset of a body up to 13 primitives long, and one far longer.
PERIODS = [k * PRIM + PRIM // 3 for k in range(6, 19)] + [97 * PRIM + 5]


def run(program, word, compiled, period, brk=None):
    """(output, stack, clock, interrupt times, return stack, memory), m."""
    out, stack, clock, times, _, m, rs, mem = speed_run(program, word, compiled, period, brk)
    return (out, stack, clock, times, rs, mem), m


def same_both_ways(program, word, periods=PERIODS, brk=None):
    for period in periods:
        (a, m), (b, _) = (run(program, word, c, period, brk) for c in (True, False))
        assert a[:5] == b[:5], (word, period)
        assert a[5] == b[5], (word, period, "memory differs")
        assert a[3], "the interrupt source fired"
    return m


def in_a_while(m, word):
    """Does word's DO loop run as a Python while over several blocks?"""
    return "_w = clk + " in source(m, word)


LOOPS = {
    # bench/bubble.fs's SORT, smaller: IF ... ELSE ... THEN, +LOOP by a constant
    "SORT": "CREATE A 40 ALLOT  : FILL  40 0 DO  I 7 * 13 + 31 AND A I + !  2 +LOOP ;"
            "  : SORT  FILL  20 1 DO  20 I - 2* A + A DO"
            "  I @ I 2 + @ 2DUP > IF I ! I 2 + ! ELSE 2DROP THEN  2 +LOOP LOOP"
            "  0 40 0 DO A I + @ + 2 +LOOP ;",
    # bench/sieve.fs's SIEVE, smaller: BEGIN ... WHILE ... REPEAT inside IF inside DO
    "SIEVE": "CREATE F 300 ALLOT  : SIEVE  F 300 + F DO 1 I C! LOOP  0 300 0 DO"
             "  F I + C@ IF  I DUP + 3 + DUP I +  BEGIN DUP 300 < WHILE"
             "  0 OVER F + C! OVER + REPEAT  DROP DROP 1 +  THEN  LOOP ;",
    # a variable step, a loop that goes down, UNTIL and AGAIN-with-EXIT-free bodies
    "STEPS": ": STEPS  0 100 0 DO  I 3 AND IF I + ELSE 1+ THEN  I 7 AND 1+ +LOOP"
             "  -50 0 DO  DUP 1 AND IF 3 + THEN  -3 +LOOP ;",
    "UNTIL": ": UNTIL  0 30 0 DO  I BEGIN 1- DUP 0< UNTIL DROP 1+  LOOP ;",
    # the stack below the loop's entry is worked on: cells carried in locals
    "DEEP": ": DEEP  1 2 3  40 0 DO  ROT I 5 MOD IF SWAP ELSE OVER + THEN  LOOP ;",
    # a flag or a step that is a cell the body also hands on, moved (SWAP)
    "FLAG": ": FLAG  0 1  40 0 DO  SWAP OVER IF 1+ ELSE 3 + THEN  LOOP ;",
    "STEPK": ": STEPK  1 2  60 0 DO  DUP 0< IF NEGATE THEN  SWAP OVER +LOOP ;",
    # two WHILEs: jumps that cross, gone through with guards inside the while
    "WHILES": ": WHILES  0  10 0 DO  I BEGIN DUP 7 < WHILE DUP 2 > WHILE 1+ REPEAT"
              "  DROP 100 + ELSE DROP 1+ THEN  LOOP ;",
    "NEST": ": NEST  0 5 0 DO 6 0 DO  I J + 3 MOD IF J + ELSE I - THEN LOOP LOOP ;",
}


@pytest.mark.parametrize("word", sorted(LOOPS))
def test_a_loop_of_several_blocks_takes_interrupts_between_the_reference_loops_primitives(word):
    m = same_both_ways(LOOPS[word], word)
    assert in_a_while(m, word)


def test_a_loop_whose_jumps_cross_goes_through_its_blocks_with_guards_inside_its_while():
    m = rcl.Forth()
    m.evaluate(LOOPS["WHILES"])
    assert m.evaluate("WHILES .") == "307 "
    assert "if b <= " in source(m, "WHILES").split("_w = clk", 1)[1]


def test_a_break_asked_for_by_a_handler_stops_the_loop_where_the_reference_loop_stops():
    for brk in (1, 3, 7):
        for period in PERIODS[:6]:
            a, b = (run(LOOPS["SIEVE"], "SIEVE", c, period, brk)[0] for c in (True, False))
            assert a[:5] == b[:5] and a[5] == b[5], (brk, period)
            assert a[0] == "error: Interrupted"


def test_a_loop_that_finds_the_stack_too_short_underflows_where_the_reference_loop_does():
    program = ("CREATE B 20 ALLOT  : SHORT  10 0 DO  I 2 MOD IF SWAP ELSE OVER + THEN"
               "  DUP B I + C!  LOOP ;")        # needs two cells, leaves two
    for word in ("SHORT", "1 SHORT", "1 2 SHORT", "1 2 3 4 5 6 7 SHORT"):
        (a, m), (b, _) = (run(program, word, c, 5 * PRIM + 7) for c in (True, False))
        assert a[:5] == b[:5] and a[5] == b[5], word
    assert in_a_while(m, "SHORT")


def fast_paths(src):
    """The lines of a loop of several blocks that run when no interrupt is
    near (its slow paths, `if _w and ...:` up to their `else:`, left out)."""
    start = src.index("_w = clk")
    loop = src[start:src.index("break\n", start)]
    out, slow = [], None
    for line in loop.splitlines():
        depth = len(line) - len(line.lstrip())
        if slow is not None and depth <= slow:
            slow = None
        if slow is None and line.strip().startswith("if _w and"):
            slow = depth
        elif slow is None:
            out.append(line.strip())
    return out


def test_bubble_and_sieve_keep_their_inner_stack_and_index_in_locals():
    m = rcl.Forth()
    m.evaluate(LOOPS["SORT"] + "  " + LOOPS["SIEVE"])
    for word in ("SORT", "SIEVE"):
        fast = fast_paths(source(m, word))
        assert len(fast) > 15
        assert not [line for line in fast if "s.pop()" in line or "s.append" in line
                    or "s.extend" in line or "rs[" in line], word
    assert "_i >= 0x8000 or _i <= 32765" in source(m, "SORT")    # 2 +LOOP, no LOOP_STEP call


# ------------------------------------------------ bodies made up by hypothesis
# Pieces that leave the stack as deep as they found it (three cells or more):
# a DO loop's body must, to be run as a Python while.
NEUTRAL = ["SWAP", "ROT", "OVER +", "DUP +", "1+", "2*", "NEGATE", "I +", "J XOR", "7 AND",
           "300 -", "DUP V !", "V @ +", "DUP V @ + V !", "DUP V C!", "2DUP < +", "0=", "DROP 5",
           "DUP 0< IF NEGATE THEN"]
simple = st.sampled_from(NEUTRAL)
words = st.lists(simple, max_size=3).map(" ".join)
cond = st.one_of(
    st.builds("DUP 1 AND IF {} ELSE {} THEN".format, words, words),
    st.builds("OVER 3 AND IF {} THEN".format, words))
straight = st.lists(st.one_of(simple, cond), max_size=3).map(" ".join)
loopy = st.one_of(
    st.builds("3 C ! BEGIN {} C @ 1- DUP C ! 0= UNTIL".format, straight),
    st.builds("2 C ! BEGIN C @ WHILE {} C @ 1- C ! REPEAT".format, straight))
body = st.lists(st.one_of(simple, cond, loopy), min_size=1, max_size=4).map(" ".join)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body=body, period=st.integers(5 * PRIM, 40 * PRIM))
def test_made_up_loop_bodies_run_as_the_reference_loop_runs_them(body, period):
    program = ("VARIABLE V  VARIABLE C  CREATE PAD2 64 ALLOT"
               "  : MADE  1 2 3  3 0 DO  12 0 DO  %s"
               "  2DUP + 63 AND DUP PAD2 + C!  OVER 15 AND 0= IF DROP 5 THEN  LOOP LOOP ;" % body)
    (a, m), (b, _) = (run(program, "MADE", c, period) for c in (True, False))
    assert a[:5] == b[:5]
    assert a[5] == b[5]
    assert a[3] and in_a_while(m, "MADE")


def test_a_loop_across_a_group_of_guards_in_a_long_definition_still_runs_as_a_while():
    # 15 IF ... THENs make 30 blocks before the loop: the loop's blocks
    # straddle the 32nd, where a new group of guards would begin.
    for before in (14, 15, 16):
        program = (": LONG  0 " + "DUP 1 AND IF 1+ THEN " * before +
                   " 20 0 DO  I 3 AND IF I + ELSE 1+ THEN  LOOP  DUP 2 AND IF 1+ THEN ;")
        m = same_both_ways(program, "LONG", PERIODS[::4])
        assert in_a_while(m, "LONG"), before


def test_the_loop_docstring_shows_the_python_that_source_prints():
    from rcl.forth import compile_loops
    from compiler_support import code_lines, in_order
    m = rcl.Forth()
    m.evaluate(": ODDS  0 10 0 DO  I 1 AND IF  I +  THEN  LOOP ;")
    doc = compile_loops.__doc__
    example = doc[doc.index(": ODDS"):doc.index("del rs[-3:]; s.append(_k0)") + 26]
    shown = [line.strip() for line in code_lines(example)[1:]]
    assert len(shown) > 25
    assert in_order(shown, [line.strip() for line in code_lines(source(m, "ODDS"))])
    assert m.evaluate("ODDS .") == "25 "


def test_loop_shape_finds_if_else_then_and_a_begin_loop_in_the_jumps():
    from rcl.forth import loop_shape
    # DO  IF A ELSE B THEN  BEGIN C WHILE D REPEAT  LOOP, as the docstring has it
    jumps = {0: ("?BRANCH", 2), 1: ("BRANCH", 3), 2: (None, None), 3: ("?BRANCH", 5),
             4: ("BRANCH", 3)}
    doc = loop_shape.__doc__
    shown = doc[doc.index('    [("block", 0)'):].split("\n\n")[0]
    assert loop_shape.shape(jumps, 0, 5) == eval(shown)
    # jumps that cross: an IF whose THEN is inside a BEGIN loop that began in its then-part
    assert loop_shape.shape({0: ("?BRANCH", 2), 1: (None, None), 2: ("?BRANCH", 1)}, 0, 3) is None


def test_an_inlined_call_in_a_loop_of_several_blocks_overflows_the_return_stack_where_the_real_call_does():
    program = ": SQ  DUP * ;  : W  0 5 0 DO  I 2 MOD IF  I SQ +  ELSE  1+  THEN  LOOP ;"
    out, m = near_overflow(program, "W", range(990, 999))
    assert in_a_while(m, "W")
    assert out[0] == out[1]
    assert any(s[0] == "ok" for s in out[0][::2]) and any(s[0] != "ok" for s in out[0][::2])


def test_a_step_known_when_compiling_ends_the_loop_where_loop_step_does():
    from rcl.forth.control import goes_on, loop_step
    for n in (1, 2, 3, 200, 0x7FFF, 0x8000, 0xFFFF, 0xFFFE, 0xFF38, 0):
        on = eval("lambda _i: " + goes_on("_i", n))
        for i in range(0, 0x10000, 7 if n not in (1, 2, 0xFFFF) else 1):
            y = loop_step(i, n)
            assert bool(on(i)) == (y is not None), (n, i)
            assert y is None or y == (i + n) & 0xFFFF
