"""Ctrl-C at a real terminal in the middle of a long move, as a user does
it: the `rcl` console script on a pty (pexpect), the default fast clock.
After it the robot is stopped, the 10 ms tick still runs (`.TIME 1000 MS
.TIME` moves on), the next move completes and the counters read what the
wheels did. The delays only choose where the Ctrl-C lands; nothing is
asserted about time. The timeouts only bound a hung child."""
import io
import os
import shutil
import sys
import time

import pytest

pexpect = pytest.importorskip("pexpect")
from pty_support import close  # noqa: E402  (after the skip without pexpect)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMEOUT = 120
FOOT = 341                                   # counts in 1 FEET


def command():
    """The installed console script, else the same entry point by -m."""
    script = os.path.join(os.path.dirname(sys.executable), "rcl")
    script = script if os.path.exists(script) else shutil.which("rcl")
    return (script, []) if script else (sys.executable, ["-m", "rcl"])


@pytest.fixture
def console(tmp_path):
    program, args = command()
    env = dict(os.environ, HOME=str(tmp_path), XDG_DATA_HOME=str(tmp_path / "data"),
               PYTHONPATH=ROOT, TERM="xterm", PROMPT_TOOLKIT_NO_CPR="1")
    child = pexpect.spawn(program, args, env=env, encoding="utf-8", timeout=TIMEOUT,
                          dimensions=(24, 80))
    child.logfile_read = io.StringIO()          # the screen, for a failure's report
    child.expect("BYE to leave")
    yield child
    close(child)


def values(child, line, label, n=2):
    child.sendline(line)
    found = []
    try:
        for _ in range(n):
            child.expect(label + r"=(-?[\d:]+) ")
            found.append(child.match.group(1))
        child.expect_exact(" ok")
    except pexpect.TIMEOUT:
        # (a busy run once saw no answer here in 120 s: say what the screen held)
        raise AssertionError("no answer to %r in %d s; the screen's last 2000 characters: %r"
                             % (line, child.timeout, child.logfile_read.getvalue()[-2000:])) from None
    return found


@pytest.mark.parametrize("delay", [0.2, 0.7, 1.5])
def test_ctrl_c_mid_move_stops_the_robot_and_the_tick_goes_on(console, delay):
    # ten hours of simulated driving: not over before the Ctrl-C even on
    # PyPy on a loaded machine (one mile once was)
    console.sendline("RERB 1 MPH 10 MILES FORWARD")
    # the move is under way, as the status line shows (a Ctrl-C typed
    # while the prompt still reads the line would be taken as a key there,
    # and the move would run its ten hours)
    console.expect_exact("moving")
    time.sleep(delay)
    console.sendintr()
    console.expect_exact("Interrupted")
    before, after = values(console, '.( T=) .TIME  1000 MS  .( T=) .TIME', "T")
    assert before != after
    start = [int(v) for v in values(console, '.( C=) ?CNT1 D. .( C=) ?CNT2 D.', "C")]
    end = [int(v) for v in values(
        console, 'RERB 2 MPH 1 FEET FORWARD  1000 MS  .( C=) ?CNT1 D. .( C=) ?CNT2 D.', "C")]
    assert [e - s for s, e in zip(start, end)] == pytest.approx([FOOT, FOOT], abs=4)
    console.sendline("BYE")
    console.expect(pexpect.EOF)
