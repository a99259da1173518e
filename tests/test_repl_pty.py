"""End to end: `python3 -m rcl` on a real pty, driven by pexpect, as a user
at a terminal would use it (STYLE 14). The timeouts only bound a hung
child; they assert nothing about speed.

Each test runs on three terminals:

* xterm: the real prompt_toolkit prompt. PROMPT_TOOLKIT_NO_CPR=1 because
  pexpect is not a terminal emulator and never answers prompt_toolkit's
  cursor-position request (ESC [6n); without it prompt_toolkit waits for
  the answer and then prints a warning about the terminal into the screen.
* dumb: TERM=dumb, prompt_toolkit's echo-only prompt (no cursor movement),
  where the output comes on the line after the typed one.
* plain: prompt_toolkit made unimportable, so rcl falls back to input().
"""
import os
import sys

import pytest

pexpect = pytest.importorskip("pexpect")
from pty_support import close  # noqa: E402  (after the skip without pexpect)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMEOUT = 120
NO_PROMPT_TOOLKIT = ("import sys; sys.modules['prompt_toolkit'] = None; "
                     "from rcl.cli import main; sys.exit(main())")

TERMINALS = {
    "xterm": ({"TERM": "xterm", "PROMPT_TOOLKIT_NO_CPR": "1"}, ["-m", "rcl"]),
    "dumb": ({"TERM": "dumb"}, ["-m", "rcl"]),
    "plain": ({"TERM": "xterm"}, ["-c", NO_PROMPT_TOOLKIT]),
}


@pytest.fixture(params=sorted(TERMINALS))
def terminal(request):
    return request.param


@pytest.fixture
def child(terminal, tmp_path):
    """rcl at a prompt on a pty, its history kept in tmp_path."""
    extra, args = TERMINALS[terminal]
    env = dict(os.environ, HOME=str(tmp_path), PYTHONPATH=ROOT, **extra)
    proc = pexpect.spawn(sys.executable, args, env=env, encoding="utf-8",
                         timeout=TIMEOUT, dimensions=(24, 80))
    proc.expect("rcl .*BYE to leave")
    yield proc
    close(proc)


def ctrl_d(child):
    """Press Ctrl-D until rcl leaves. One typed while the previous line's
    output is still coming lands in the terminal's cooked mode, where it is
    not a character, and is lost when the prompt switches to raw mode (as
    in any readline-style program); so the key is pressed again."""
    for _ in range(TIMEOUT // 2):
        child.sendcontrol("d")
        if child.expect([pexpect.EOF, pexpect.TIMEOUT], timeout=2) == 0:
            return
    raise AssertionError("rcl did not leave at Ctrl-D:\n" + child.before)


def test_session_shows_ok_defines_words_reports_errors_and_leaves_at_ctrl_d(child):
    child.sendline("2 3 + .")
    child.expect_exact("5  ok")
    child.sendline(": SQ DUP * ;")
    child.sendline("7 SQ .")
    child.expect_exact("49  ok")
    child.sendline("foo")
    child.expect_exact("FOO  ?")
    ctrl_d(child)
    child.close()
    assert child.exitstatus == 0
    assert "Traceback" not in child.before


def test_output_follows_the_typed_line_on_the_same_screen_line(child, terminal):
    if terminal == "dumb":
        pytest.skip("a dumb terminal cannot go back up to the typed line")
    child.sendline("2 3 + .")
    child.expect_exact("2 3 + . 5  ok")


def test_no_ok_while_a_definition_is_open(child):
    child.sendline(": CUBE DUP DUP")
    child.sendline("* * ;")
    child.expect_exact(" ok")
    child.sendline("3 CUBE .")
    child.expect_exact("27  ok")
    assert "DUP DUP  ok" not in child.before


def test_bye_leaves_with_status_zero(child):
    child.sendline("BYE")
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0


def test_ctrl_c_interrupts_a_running_word_and_the_prompt_goes_on(child):
    child.sendline(": FOREVER BEGIN 1 . AGAIN ; FOREVER")
    child.expect_exact("1 1 1 ")
    child.sendintr()
    child.expect_exact("Interrupted")
    child.sendline("2 .")
    child.expect_exact("2  ok")


def test_ctrl_c_at_the_prompt_clears_the_line(child):
    child.send("4 .")
    child.sendintr()
    child.sendline("5 .")
    child.expect_exact("5  ok")
    assert "4  ok" not in child.before and "4 5" not in child.before


def test_accept_reads_a_line_from_the_user(child):
    child.sendline("PAD 80 ACCEPT PAD SWAP TYPE")
    child.sendline("typed")
    child.expect_exact("typed ok")


def test_clock_meta_command_shows_virtual_seconds(child):
    child.sendline("#clock")
    child.expect(r"clock \d+\.\d+ s")


def test_page_clears_a_terminal_as_terminals_expect(child, terminal):
    """PAGE's form feed reaches a terminal as ANSI's erase-screen and
    cursor-home (a terminal shows a bare form feed as a line feed at
    best); a dumb terminal gets the form feed itself."""
    child.sendline("1 . PAGE 2 .")
    if terminal == "dumb":
        child.expect_exact("1 \f2  ok")
    else:
        child.expect_exact("1 \x1b[2J\x1b[H2  ok")
    ctrl_d(child)


def test_a_file_error_at_a_terminal_stops_the_later_e_but_the_prompt_opens(tmp_path):
    bad = tmp_path / "bad.fs"
    bad.write_text("foo\n")
    env = dict(os.environ, HOME=str(tmp_path), PYTHONPATH=ROOT, TERM="dumb")
    child = pexpect.spawn(sys.executable, ["-m", "rcl", str(bad), "-e", "111 ."], env=env,
                          encoding="utf-8", timeout=TIMEOUT, dimensions=(24, 80))
    try:
        child.expect_exact("bad.fs:1: FOO  ?")
        child.sendline("2 3 + .")
        child.expect_exact("5  ok")
        assert "111" not in child.before
        ctrl_d(child)
    finally:
        close(child)
    assert "Traceback" not in child.before
