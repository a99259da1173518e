"""Compiled code that changes under a running definition: a store into a
definition's body (its literal, a call cell, a CONSTANT's cell) made by
the caller itself, by a word it calls or by an interrupt handler is seen
at the very next primitive, as the reference loop sees it; the running
caller goes on in the reference loop (compile_deps.py, compiler.py). And
forgetting (FORGET, a MARKER) throws away only the code resting on what
was forgotten: a word defined before keeps its compiled function and the
name tables are pruned, not built again."""
from hypothesis import HealthCheck, given, settings, strategies as st

import rcl
from rcl.forth.decode import decode
from compiler_support import PERIODS, PRIM, run, same_both_ways
from suite_size import scaled

P4 = ": K1 5 ;  : P4 0 3 0 DO I 10 + ['] K1 >BODY CELL+ ! K1 + LOOP ;"


def cell_of(m, word, value):
    """The address of the cell in word's body that holds value: a
    literal's (its number) or a call's (the called word's xt)."""
    ip = (m.dictionary.find(word)[0] + 2) & 0xFFFF
    while True:
        ins = decode(m, ip)
        if ins.op == "literal" and ins.args == (value,):
            return (ins.addr + 2) & 0xFFFF
        if ins.op in ("colon", "inline") and ins.xt == value:
            return ins.addr
        assert ins.op != "EXIT", (word, value)
        ip = ins.next


def both(program, line, target=None):
    """What line prints after program, compiled and by the reference loop;
    target (word, value): the VARIABLE AT gets that cell's address first."""
    out = []
    for compiled in (True, False):
        m = rcl.Forth()
        m.compiled = compiled
        m.evaluate("VARIABLE AT  " + program)
        if target is not None:
            word, value = target
            if isinstance(value, str):
                value = m.dictionary.find(value)[0]
            m.evaluate("%d AT !" % cell_of(m, word, value))
        out.append(m.evaluate(line))
    return out


def test_a_literal_patched_by_the_loop_that_calls_the_word_is_seen_at_the_next_call():
    assert both(P4, "P4 . K1 . P4 .") == ["33 12 33 "] * 2


# Each program's W stores into the code of a word it runs, then runs it:
# (program, the cell AT points at, what `W . W .` prints).
PATCHES = {
    # the caller's own literal, just ahead of it: 0+1+2+3, where 7 was
    "own literal": (": W  0 4 0 DO  I AT @ !  7 +  LOOP ;", ("W", 7), "6 6 "),
    # C! into the literal's low byte, in a word pasted into the caller: 20+21+22+23
    "byte": (": K 5 ;  : W  0 4 0 DO  I 20 + AT @ C!  K +  LOOP ;", ("K", 5), "86 86 "),
    # 2! over a literal and the cell before it (LIT's own cell, written back as it was)
    "double": (": K 5 ;  : W  0 4 0 DO  I 30 +  AT @ 2 - @  AT @ 2 - 2!  K +  LOOP ;",
               ("K", 5), "126 126 "),
    # a call cell turned to another word (USE is not pasted: it has a loop)
    "call": (": A 1+ ;  : B 100 + ;  : USE  0 5 0 DO DUP DROP LOOP  A ;"
             "  : W  0 3 0 DO  ['] B AT @ !  USE +  LOOP ;", ("USE", "A"), "300 300 "),
    # a callee stores into its caller's literal while the caller is mid-block
    # (PATCH's loop keeps it a call): 10+11+12+13, then 14+15+16+17
    "callee": (": PATCH  AT @ @ 1+ AT @ !  1 0 DO LOOP ;  : W  0 4 0 DO  PATCH 9 +  LOOP ;",
               ("W", 9), "46 62 "),
    # CMOVE (a Python primitive) copies a literal in
    "cmove": ("CREATE SRC 77 ,  : K 5 ;  : W  K  SRC AT @ 2 CMOVE  K + ;", ("K", 5), "82 154 "),
}


def test_stores_into_the_code_a_running_definition_runs_give_the_reference_results():
    for name, (program, target, printed) in PATCHES.items():
        assert both(program, "W . W .", target) == [printed] * 2, name


def test_a_constant_stored_into_by_the_loop_that_uses_it_is_seen():
    # +! (a Python primitive) into a CONSTANT's cell: its value is compiled in
    program = "3 CONSTANT C3  : W  0 4 0 DO  1 ['] C3 >BODY +!  C3 +  LOOP ;"
    assert both(program, "W . C3 .") == ["22 7 "] * 2


def test_a_handler_patching_a_literal_of_the_running_loop_is_seen_where_the_reference_sees_it():
    program = (": K 5 ;  : TICK  1 TICKS +!  TICKS @ ['] K >BODY CELL+ ! ;"
               "  : W  0 60 0 DO  K + I +  LOOP ;")
    same_both_ways(program, "W", PERIODS + [2 * PRIM + 1, PRIM + 7])


# ---------------------------------------------------- stores made up by hypothesis
WORDS = (": A 5 ;  : B 7 + ;  : C 3 * ;  : E 1+ 2* ;  : D B C ;"
         "  : F 3 0 DO 1+ LOOP 11 + ;  : G DUP 0< IF NEGATE THEN 13 - ;")


def cells():
    """(literal value cells, call cells that hold an ( n -- n ) word) of WORDS."""
    m = rcl.Forth()
    m.evaluate("VARIABLE TICKS  : TICK  1 TICKS +! ;  " + WORDS)   # (as run() lays them down)
    values, calls = [], []
    for name in "ABCDEFG":
        ip = (m.dictionary.find(name)[0] + 2) & 0xFFFF
        while True:
            ins = decode(m, ip)
            if ins.op == "EXIT":
                break
            if ins.op == "literal" and len(ins.args) == 1:
                values.append((ins.addr + 2) & 0xFFFF)
            if ins.op == "colon":
                calls.append(ins.addr)
            ip = ins.next
    xts = [m.dictionary.find(n)[0] for n in ("B", "C", "E", "G")]
    return values, calls, xts


VALUES, CALLS, XTS = cells()
piece = st.one_of(
    st.sampled_from(["B", "C", "D", "E", "F", "G", "A +", "I +", "J XOR"]),
    st.builds("{} {} !".format, st.sampled_from(["I", "DUP", "9", "-4"]), st.sampled_from(VALUES)),
    st.builds("{} {} !".format, st.sampled_from(XTS), st.sampled_from(CALLS)),
    st.builds("I {} C!".format, st.sampled_from(VALUES)))


@settings(max_examples=scaled(40, 15), deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.too_slow])
@given(body=st.lists(piece, min_size=1, max_size=6).map(" ".join),
       period=st.integers(3 * PRIM, 40 * PRIM),
       handler=st.sampled_from(["", "TICKS @ %d !" % VALUES[1], "TICKS @ %d C!" % VALUES[0]]))
def test_random_stores_into_words_a_running_loop_calls_give_the_reference_run(body, period, handler):
    program = (WORDS + "  : TICK  1 TICKS +!  %s ;" % handler
               + "  : RUN  1  3 0 DO  5 0 DO  %s  LOOP LOOP  A D F G ;" % body)
    a, b = (run(program, "RUN", c, period) for c in (True, False))
    assert a[:5] == b[:5]
    assert a[7] == b[7], "memory differs"


# ----------------------------------------------------------------- forgetting
def compiled_of(m, name):
    return m.fn.get((m.dictionary.find(name)[0] + 2) & 0xFFFF)


def test_a_marker_keeps_the_compiled_code_and_name_tables_of_what_came_before():
    program = ": SQ DUP * ;  : HOT  0 20 0 DO I SQ + LOOP ;  MARKER MK  : LATER HOT 1+ ;"
    for forget in ("MK", "FORGET LATER"):
        m = rcl.Forth()
        m.evaluate(program)
        assert m.evaluate("HOT . LATER .") == "2470 2471 "
        hot, later = compiled_of(m, "HOT"), compiled_of(m, "LATER")
        assert hot is not None and later is not None
        body = (m.dictionary.find("LATER")[0] + 2) & 0xFFFF
        rebuilds = m.dictionary.rebuilds
        m.evaluate(forget)
        assert compiled_of(m, "HOT") is hot and not hot.__globals__["STALE"]
        assert m.fn.get(body) is None and later.__globals__["STALE"]     # what went, went
        assert m.dictionary.find("LATER") is None
        assert m.dictionary.rebuilds == rebuilds, "name tables built again"
        assert m.evaluate("HOT .") == "2470 "


def test_after_forgetting_new_words_over_the_old_code_run_as_the_reference_runs_them():
    program = (": SQ DUP * ;  : HOT  0 20 0 DO I SQ + LOOP ;  MARKER MK"
               "  : LATER  HOT 1+ ;  : L2  LATER LATER + ;")
    assert both(program, "L2 .  MK  : NEW  HOT 2 + ;  : N2 NEW 3 * ;  N2 .") == [
        "4942 7416 "] * 2
    assert both(program, "L2 . MK MARKER MK : X HOT 5 + ; X . MK MARKER MK HOT .") == [
        "4942 2475 2470 "] * 2


def test_hot_mk_marker_mk_recompiles_nothing_hot_needs():
    m = rcl.Forth()
    m.evaluate(": SQ DUP * ;  : HOT  0 20 0 DO I SQ + LOOP ;  MARKER MK")
    m.evaluate("HOT MK MARKER MK")
    kept = dict(m.fn)
    rebuilds = m.dictionary.rebuilds
    for _ in range(5):
        assert m.evaluate("HOT . MK MARKER MK") == "2470 "
    assert all(m.fn.get(a) is f for a, f in kept.items())
    assert m.dictionary.rebuilds == rebuilds
