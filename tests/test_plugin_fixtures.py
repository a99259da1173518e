"""rcl's pytest fixtures in a real pytest run (pytester, in-process):
rcl_robot and rcl_forth are fresh for each test, load the configured and
marked files first, say clearly when a file does not load, and leave a
user's own fixtures of other names alone."""
import pathlib
import shutil

import rcl
import rcl.testing  # noqa: F401  (imported once here, not in every inner run)

from inner_pytest import run

EXAMPLES = pathlib.Path(rcl.SCREENS) / "examples"



def test_each_test_gets_a_fresh_robot_and_a_fresh_bare_machine(pytester):
    pytester.makepyfile("""
        import pytest, rcl

        def test_one(rcl_robot, rcl_forth):
            rcl_robot.evaluate(": MINE 1 ; 3.5 FEET FORWARD")
            rcl_forth.evaluate("VARIABLE V 7 V !")
            assert rcl_robot.sim.pose[0] > 40

        def test_two(rcl_robot, rcl_forth):
            assert rcl_robot.sim.pose == (0.0, 0.0, 0.0)
            assert rcl_robot.sim.seconds < 1
            assert "MINE" not in rcl_robot.evaluate("WORDS")
            with pytest.raises(rcl.ForthError, match=r"V  \\?"):
                rcl_forth.evaluate("' V")
    """)
    run(pytester, "-rfs").assert_outcomes(passed=2)


def test_the_robot_has_rcl_loaded_and_the_bare_machine_does_not(pytester):
    pytester.makepyfile("""
        import pytest, rcl

        def test_robot(rcl_robot):
            rcl_robot.evaluate("3.5 FEET EXPECTED")
            assert rcl_robot.stack == [1193, 0]

        def test_bare(rcl_forth):
            with pytest.raises(rcl.ForthError, match=r"FEET  \\?"):
                rcl_forth.evaluate("3.5 FEET")
    """)
    run(pytester, "-rfs").assert_outcomes(passed=2)


def test_configured_files_load_into_every_machine_from_the_rootdir(pytester):
    pytester.makepyprojecttoml("""
        [tool.pytest.ini_options]
        rcl_load = ["lib/box.fs"]
        rcl_load_bare = ["lib/sq.fs"]
    """)
    pytester.mkdir("lib")
    shutil.copy(EXAMPLES / "listing2.fs", pytester.path / "lib" / "box.fs")
    (pytester.path / "lib" / "sq.fs").write_text(": SQ  DUP * ;\n")
    pytester.mkdir("sub")
    (pytester.path / "sub" / "test_x.py").write_text(
        "def test_box(rcl_robot):\n    rcl_robot.evaluate(\"' BOX DROP\")\n"
        "def test_sq(rcl_forth):\n    rcl_forth.evaluate('3 SQ')\n"
        "    assert rcl_forth.stack == [9]\n")
    run(pytester, "-rfs").assert_outcomes(passed=2)


def test_a_marker_loads_more_files_beside_the_test(pytester):
    pytester.makefile(".fs", patrol=": PATROL  1 FEET FORWARD 180 DEGREES LEFT ;")
    pytester.makepyfile("""
        import pytest

        @pytest.mark.rcl_load("patrol.fs")
        def test_patrol(rcl_robot):
            rcl_robot.evaluate("PATROL")
            assert rcl_robot.sim.pose[0] > 11
    """)
    run(pytester, "-rfs").assert_outcomes(passed=1)


def test_a_file_that_does_not_load_is_a_clear_setup_error(pytester):
    pytester.makefile(".fs", broken="\\ first\n: X  NOSUCH ;")
    pytester.makepyfile("""
        import pytest

        @pytest.mark.rcl_load("broken.fs")
        def test_x(rcl_robot):
            pass
    """)
    result = run(pytester, "-rfs")
    result.assert_outcomes(errors=1)
    result.stdout.fnmatch_lines(["*rcl could not load the test's files: *broken.fs:2: NOSUCH  ?"])
    assert "Traceback" not in result.stdout.str()


def test_the_plugins_names_leave_a_users_own_fixtures_alone(pytester):
    pytester.makeconftest("""
        import pytest

        @pytest.fixture
        def robot():
            return "my own robot"

        @pytest.fixture
        def forth():
            return "my own forth"
    """)
    pytester.makepyfile("""
        def test_mine(robot, forth, rcl_robot):
            assert (robot, forth) == ("my own robot", "my own forth")
    """)
    run(pytester, "-rfs").assert_outcomes(passed=1)


def test_a_project_without_rcl_tests_runs_as_before(pytester):
    pytester.makepyfile("def test_plain():\n    assert 1 + 1 == 2\n")
    (pytester.path / "words.fs").write_text("T{ 1 -> 2 }T\n")     # not test_*.fs
    result = run(pytester, "-rfs", "-v")
    result.assert_outcomes(passed=1)
    result.stdout.fnmatch_lines(["*test_plain PASSED*"])
