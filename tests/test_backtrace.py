"""An error names the word it came from and the words that called it, with
the file:line of each where known (as gforth's backtrace does): worked out
when the error is reported, from the return stack and the dictionary, the
same for compiled code (small words pasted into their callers) and the
reference loop."""
import os
import subprocess
import sys

import pytest

import rcl
from rcl.forth.wordloc import describe

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

RT = """\
: FOO  ( n -- )  DROP DROP ;
: BAR  ( -- )
   1 FOO ;
: BAZ  BAR 5 ;
BAZ
"""


@pytest.fixture
def rt(tmp_path):
    path = tmp_path / "rt.fs"
    path.write_text(RT)
    return str(path)


def failing(m, text):
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate(text)
    return e.value


@pytest.mark.parametrize("compiled", [True, False])
def test_an_error_from_a_file_names_the_word_and_its_callers_with_their_lines(rt, compiled):
    m = rcl.Forth()
    m.compiled = compiled
    with pytest.raises(rcl.ForthError) as e:
        m.include(rt)
    assert (e.value.file, e.value.line, e.value.message) == (rt, 5, "Stack Underflow")
    assert e.value.backtrace == [("FOO", rt, 1), ("BAR", rt, 3), ("BAZ", rt, 4)]


# (a body, then the words that call it): small words are pasted into their
# callers when compiled, others called; DO loops keep their index on the
# return stack; DEFER and EXECUTE call through a cell.
CASES = [
    (": W1 DROP ; : W2 W1 ; : W3 W2 ;", "W3", ["W1", "W2", "W3"]),
    (": W1 0 DO I . LOOP DROP ; : W2 2 W1 ; : W3 W2 ;", "W3", ["W1", "W2", "W3"]),
    (": W1 DROP ; : W2 3 0 DO W1 LOOP ; : W3 W2 ;", "W3", ["W1", "W2", "W3"]),
    (": W1 DROP ; DEFER W2 ' W1 IS W2 : W3 W2 ;", "W3", ["W1", "W3"]),
    (": W1 DROP ; : W3 ['] W1 EXECUTE ;", "W3", ["W1", "W3"]),
    (": W1 DROP ; : W3 S\" W1\" EVALUATE ;", "W3", ["W1", "W3"]),
    (": W1 DUP . ; : W3 W1 ;", "W3", ["W1", "W3"]),
]


@pytest.mark.parametrize("source,run,chain", CASES)
def test_the_backtrace_is_the_same_compiled_and_in_the_reference_loop(source, run, chain):
    seen = []
    for compiled in (True, False):
        m = rcl.Forth()
        m.compiled = compiled
        m.evaluate(source)
        e = failing(m, run)
        seen.append([name for name, _, _ in e.backtrace])
    assert seen == [chain, chain]


def test_an_error_typed_at_the_top_names_no_word():
    assert failing(rcl.Forth(), "DROP").backtrace == []


def test_abort_quote_shows_only_its_message():
    m = rcl.Forth()
    m.evaluate(': W1 1 ABORT" no" ; : W2 W1 ;')
    e = failing(m, "W2")
    assert [w for w, _, _ in e.backtrace] == ["W1", "W2"] and e.words() == []


def test_the_lines_shown_name_each_word_and_place(rt):
    frames = [("FOO", rt, 1), ("BAR", rt, 3), ("TYPED", None, None)]
    assert describe(frames) == ["  in FOO  %s:1" % rt, "  called from BAR  %s:3" % rt,
                                "  called from TYPED"]


def run(*args, stdin=""):
    env = dict(os.environ, PYTHONPATH=ROOT)
    done = subprocess.run([sys.executable, "-m", "rcl", *args], input=stdin, env=env,
                          capture_output=True, text=True, timeout=60)
    assert "Traceback" not in done.stdout + done.stderr
    return done


def test_rcl_with_a_file_shows_the_backtrace_on_stderr(rt):
    done = run(rt)
    assert done.stderr == ("%s:5: Stack Underflow\n  in FOO  %s:1\n  called from BAR  %s:3\n"
                           "  called from BAZ  %s:4\n" % (rt, rt, rt, rt))
    assert done.returncode == 1


def test_a_piped_error_shows_the_backtrace_and_the_next_line_runs():
    done = run(stdin=": FOO DROP ;\n: BAR FOO ;\nBAR\n3 .\n")
    assert done.stdout == " Stack Underflow \n  in FOO\n  called from BAR\n3 \n"


def test_a_word_of_rcl_names_its_screen_and_line():
    e = failing(rcl.open(), "INCHES")
    screens = rcl.SCREENS
    assert e.words() == [("FIXED", os.path.join(screens, "50-fixed.fs"), 22),
                         ("INCHES", os.path.join(screens, "60-units.fs"), 15)]
