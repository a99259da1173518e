"""Calls in compiled code keep virtual time and the stacks exact: EXECUTE
of an xt fetched from a cell and a DEFER's action are compared first with
the colon word the cell held when the caller was compiled and called
straight into its compiled body; any other xt (another colon word, a
primitive, a DOES> word, a CONSTANT), or that word once a store into it
threw compiled code away, goes the general way. Both ways give the
reference loop's output, stacks, clock, interrupt times and return-stack
overflow, also when an interrupt handler changes the vector, or the word
itself, between any two primitives."""
from hypothesis import given, settings
from hypothesis import strategies as st

import rcl
from rcl.forth.compiler import source
from compiler_support import PERIODS, PRIM, run, same_both_ways

FIB = ("VARIABLE FIB-VECTOR"
       "  : FIB  DUP 2 < IF EXIT THEN  DUP 1 - FIB-VECTOR @ EXECUTE"
       "  SWAP 2 - FIB-VECTOR @ EXECUTE + ;  ' FIB FIB-VECTOR !")

# A vector the interrupt handler turns round: a colon word, a primitive,
# a DOES> word, a CONSTANT, another colon word, in turn at every tick.
TURNING = (": A  1+ ;  : B  2* 3 + ;  : MK  CREATE , DOES> @ + ;  5 MK FIVE  9 CONSTANT NINE"
           "  CREATE XTS  ' A , ' 1+ , ' FIVE , ' NINE , ' B ,  VARIABLE V  ' A V !"
           "  DEFER D  ' A IS D  VARIABLE N"
           "  : TICK  N @ 1+ 5 MOD DUP N !  2* XTS + @  DUP V !  IS D ;"
           "  : VEC  0 60 0 DO  I V @ EXECUTE + 32767 AND  LOOP ;"
           "  : DEF  0 60 0 DO  I D + 32767 AND  LOOP ;")


def test_execute_of_a_vector_holding_a_colon_word_calls_its_compiled_body_directly():
    m = rcl.Forth()
    m.evaluate(FIB + "  10 FIB .")
    xt = m.dictionary.find("FIB")[0]
    src = source(m, "FIB")
    assert src.count("_f = FN(%d) if " % (xt + 2)) == 2
    assert src.count(" == %d else None" % xt) == 2 and src.count("r = _f(m)") == 2


def test_recursion_through_a_vector_takes_interrupts_between_the_reference_loops_primitives():
    same_both_ways(FIB, "12 FIB", PERIODS)


def test_a_vector_turned_round_by_the_handler_runs_as_the_reference_loop_runs_it():
    for word in ("VEC", "DEF"):
        same_both_ways(TURNING, word, PERIODS + [2 * PRIM + 1, PRIM + 7])


@settings(max_examples=25, deadline=None)
@given(period=st.integers(2 * PRIM, 60 * PRIM), word=st.sampled_from(["VEC", "DEF", "9 FIB"]))
def test_any_interrupt_period_gives_the_reference_loops_run(period, word):
    a, b = (run(FIB + " " + TURNING, word, c, period) for c in (True, False))
    assert a[:5] == b[:5]


def test_a_store_into_the_guessed_words_code_field_is_seen():
    # A becomes a CONSTANT whose value is its first body cell: the caller,
    # compiled while V held A as a colon word, must not call A's body
    for compiled in (True, False):
        m = rcl.Forth()
        m.compiled = compiled
        m.evaluate(": A  1+ ;  VARIABLE V  ' A V !  : W  5 V @ EXECUTE ;")
        assert m.evaluate("W .") == "6 "
        m.evaluate("9 CONSTANT NINE  ' NINE @ ' A !")
        assert m.evaluate("W . .") == "%d 5 " % m.memory.fetch(m.dictionary.find("A")[0] + 2)


def test_recursion_through_a_vector_overflows_the_return_stack_where_the_reference_does():
    program = "VARIABLE V  : DEEP  DUP 0= IF EXIT THEN  1- V @ EXECUTE ;  ' DEEP V !"
    for depth in (996, 997, 998, 999, 1000):
        a, b = (run(program, "%d DEEP" % depth, c, 50 * PRIM) for c in (True, False))
        assert a[:5] == b[:5], depth
    assert "Return Stack Overflow" in a[0]


def test_a_handler_that_turns_the_guessed_word_into_a_constant_mid_run_is_seen_at_once():
    # W is running (compiled while V held the colon word A) when the
    # handler stores a CONSTANT's code field into A's: the very next
    # EXECUTE of A must push A's first body cell, as the reference does
    program = (": A  DUP ;  VARIABLE V  ' A V !  9 CONSTANT NINE  VARIABLE N"
               "  : TICK  1 N +!  N @ 3 = IF  ['] NINE @ ['] A !  THEN ;"
               "  : W  0 60 0 DO  I V @ EXECUTE + + 32767 AND  LOOP ;")
    same_both_ways(program, "W", PERIODS)
