"""Forth test files run by pytest (rcl's plugin, in a real pytest run in a
temporary directory): each top-level T{ ... }T of a test_*.fs is an item,
a failure names file:line, the source line and both stacks, a file that
stops loading says where, on the robot by default, bare when asked."""
import pathlib
import shutil

import rcl
import rcl.testing.forthfile  # noqa: F401  (imported once here, not in every inner run)

from inner_pytest import run

EXAMPLES = pathlib.Path(rcl.SCREENS) / "examples"



def test_each_t_line_of_a_test_file_is_an_item_that_passes(pytester):
    pytester.makefile(".fs", test_units="T{ 3.5 FEET EXPECTED -> 1193. }T\nT{ 1 2 + -> 3 }T\n")
    result = run(pytester, "-rfs", "-v")
    result.assert_outcomes(passed=3)
    result.stdout.fnmatch_lines(["*test_units.fs::load PASSED*",
                                 "*test_units.fs::line 1 PASSED*",
                                 "*test_units.fs::line 2 PASSED*"])


def test_a_failing_test_names_file_line_source_and_both_stacks(pytester):
    pytester.makefile(".fs", test_units="\\ units\nT{ 3.5 FEET EXPECTED -> 1194. }T\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(["*test_units.fs: line 2*",
                                 "test_units.fs:2: INCORRECT RESULT",
                                 "    T{ 3.5 FEET EXPECTED -> 1194. }T",
                                 "  expected: 1194 0",
                                 "  actual:   1193 0",
                                 "FAILED test_units.fs::line 2 - test_units.fs:2: INCORRECT RESULT"])


def test_a_failure_after_the_robot_moved_shows_what_it_did(pytester):
    pytester.makefile(".fs", test_move="1 FEET FORWARD\nT{ 1 -> 2 }T\n")
    result = run(pytester, "-rfs")
    result.stdout.fnmatch_lines(["*expected: 2", "*actual:   1", "what the robot did:",
                                 "*wheel counts: left 3??, right 3??*",   # 12 in / 0.0352 in
                                 "  last moves:", "    FORWARD *counts left +3?? right +3??*"])


def test_an_error_in_a_test_fails_that_test_and_the_rest_are_not_reached(pytester):
    pytester.makefile(".fs", test_err="T{ 1 -> 1 }T\nT{ FOO -> }T\nT{ 2 -> 2 }T\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(passed=2, failed=1, skipped=1)
    result.stdout.fnmatch_lines(["test_err.fs:2: FOO  ?", "    T{ FOO -> }T",
                                 "SKIPPED*test_err.fs:3: not reached: the load stopped at test_err.fs:2"])


def test_a_file_that_fails_to_load_reports_its_error_at_file_and_line(pytester):
    pytester.makefile(".fs", test_load=": GOOD 1 ;\n: BAD  NOSUCH ;\nT{ GOOD -> 1 }T\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["*test_load.fs: load*", "test_load.fs:2: NOSUCH  ?",
                                 "    : BAD  NOSUCH ;"])


def test_an_included_file_that_fails_is_named_with_its_own_line(pytester):
    (pytester.path / "prog.fs").write_text("\n\n: X 1 +\n; ZZZ\n")
    pytester.makefile(".fs", test_prog="INCLUDE prog.fs\nT{ 1 X -> 2 }T\n")
    result = run(pytester, "-rfs")
    result.stdout.fnmatch_lines(["prog.fs:4: ZZZ  ?", "    ; ZZZ"])


def test_the_robot_is_the_default_and_a_directive_asks_for_a_bare_machine(pytester):
    pytester.makefile(".fs", test_bare="\\ rcl: bare\nT{ 1 -> 1 }T\nT{ 1 FEET -> }T\n")
    result = run(pytester, "-rfs")
    result.stdout.fnmatch_lines(["test_bare.fs:3: FEET  ?"])
    result.assert_outcomes(passed=2, failed=1)


def test_an_unknown_directive_is_a_clear_collection_error(pytester):
    pytester.makefile(".fs", test_odd="\\ rcl: turbo\nT{ 1 -> 1 }T\n")
    result = run(pytester, "-rfs")
    result.stdout.fnmatch_lines(["*test_odd.fs:1:*rcl: robot*rcl: bare*"])
    assert result.ret != 0


def test_the_articles_box_runs_from_a_test_file_beside_it(pytester):
    shutil.copy(EXAMPLES / "listing2.fs", pytester.path / "box.fs")
    pytester.makefile(".fs", test_box="INCLUDE box.fs\nT{ 3.5 FIXED BOX -> }T\n"
                      "T{ FERR @ MOVING @ -> 0 0 }T\n")
    run(pytester, "-rfs").assert_outcomes(passed=3)


def test_only_test_star_fs_files_are_collected(pytester):
    for name in ("checklist.fs", "control.fs"):           # like tests/forth/
        shutil.copy(pathlib.Path(__file__).parent / "forth" / name, pytester.path / name)
    pytester.makefile(".fs", helper="T{ 1 -> 2 }T\n")
    result = run(pytester, "-rfs")
    assert result.ret == 5                                # no tests collected


def test_the_file_patterns_are_a_setting(pytester):
    pytester.makeini("[pytest]\nrcl_test_files = check_*.fs\n")
    pytester.makefile(".fs", check_a="T{ 1 -> 1 }T\n", test_b="T{ 1 -> 2 }T\n")
    run(pytester, "-rfs").assert_outcomes(passed=2)


def test_a_test_inside_a_definition_has_no_item_but_its_failure_fails_load(pytester):
    pytester.makefile(".fs", test_def=": CHECK  T{ 1 -> 2 }T ;\nCHECK\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines(["*test_def.fs: load*", "test_def.fs:2: INCORRECT RESULT"])


def test_configured_files_are_loaded_before_each_test_file(pytester):
    pytester.makeini("[pytest]\nrcl_load = lib/units.fs\nrcl_load_bare = lib/sq.fs\n")
    pytester.mkdir("lib")
    (pytester.path / "lib" / "units.fs").write_text(": SIDE  3.5 FEET ;\n")
    (pytester.path / "lib" / "sq.fs").write_text(": SQ  DUP * ;\n")
    pytester.makefile(".fs", test_a="T{ SIDE EXPECTED -> 1193. }T\n",
                      test_b="\\ rcl: bare\nT{ 3 SQ -> 9 }T\n")
    run(pytester, "-rfs").assert_outcomes(passed=4)


def test_an_error_after_a_finished_test_on_its_line_fails_load_not_the_test(pytester):
    pytester.makefile(".fs", test_after="T{ 1 -> 1 }T  NOSUCH\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(passed=1, failed=1)
    result.stdout.fnmatch_lines(["*test_after.fs: load*", "test_after.fs:1: NOSUCH  ?"])


def test_a_configured_file_that_is_missing_is_named(pytester):
    pytester.makeini("[pytest]\nrcl_load = lib/nowhere.fs\n")
    pytester.makefile(".fs", test_a="T{ 1 -> 1 }T\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["*nowhere.fs  File not found",
                                 "SKIPPED*not reached: the load stopped at *nowhere.fs  File not found"])


def test_bye_in_a_test_file_ends_its_load_with_a_clear_failure(pytester):
    pytester.makefile(".fs", test_bye="T{ 1 -> 1 }T\nBYE\nT{ 2 -> 2 }T\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(passed=1, failed=1, skipped=1)
    result.stdout.fnmatch_lines(["BYE: the file ended before its last line"])


def test_a_file_that_brings_its_own_tester_is_told_to_leave_it_out(pytester):
    pytester.makefile(".fs", test_own="VARIABLE DEPTH0\n: T{  DEPTH DEPTH0 ! ;\n"
                      ": ->  ;\n: }T  ;\nT{ 1 -> 1 }T\n")
    result = run(pytester, "-rfs")
    result.assert_outcomes(failed=1, skipped=1)
    result.stdout.fnmatch_lines(["test_own.fs: the file redefines T{ -> }T (a tester of its own?)*"])
