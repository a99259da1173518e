"""Forth 2012 Locals word set (chapter 13): {: ... :}, (LOCAL), LOCALS|,
on the bare and full systems; and that a local compiles to code as fast
as the stack code it replaces."""
import re

import pytest


# --- declaring and reading ---------------------------------------------------------------

def test_arguments_take_the_stack_in_order_the_last_from_the_top(sys_run):
    assert sys_run(": T {: a b c :} c b a ; 1 2 3 T") == [3, 2, 1]


def test_a_local_can_be_read_any_number_of_times(sys_run):
    assert sys_run(": T {: x :} x x * x + ; 5 T") == [30]


def test_values_after_the_bar_take_nothing_from_the_stack(sys_run):
    assert sys_run(": T {: a | b c :} 9 ; 7 8 T") == [7, 9]


def test_what_follows_the_double_dash_is_a_comment(sys_run):
    assert sys_run(": T {: a b -- sum diff :} a b + a b - ; 10 3 T") == [13, 7]


def test_a_declaration_without_arguments_is_allowed(sys_run):
    assert sys_run(": T {: | tmp :} 4 TO tmp tmp tmp + ; T") == [8]


def test_a_declaration_may_span_lines(sys_run):
    assert sys_run(": T {: a\nb :} a b - ;\n 9 4 T") == [5]


def test_to_stores_into_a_local(sys_run):
    assert sys_run(": T {: n | acc :} n 0 DO acc I + TO acc LOOP acc ; 5 T") == [10]


def test_a_local_shadows_a_word_of_the_same_name(sys_run):
    assert sys_run(": T {: dup :} dup 1+ ; 41 T 5 DUP") == [42, 5, 5]


def test_locals_are_forgotten_after_the_definition(system, forth_error):
    system.evaluate(": T {: zork :} zork ;")
    with pytest.raises(forth_error):
        system.evaluate("zork")


def test_locals_work_in_a_noname_definition(sys_run):
    assert sys_run(":NONAME {: a b :} b a ; 1 2 ROT EXECUTE") == [2, 1]


def test_each_call_has_its_own_locals_in_recursion(sys_run):
    src = ": FACT {: n :} n 2 < IF 1 ELSE n 1- RECURSE n * THEN ; 7 FACT"
    assert sys_run(src) == [5040]


def test_names_compare_without_case(sys_run):
    assert sys_run(": T {: Alpha :} ALPHA alpha + ; 4 T") == [8]


# --- with control structures and the return stack ---------------------------------------

def test_locals_can_be_read_inside_do_loops(sys_run):
    assert sys_run(": T {: base :} 3 0 DO base I + LOOP ; 100 T") == [100, 101, 102]


def test_locals_can_be_read_inside_nested_do_loops(sys_run):
    src = ": T {: k :} 2 0 DO 2 0 DO k I J 10 * + + LOOP LOOP ; 100 T"
    assert sys_run(src) == [100, 101, 110, 111]


def test_exit_drops_the_locals_before_it_returns(sys_run):
    src = ": T {: a b :} a IF b EXIT THEN a b + ; : U 1 0 T 5 2 T 3 ; U"
    assert sys_run(src) == [0, 2, 3]


def test_exit_after_unloop_inside_a_loop_returns_cleanly(sys_run):
    src = ": T {: n :} 10 0 DO I n = IF I UNLOOP EXIT THEN LOOP -1 ; 4 T 99 T"
    assert sys_run(src) == [4, -1]


def test_locals_leave_the_return_stack_as_they_found_it(sys_run):
    assert sys_run(": T {: a b | c d :} a b ; : U 7 >R 1 2 T R> ; U") == [1, 2, 7]


def test_a_caught_throw_from_inside_a_word_with_locals_unwinds_them(sys_run):
    # CATCH keeps the depth: the thrown-from argument's cell stays, then 5
    src = ": T {: a :} a THROW ; : U 5 ['] T CATCH 9 >R R> ; U 0 ' T CATCH"
    assert sys_run(src)[1:] == [5, 9, 0]


# --- (LOCAL) and LOCALS| --------------------------------------------------------------

def test_paren_local_declares_one_local_per_call_and_ends_with_zero_length(sys_run):
    src = (": LOCAL-X  S\" x\" (LOCAL) ; IMMEDIATE  : END-LOCALS  0 0 (LOCAL) ; IMMEDIATE "
           ": T LOCAL-X END-LOCALS x x * ; 6 T")
    assert sys_run(src) == [36]


def test_paren_local_gives_the_first_declared_the_top_of_the_stack(sys_run):
    src = ': T [ S" a" (LOCAL) S" b" (LOCAL) 0 0 (LOCAL) ] a b ; 1 2 T'
    assert sys_run(src) == [2, 1]


def test_locals_bar_gives_the_first_name_the_top_of_the_stack(sys_run):
    assert sys_run(": T LOCALS| a b | a b - ; 10 3 T") == [-7]


# --- errors -------------------------------------------------------------------------

def test_a_declaration_outside_a_definition_is_an_error(system, forth_error):
    with pytest.raises(forth_error):
        system.evaluate("{: a :}")


def test_a_second_declaration_in_one_definition_is_an_error(system, forth_error):
    with pytest.raises(forth_error):
        system.evaluate(": T {: a :} {: b :} ;")


def test_an_unfinished_declaration_is_an_error_and_compiles_nothing(system, forth_error):
    with pytest.raises(forth_error):
        system.evaluate(": T {: a b")
    assert system.evaluate("1 2 + .") == "3 "


# --- speed: a local is as cheap as a stack operation --------------------------------------

def compiled_source(m, name):
    from rcl.forth.compiler import compile_code

    return compile_code(m, m.dictionary.find(name)[0] + 2).source


def test_a_local_read_after_a_loop_compiles_to_an_inline_return_stack_read(forth):
    forth.evaluate(": L {: a b :} 3 0 DO LOOP a b + a * ;")
    src = compiled_source(forth, "L")
    assert "rs[-2]" in src and "rs[-1]" in src
    assert not re.search(r"\bP\d+\(m", src)            # no call of a primitive's function


PROGRAMS = [
    ": T {: a b c :} a b * c + a c * - ; 7 3 5 T",
    ": T {: n | acc :} n 0 DO acc I + TO acc LOOP acc ; 6 T",
    ": T {: a b :} a IF b EXIT THEN a b * ; 0 5 T 2 5 T",
    ": T {: a :} a 1+ TO a a >R R@ R> a + ; 4 T",
    ": T {: k :} 2 0 DO 2 0 DO k I J 10 * + + LOOP LOOP ; 100 T",
    ": FACT {: n :} n 2 < IF 1 ELSE n 1- RECURSE n * THEN ; 7 FACT",
    ": T {: a b | c :} b TO c a TO b c TO a a b ; 1 2 T",
]


@pytest.mark.parametrize("src", PROGRAMS)
def test_compiled_locals_do_what_the_reference_interpreter_does(src):
    import rcl

    fast, slow = rcl.Forth(), rcl.Forth()
    slow.compiled = False
    fast.evaluate(src)
    slow.evaluate(src)
    assert fast.stack == slow.stack and fast.clock == slow.clock and not fast.rs


def test_a_definition_in_one_block_never_builds_its_frame(forth):
    forth.evaluate(": L {: a b c :} a b * c + a c * - ;")
    src = compiled_source(forth, "L").split("else:")[1]      # the fast path
    assert "rs.extend" not in src and "rs[-" not in src and "del rs" not in src


def test_a_locals_word_costs_the_virtual_time_of_its_primitives_only(forth):
    # the call, (LOCALS) a b + a * (UNLOCALS) EXIT: 9 primitives of 1000/36 us each
    from rcl.forth.primitives import DEFAULT_COST

    forth.evaluate(": L {: a b :} a b + a * ;")
    before = forth.clock
    forth.evaluate("3 4 L")
    assert forth.stack == [21]
    assert forth.clock - before == 9 * DEFAULT_COST


def test_environment_says_how_many_locals_a_definition_may_have(sys_run):
    assert sys_run('S" #LOCALS" ENVIRONMENT?') == [32, -1]


def test_sixteen_locals_or_more_are_supplied(sys_run):
    names = " ".join("L%d" % i for i in range(32))
    src = ": T {: %s :} L31 L0 ; " % names + " ".join(str(i) for i in range(32)) + " T"
    assert sys_run(src) == [31, 0]


# --- with the compiler's inlining of small colon definitions -------------------------------

def run_both_ways(program, line):
    import rcl

    out = []
    for compiled in (True, False):
        m = rcl.Forth()
        m.compiled = compiled
        m.evaluate(program)
        try:
            text = m.evaluate(line)
        except rcl.ForthError as e:
            text = "error: %s" % e.message
        out.append((text, m.stack, m.clock, len(m.rs)))
    return out


def test_a_word_with_locals_is_called_not_pasted_into_its_caller(forth):
    from rcl.forth.compiler import source

    forth.evaluate(": ADD {: a b :} a b + ;  : USE  1 2 ADD ;")
    assert "FN(" in source(forth, "USE")


@pytest.mark.parametrize("frame, deepest", [("n", 500), ("n | x", 333), ("n | x y", 250)])
def test_a_frame_before_an_inlined_call_overflows_the_return_stack_where_the_reference_does(
        frame, deepest):
    # the frame and SQ's inlined call are in one block: the block's depth
    # check must count the frame's cells, kept in Python names or not
    program = ": SQ  DUP * ;  : DEEP {: %s :}  5 SQ DROP  n IF n 1- RECURSE THEN ;" % frame
    for depth in range(deepest - 6, deepest + 3):   # each level: its frame and return
        fast, slow = run_both_ways(program, "%d DEEP" % depth)
        assert fast == slow, depth
