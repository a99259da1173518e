"""Finding a test file's T{ lines without running it: the scanner skips
comments, strings and definitions as the outer interpreter does, and the
line and column it gives each T{ are those the tester notes at run time."""
import pytest

import rcl
from rcl.testing.scan import ScanError, scan
from rcl.words.tester import state_of

FILE = r"""\ a test file
: SQ  DUP * ;  \ T{ in a comment
T{ 3 SQ -> 9 }T  T{ 1 -> 1 }T
T{ 1 2 ( a T{ in a comment ) + -> 3 }T
( a comment over
  two lines T{ ) T{ S" T{ " NIP -> 3 }T
T{ 1
   2 -> 1 2 }T
TESTING T{ is not a test here
: CHECK  T{ 1 -> 1 }T ;
CHAR T{ DROP  T{ 5 -> 5 }T
"""


def test_the_scanner_finds_each_top_level_t_with_its_line_and_span():
    mode, specs = scan(FILE.splitlines())
    assert mode == "robot"
    assert [(s.name, s.line, s.end_line) for s in specs] == [
        ("line 3", 3, 3), ("line 3.2", 3, 3), ("line 4", 4, 4), ("line 6", 6, 6),
        ("line 7", 7, 8), ("line 11", 11, 11)]
    assert specs[4].source == ["T{ 1", "   2 -> 1 2 }T"]


def test_the_scanner_and_the_tester_agree_on_where_each_test_stands(tmp_path):
    path = tmp_path / "test_where.fs"
    path.write_text(FILE)
    m, heard = rcl.Forth(), []
    state_of(m).listener = heard.append
    m.include(str(path))
    ran = [(r.line, r.column) for r in heard]
    assert ran == [(s.line, s.column) for s in scan(FILE.splitlines())[1]]
    assert all(r.ok for r in heard)


@pytest.mark.parametrize("first_lines, mode", [
    (["\\ rcl: bare"], "bare"),
    (["\\ my tests", "\\ RCL: Bare", "T{ 1 -> 1 }T"], "bare"),
    (["\\ rcl: robot"], "robot"),
    (["T{ 1 -> 1 }T", "\\ rcl: bare"], "robot"),     # only the leading comments count
])
def test_a_directive_among_the_leading_comment_lines_chooses_the_machine(first_lines, mode):
    assert scan(first_lines)[0] == mode


def test_an_unknown_directive_is_an_error_that_shows_the_two_choices():
    with pytest.raises(ScanError, match=r"rcl: robot.*rcl: bare"):
        scan(["\\ rcl: turbo"])
