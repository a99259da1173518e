"""Forth-level golden files (STYLE 12): each tests/forth/NAME.fs is typed
at the prompt of a fresh machine, line by line, and the screen F83 would
show must equal NAME.out. Nothing here is nondeterministic, so there is
nothing to normalize."""
import pathlib

import pytest

import rcl

HERE = pathlib.Path(__file__).parent / "forth"
CASES = sorted(p.stem for p in HERE.glob("*.fs"))


@pytest.mark.parametrize("name", CASES)
def test_golden_session_matches_its_expected_screen(name):
    typed = (HERE / (name + ".fs")).read_text().rstrip("\n")
    expected = (HERE / (name + ".out")).read_text()
    assert rcl.Forth().session(typed) == expected
