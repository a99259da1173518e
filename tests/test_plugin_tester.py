"""The standard tester's words, T{ -> }T TESTING #ERRORS VERBOSE, built
into every rcl machine: silent when a test holds, the standard message,
the source line and both stacks when it does not, the stack put back to
its depth at T{ either way."""
import pytest

import rcl
from rcl.words.tester import state_of


@pytest.fixture(params=["bare", "robot"])
def machine(request):
    return rcl.Forth() if request.param == "bare" else rcl.open()


def test_a_test_that_holds_prints_nothing_and_leaves_the_stack_as_it_was(machine):
    assert machine.evaluate("7 T{ 1 2 + -> 3 }T") == ""
    assert machine.stack == [7]


def test_an_incorrect_result_prints_the_line_and_both_stacks(machine):
    out = machine.evaluate("T{ 1 2 + -> 4 }T")
    assert out == "INCORRECT RESULT: T{ 1 2 + -> 4 }T\n  expected: 4\n  actual:   3\n"


def test_a_failed_test_counts_in_errors_and_the_session_goes_on(machine):
    machine.evaluate("T{ 1 -> 2 }T T{ 3 -> 3 }T T{ 1 2 -> 1 }T")
    assert machine.evaluate("#ERRORS @ .") == "2 "


def test_a_different_number_of_results_is_a_wrong_number_of_results(machine):
    out = machine.evaluate("T{ 1 2 -> 1 }T")
    assert out.startswith("WRONG NUMBER OF RESULTS: T{ 1 2 -> 1 }T\n")
    assert "  expected: 1\n  actual:   1 2\n" in out


def test_code_that_eats_cells_below_t_is_caught_and_the_depth_restored(machine):
    out = machine.evaluate("5 6 T{ DROP -> }T")
    assert "WRONG NUMBER OF RESULTS" in out and "(1 cell taken from below T{)" in out
    assert len(machine.stack) == 2


def test_doubles_compare_as_their_two_cells(machine):
    assert machine.evaluate("T{ 1193. -> 1193 0 }T") == ""


def test_a_test_may_span_lines(machine):
    assert machine.evaluate("T{ 1 2\n + -> 3 }T") == ""


def test_testing_skips_its_line_quietly_unless_verbose(machine):
    assert machine.evaluate("TESTING addition T{ 1 -> 2 }T") == ""
    assert machine.evaluate("TRUE VERBOSE ! TESTING addition") == "TRUE VERBOSE ! TESTING addition\n"


def test_rcl_words_are_tested_the_same_way_on_the_robot():
    robot = rcl.open()
    assert robot.evaluate("T{ 3.5 FEET EXPECTED -> 1193. }T") == ""   # 3 x 35000 / 88


def test_a_listener_hears_every_result_with_where_it_stood():
    m, heard = rcl.Forth(), []
    state_of(m).listener = heard.append
    m.evaluate("T{ 1 -> 1 }T  T{ 2 -> 3 }T")
    assert [(r.ok, r.line, r.column, r.expected, r.actual) for r in heard] == [
        (True, 1, 3, [1], [1]), (False, 1, 17, [3], [2])]
