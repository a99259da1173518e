"""docs/testing.md tells the truth: its example files, written out as the
page shows them, pass under pytest, and the failures it shows are what
pytest prints when a number in them is wrong."""
import pathlib
import re

import rcl
import rcl.testing.forthfile  # noqa: F401  (imported once here, not in every inner run)

from inner_pytest import run

DOC = pathlib.Path(__file__).parent.parent / "docs" / "testing.md"
BLOCK = re.compile(r"```(?:forth|python)\n(.*?)```", re.S)
NAMED = re.compile(r"^(?:\\|#) (?:rcl: \w+\n\\ )?(\w+\.(?:fs|py)):")


def example_files():
    """{name: text} of every code block whose first comment names a file."""
    files = {}
    for block in BLOCK.findall(DOC.read_text()):
        match = NAMED.match(block)
        if match:
            files[match.group(1)] = block
    return files



def test_the_pages_example_files_are_all_there():
    assert sorted(example_files()) == ["box.fs", "test_box.fs", "test_box.py", "test_stack.fs"]


def test_the_worked_example_passes_as_the_page_shows(pytester):
    for name, text in example_files().items():
        (pytester.path / name).write_text(text)
    result = run(pytester, "-v")
    result.assert_outcomes(passed=11)
    result.stdout.fnmatch_lines(["test_box.fs::load PASSED*", "test_box.fs::line 4 PASSED*",
                                 "test_box.fs::line 9 PASSED*",
                                 "test_box.py::test_box_comes_back_a_third_of_an_inch_from_its_start PASSED*"])


def test_the_failures_the_page_shows_are_what_pytest_prints(pytester):
    files = example_files()
    (pytester.path / "box.fs").write_text(files["box.fs"])
    (pytester.path / "test_box.fs").write_text(files["test_box.fs"].replace("1193. }T", "1194. }T"))
    (pytester.path / "test_box.py").write_text(files["test_box.py"].replace(
        "x=0.21, y=0.33", "x=0.0, y=0.0"))
    result = run(pytester)
    result.assert_outcomes(passed=6, failed=2)
    page = DOC.read_text()
    shown = [line for block in re.findall(r"```\n(_+ test_box.fs.*?|>.*?)```", page, re.S)
             for line in block.splitlines() if line != "..."]
    assert len(shown) > 10
    result.stdout.fnmatch_lines(shown)


def test_the_prompt_shows_a_failed_test_as_the_page_says():
    page = DOC.read_text()
    screen = re.search(r"```\n(T\{ 1 2 \+ -> 4 \}T.*?)```", page, re.S).group(1)
    assert rcl.Forth().session("T{ 1 2 + -> 4 }T") == screen


def test_the_pages_few_lines_in_short_pass_beside_the_articles_box(pytester):
    page = DOC.read_text()
    section = page[page.index("## In short"):page.index("## A worked example")]
    (forth, fs), (python, py) = re.findall(r"```(forth|python)\n(.*?)```", section, re.S)
    (pytester.path / "box.fs").write_text(example_files()["box.fs"])
    (pytester.path / "test_box.fs").write_text(fs)
    (pytester.path / "test_box.py").write_text(py)
    run(pytester).assert_outcomes(passed=4)
