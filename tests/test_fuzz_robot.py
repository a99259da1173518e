"""The whole system under random and hostile lines (tests/robot_fuzz.py):
10,000 of them in CI (CI set), the first 2,000 of the same lines in a
default run, the same every run. After each: no Python exception, no
internal error, every relay off (no line overran its budget with a motor
on: the budget's abort stops them), and a canary word still works."""
import os

import pytest

import rcl

import robot_fuzz
from suite_size import scaled

LINES = scaled(10_000, 2_000)


@pytest.fixture(autouse=True)
def in_a_scratch_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)


def test_ten_thousand_random_lines_never_leave_a_motor_on_or_break_rcl():
    m = robot_fuzz.machine()
    words = robot_fuzz.dictionary_words(m)
    outcomes = {}
    for text in robot_fuzz.lines(LINES, seed=1, words=words):
        outcome = robot_fuzz.run_line(m, text)
        outcomes[outcome] = outcomes.get(outcome, 0) + 1
    assert sum(outcomes.values()) == LINES
    assert outcomes["ok"] > LINES // 10                 # it did more than refuse
    assert not os.listdir(".")                          # and wrote no file


def test_what_a_line_printed_before_bye_leaves_with_bye_not_in_the_next_lines_output():
    # The fuzz's line 1,834 (seed 1): CREATE's warning came back as the canary's output.
    m = robot_fuzz.machine()
    with pytest.raises(rcl.Bye) as bye:
        m.evaluate("END-AT CREATE ' BYE IS CONTROL")
    assert bye.value.output == "' isn't unique "
    assert m.evaluate("CANARY") == "3 "
    assert robot_fuzz.run_line(m, "CREATE ' BYE") == "bye"     # its canary check passes
