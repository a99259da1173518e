"""Forth 2012 Exception word set (CATCH and THROW) and how uncaught
exceptions surface in Python as rcl.ForthError."""
import pytest


# --- CATCH and THROW inside Forth -----------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("1 2 0 THROW", [1, 2]),
    (": T 0 THROW 5 ; T", [5]),
])
def test_zero_throw_does_nothing(run, src, expected):
    assert run(src) == expected


def test_catch_pushes_zero_when_nothing_is_thrown(run):
    assert run(": T 1 2 + ; ' T CATCH") == [3, 0]


def test_catch_returns_the_thrown_code(run):
    assert run(": T 99 THROW ; ' T CATCH") == [99]


def test_throw_restores_the_stack_depth_to_what_it_was_at_catch(run):
    assert run(": T 1 2 3 4 55 THROW ; 7 ' T CATCH") == [7, 55]


def test_throw_restores_depth_even_after_items_were_consumed(run):
    stack = run(": T DROP DROP 33 THROW ; 1 2 3 ' T CATCH")
    assert len(stack) == 4
    assert stack[0] == 1 and stack[-1] == 33


def test_throw_unwinds_several_levels_of_calls(run):
    assert run(": A 3 THROW ; : B A 1 ; : C B 2 ; ' C CATCH") == [3]


def test_throw_from_inside_a_do_loop_is_caught(run):
    src = ": T 10 0 DO I 5 = IF 9 THROW THEN LOOP ; ' T CATCH 1 2 +"
    assert run(src) == [9, 3]


def test_nested_catch_catches_the_innermost_throw(run):
    src = ": INNER 5 THROW ; : MID ['] INNER CATCH 100 + ; ' MID CATCH"
    assert run(src) == [105, 0]


def test_a_rethrown_code_reaches_the_outer_catch(run):
    src = ": INNER 5 THROW ; : MID ['] INNER CATCH THROW 7 ; ' MID CATCH"
    assert run(src) == [5]


def test_execution_continues_after_a_catch_inside_a_definition(run):
    src = ": INNER 6 THROW ; : T ['] INNER CATCH 10 * 1+ ; T T"
    assert run(src) == [61, 61]


def test_abort_is_caught_as_minus_1(run):
    assert run("' ABORT CATCH") == [-1]
    assert run("DROP : T 1 2 ABORT ; 9 ' T CATCH") == [9, -1]


def test_abort_quote_with_a_true_flag_is_caught_as_minus_2(run):
    stack = run(': T ABORT" oops" ; 5 -1 \' T CATCH')
    assert len(stack) == 3
    assert stack[0] == 5 and stack[-1] == -2


def test_abort_quote_with_a_false_flag_does_nothing(run):
    assert run(': T ABORT" oops" 7 ; 5 0 \' T CATCH') == [5, 7, 0]


def test_an_undefined_word_in_an_evaluated_string_is_caught_as_minus_13(run):
    assert run(': T S" 1 2 NOSUCHWORD" EVALUATE ; \' T CATCH') == [-13]


def test_an_undefined_word_from_interpreted_evaluate_is_caught_as_minus_13(run):
    stack = run('S" NOSUCHWORD" \' EVALUATE CATCH')
    assert len(stack) == 3
    assert stack[-1] == -13


def test_input_resumes_after_the_line_that_called_catch(run):
    assert run(': T S" NOSUCHWORD" EVALUATE ; \' T CATCH 42') == [-13, 42]


def test_stack_underflow_is_caught_as_minus_4(run):
    assert run(": UNDER DROP ; ' UNDER CATCH") == [-4]


def test_the_machine_works_normally_after_a_caught_underflow(run):
    assert run(": UNDER DROP ; ' UNDER CATCH DROP 2 3 *") == [6]


# --- uncaught exceptions in Python --------------------------------------------

@pytest.mark.parametrize("code", [1, 77, 4096, 32767])
def test_an_uncaught_user_throw_raises_forth_error_with_that_code(forth, forth_error, code):
    with pytest.raises(forth_error) as e:
        forth.evaluate(f"{code} THROW")
    assert e.value.code == code


def test_an_uncaught_throw_from_a_definition_raises_forth_error(forth, forth_error):
    with pytest.raises(forth_error) as e:
        forth.evaluate(": T 1 2 77 THROW ; T")
    assert e.value.code == 77


def test_an_uncaught_throw_empties_the_stack(forth, forth_error):
    with pytest.raises(forth_error):
        forth.evaluate("1 2 3 77 THROW")
    assert forth.stack == []


def test_an_uncaught_throw_leaves_the_machine_usable(forth, forth_error):
    with pytest.raises(forth_error):
        forth.evaluate(": T 77 THROW ; T")
    assert forth.evaluate("2 3 + .") == "5 "


def test_an_uncaught_abort_raises_forth_error_minus_1(forth, forth_error):
    with pytest.raises(forth_error) as e:
        forth.evaluate("ABORT")
    assert e.value.code == -1


def test_an_uncaught_abort_quote_raises_minus_2_with_its_message(forth, forth_error):
    with pytest.raises(forth_error) as e:
        forth.evaluate(': T ABORT" it broke" ; -1 T')
    assert e.value.code == -2
    assert "it broke" in str(e.value)


def test_an_uncaught_undefined_word_raises_minus_13_naming_the_word(forth, forth_error):
    with pytest.raises(forth_error) as e:
        forth.evaluate("1 2 NOSUCHWORD 3")
    assert e.value.code == -13
    assert e.value.word == "NOSUCHWORD"


def test_an_uncaught_stack_underflow_raises_minus_4(forth, forth_error):
    with pytest.raises(forth_error) as e:
        forth.evaluate("DROP")
    assert e.value.code == -4


def test_output_before_an_uncaught_throw_is_kept_on_the_error(forth, forth_error):
    with pytest.raises(forth_error) as e:
        forth.evaluate(': T ." hi" 5 THROW ; T')
    assert e.value.output == "hi"


def test_a_definition_left_open_by_an_error_is_abandoned(forth, forth_error):
    with pytest.raises(forth_error):
        forth.evaluate(": T 1 NOSUCHWORD ;")
    assert forth.evaluate("5 .") == "5 "
