"""The console as a person at a terminal meets it: `python3 -m rcl` on a
real pty (pexpect), the prompt_toolkit prompt on an xterm, asserting what
reaches the screen: TAB completion, the continuation prompt, an abandoned
definition, file:line, history, the bottom status line during a move, the
bell, typeahead while a word runs. The timeouts only bound a hung child.

The status line is drawn as `ESC 7, ESC [ 24 ; 1 H, reverse video, text,
ESC 8` on the last row of a 24-row screen; STATUS matches one drawing.
"""
import os
import re
import sys

import pytest

pexpect = pytest.importorskip("pexpect")
from pty_support import close  # noqa: E402  (after the skip without pexpect)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMEOUT = 120
STATUS = r"\x1b\[24;1H\x1b\[7m([^\x1b]*)\x1b\[0m"


def spawn(tmp_path, *options):
    env = dict(os.environ, HOME=str(tmp_path), XDG_DATA_HOME=str(tmp_path / "data"),
               PYTHONPATH=ROOT, TERM="xterm", PROMPT_TOOLKIT_NO_CPR="1")
    child = pexpect.spawn(sys.executable, ["-m", "rcl", *options], env=env,
                          encoding="utf-8", timeout=TIMEOUT, dimensions=(24, 80))
    child.expect("BYE to leave")
    return child


@pytest.fixture
def console(tmp_path):
    children = []

    def start(*options):
        children.append(spawn(tmp_path, *options))
        return children[-1]
    yield start
    for child in children:
        close(child)


def leave(child):
    child.sendline("BYE")
    child.expect(pexpect.EOF)


def test_tab_completes_a_word_of_the_search_order_whatever_its_case(console):
    child = console()
    child.send("rcl-wo\t")
    child.expect_exact("RCL-WORDS")
    child.send("\r")
    child.expect_exact("Layer 8, command language:")
    child.expect_exact(" ok")


def test_tab_completes_a_word_the_user_just_defined(console):
    child = console()
    child.sendline(": ZIGZAG 7 . ;")
    child.expect_exact(" ok")
    child.send("zigz\t")
    child.expect_exact("ZIGZAG")
    child.send("\r")
    child.expect_exact("7  ok")


def test_continuation_prompt_names_the_open_definition(console):
    child = console()
    child.sendline(": CUBE DUP DUP")
    child.expect_exact("CUBE]")
    child.sendline("* * ;")
    child.expect_exact(" ok")
    child.sendline("3 CUBE .")
    child.expect_exact("27  ok")


def test_lines_after_an_error_in_an_open_definition_are_skipped_up_to_its_semicolon(console):
    child = console()
    child.sendline(": BAD 1")
    child.expect_exact("BAD]")
    child.sendline("foo")
    child.expect_exact("FOO  ?")
    child.expect_exact("BAD is abandoned")
    child.sendline("7 .")
    child.expect_exact(" skipped")
    child.sendline("8 . ;")
    child.expect_exact(" skipped, the definition is over")
    child.sendline("9 .")
    child.expect_exact("9  ok")
    assert "7  ok" not in child.before and "8 " not in child.before


def test_an_error_in_a_definition_of_an_included_file_does_not_skip_the_next_line(console, tmp_path):
    path = tmp_path / "trip.fs"
    path.write_text(": TRIP 1\n  TRUN-LEFT 2 ;\n")
    child = console()
    child.sendline("INCLUDE %s" % path)
    child.expect_exact("%s:2: TRUN-LEFT  ?" % path)
    child.sendline("2 3 + .")
    child.expect_exact("5  ok")
    assert "abandoned" not in child.before


def test_an_error_inside_words_names_the_word_and_its_callers_at_the_prompt(console):
    child = console()
    child.sendline(": FOO DROP ;")
    child.expect_exact(" ok")
    child.sendline(": BAR FOO ;")
    child.expect_exact(" ok")
    child.sendline("BAR")
    child.expect_exact("Stack Underflow")
    child.expect_exact("in FOO")
    child.expect_exact("called from BAR")
    child.sendline("2 .")
    child.expect_exact("2  ok")


def test_an_error_in_a_file_included_at_the_prompt_names_file_and_line(console, tmp_path):
    path = tmp_path / "broken.fs"
    path.write_text(": FINE 1 ;\n\nnosuchword\n")
    child = console()
    child.sendline("INCLUDE %s" % path)
    child.expect_exact("%s:3: NOSUCHWORD  ?" % path)


def test_history_persists_across_sessions_and_ctrl_r_searches_it(console, tmp_path):
    child = console()
    child.sendline("1234 5 + .")
    child.expect_exact("1239  ok")
    leave(child)
    assert (tmp_path / "data" / "rcl" / "history").exists()
    child = console()
    child.sendcontrol("r")
    child.send("1234")
    child.send("\r")                     # take the found line
    child.send("\r")                     # and run it
    child.expect_exact("1239  ok")


def test_status_line_shows_time_pose_arm_jaw_and_stack(console):
    child = console("--start", "09:41")
    child.sendline("1 2")
    child.expect(STATUS)
    child.expect(r"09:41:\d\d  x 0\.0 y 0\.0 in  heading 0\.0  arm 8\.00 jaw 0\.00 in  stack 2")


def test_status_line_shows_the_move_progress_changing_during_a_move(console):
    child = console("--realtime")
    child.sendline("RERB 2 MPH 3.4 FEET FORWARD")
    child.expect(STATUS + "")
    seen = set()
    while len(seen) < 2:
        child.expect(r"moving (\d+)%")
        seen.add(int(child.match.group(1)))
    child.expect_exact(" ok")
    child.expect(r"x 40\.\d y 0\.0 in  heading 0\.0  arm 8\.00")
    assert len(seen) >= 2


def test_a_beep_rings_the_terminal_bell_unless_silenced(console):
    child = console()
    child.sendline("BEEP")
    child.expect_exact("BEEP  ok")
    child.expect_exact("\a")                # rung as the beep is seen
    child.sendline("#bell off")
    child.expect_exact("bell off")
    child.sendline("BEEP 5 .")
    child.expect_exact("5  ok")
    child.sendline("6 .")
    child.expect_exact("6  ok")
    assert "\a" not in child.before


def test_a_line_typed_while_a_word_runs_waits_and_is_not_echoed_over_its_output(console):
    child = console("--realtime")
    child.sendline(".\" start\" 1500 MS .\" end\"")
    child.expect_exact("start")
    child.sendline("2 3 + .")
    child.expect_exact("end")
    assert "2 3 + ." not in child.before     # not echoed while MS ran
    child.expect_exact("5  ok")


def test_realtime_clock_runs_while_the_prompt_waits(console):
    import time
    child = console("--realtime", "--start", "10:00")
    child.sendline(".TIME")
    child.expect(r"10:00:0\d  ok")
    time.sleep(2.0)                          # the wall clock passes at the prompt
    child.expect(r"\x1b\[7m10:00:0[2-9]")     # and the status line shows it
    child.sendline(".TIME")
    child.expect(r"10:00:(\d\d)  ok")
    assert int(child.match.group(1)) >= 2


def test_help_alone_shows_how_to_start(console):
    child = console()
    child.sendline("HELP")
    child.expect_exact("RERB 2 MPH 3.4 FEET FORWARD")
    child.expect_exact("INCLUDE examples/listing1.fs")


# ------------------------------------------------ the screen, through tmux
# tmux is a real terminal emulator that answers cursor-position requests
# (pexpect does not): what it shows is what a user sees.
def tmux(*args):
    import subprocess
    return subprocess.run(["tmux", *args], capture_output=True, text=True, timeout=10)


def screen_until(session, predicate):
    """The tmux screen's rows once predicate(rows) holds; bounded wait."""
    import time
    for _ in range(200):
        rows = tmux("capture-pane", "-t", session, "-p").stdout.rstrip("\n").split("\n")
        if predicate(rows):
            return rows
        time.sleep(0.1)
    raise AssertionError("screen never showed it:\n" + "\n".join(rows))


@pytest.fixture
def tmux_rcl(tmp_path):
    import shutil
    if shutil.which("tmux") is None:
        pytest.skip("tmux is not installed")
    session = "rcl-test-%d" % os.getpid()
    command = "env PYTHONPATH=%s HOME=%s XDG_DATA_HOME=%s TERM=xterm %s -m rcl --start 07:15" % (
        ROOT, tmp_path, tmp_path / "data", sys.executable)
    tmux("-f", "/dev/null", "new-session", "-d", "-s", session, "-x", "80", "-y", "12", command)
    yield session
    tmux("kill-session", "-t", session)


def test_the_status_line_keeps_the_last_row_and_the_session_scrolls_above_it(tmux_rcl):
    screen_until(tmux_rcl, lambda rows: rows[-1].startswith("07:15:"))
    for n in range(15):                          # more lines than the screen has
        tmux("send-keys", "-t", tmux_rcl, "%d ." % n, "Enter")
        screen_until(tmux_rcl, lambda rows: any(r.startswith("%d . %d  ok" % (n, n))
                                                for r in rows))
    rows = screen_until(tmux_rcl, lambda rows: "14 . 14  ok" in rows)
    assert rows[-1].startswith("07:15:") and "stack 0" in rows[-1]
    assert "13 . 13  ok" in rows                 # the session scrolled above the status row
    assert rows.index("14 . 14  ok") == len(rows) - 3    # then the empty prompt's row
