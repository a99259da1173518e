"""Control structures: IF, BEGIN loops, DO loops, LEAVE, and pairing checks.

Spec: F83's control structures (docs/forth2012.md, "Core: F83's meanings":
DO loops, and any non-zero flag is true).
"""
import pytest


def run(forth, text):
    return forth.evaluate(text)


def error_from(forth, text):
    import rcl
    with pytest.raises(rcl.ForthError) as info:
        forth.evaluate(text)
    return info.value


# ---------------------------------------------------------------------------
# IF ELSE THEN
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("flag, result", [(-1, [1]), (0, [2]), (5, [1])])
def test_if_else_then_runs_the_true_part_for_any_non_zero_flag(forth, flag, result):
    run(forth, ": T IF 1 ELSE 2 THEN ;")
    run(forth, f"{flag} T")
    assert forth.stack == result


@pytest.mark.parametrize("flag, result", [(0, [9]), (7, [9, 1])])
def test_if_then_skips_its_body_for_a_zero_flag(forth, flag, result):
    run(forth, ": T 9 SWAP IF 1 THEN ;")
    run(forth, f"{flag} T")
    assert forth.stack == result


# ---------------------------------------------------------------------------
# BEGIN loops
# ---------------------------------------------------------------------------

def test_begin_until_loops_until_the_flag_is_true(forth):
    assert run(forth, ": T 0 BEGIN 1+ DUP . DUP 3 = UNTIL DROP ;  T") == "1 2 3 "


def test_until_treats_any_non_zero_value_as_true(forth):
    run(forth, ": T 0 BEGIN 1+ DUP 4 AND UNTIL ;  T")
    assert forth.stack == [4]


def test_begin_while_repeat_exits_when_the_flag_is_zero(forth):
    run(forth, ": T BEGIN DUP 5 < WHILE 1+ REPEAT ;  0 T")
    assert forth.stack == [5]


def test_while_can_exit_before_the_first_pass_of_the_body(forth):
    run(forth, ": T BEGIN DUP 5 < WHILE 1+ REPEAT ;  10 T")
    assert forth.stack == [10]


def test_begin_again_loops_until_exit_leaves_the_definition(forth):
    run(forth, ": T 0 BEGIN 1+ DUP 7 = IF EXIT THEN AGAIN ;  T")
    assert forth.stack == [7]


def test_exit_returns_from_the_current_definition(forth):
    assert run(forth, ": T 1 . EXIT 2 . ;  T") == "1 "


# ---------------------------------------------------------------------------
# DO loops
# ---------------------------------------------------------------------------

def test_do_loop_counts_from_start_up_to_limit_minus_one(forth):
    assert run(forth, ": T 10 0 DO I . LOOP ;  T") == "0 1 2 3 4 5 6 7 8 9 "


def test_do_loop_with_equal_limit_and_start_runs_65536_times(forth):
    run(forth, "2VARIABLE N  : T 0 0 DO N 2@ 1. D+ N 2! LOOP ;  T")
    assert run(forth, "N 2@ D.") == "65536 "


def test_plus_loop_steps_by_its_increment(forth):
    assert run(forth, ": T 10 0 DO I . 3 +LOOP ;  T") == "0 3 6 9 "


def test_negative_plus_loop_runs_down_to_and_including_the_limit(forth):
    assert run(forth, ": T 0 10 DO I . -1 +LOOP ;  T") == "10 9 8 7 6 5 4 3 2 1 0 "


def test_do_runs_its_body_at_least_once(forth):
    assert run(forth, ": T 0 5 DO I . LEAVE LOOP ;  T") == "5 "


def test_question_do_skips_the_body_when_start_equals_limit(forth):
    assert run(forth, ": T 0 ?DO 1 . LOOP ;  0 T") == ""


def test_question_do_runs_the_body_when_start_differs_from_limit(forth):
    assert run(forth, ": T 0 ?DO 1 . LOOP ;  3 T") == "1 1 1 "


def test_leave_exits_the_loop_at_once_skipping_the_rest_of_the_iteration(forth):
    run(forth, ": T 10 0 DO I DUP . 2 = IF LEAVE THEN 100 . LOOP ;")
    assert run(forth, "T") == "0 100 1 100 2 "


def test_leave_continues_after_loop(forth):
    assert run(forth, ": T 10 0 DO I 2 = IF LEAVE THEN LOOP 99 . ;  T") == "99 "


def test_leave_drops_the_loop_frame_so_the_caller_continues_normally(forth):
    run(forth, ": T 10 0 DO LEAVE LOOP 42 ;  T")
    assert forth.stack == [42]


def test_question_leave_leaves_on_a_non_zero_flag(forth):
    assert run(forth, ": T 10 0 DO I DUP . 3 = ?LEAVE LOOP ;  T") == "0 1 2 3 "


def test_question_leave_treats_any_non_zero_value_as_true(forth):
    assert run(forth, ": T 10 0 DO I DUP . 4 AND ?LEAVE LOOP ;  T") == "0 1 2 3 4 "


def test_j_is_the_index_of_the_next_outer_loop(forth):
    run(forth, ": T 3 0 DO 2 0 DO J 10 * I + . LOOP LOOP ;")
    assert run(forth, "T") == "0 1 10 11 20 21 "


def test_i_inside_a_loop_with_negative_bounds(forth):
    assert run(forth, ": T -1 -4 DO I . LOOP ;  T") == "-4 -3 -2 "


# ---------------------------------------------------------------------------
# Compile-time pairing check
# ---------------------------------------------------------------------------

def test_then_without_if_aborts_with_conditionals_wrong(forth):
    assert error_from(forth, ": T THEN ;").message == "Conditionals Wrong"


def test_machine_interprets_again_after_conditionals_wrong(forth):
    error_from(forth, ": T THEN ;")
    assert run(forth, "2 3 + .") == "5 "
