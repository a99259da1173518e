"""A host that answers its ticks late (a busy machine) against a board that
does not wait for it: the move's failure is reported as the host's, with
the figure (` Host too slow `), not as a following error the user would
blame on the motors (docs/protocol.md section 5)."""
import re
import subprocess
import sys
import time

import pytest

import rcl


@pytest.fixture
def free_running_board():
    proc = subprocess.Popen([sys.executable, "-m", "rcl.hw.boardcli", "--pty", "--free-running"],
                            stdout=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True)
    yield proc.stdout.readline().strip()
    proc.terminate()
    proc.wait(10)


def late_host(m, seconds):
    """Every tick's answer `seconds` late: the handler starts that long
    after its TICK came (the machine's own run_tick, delayed)."""
    run_tick = m.board.run_tick

    def late(machine, tick):
        time.sleep(seconds)
        return run_tick(machine, tick)
    m.board.run_tick = late


def test_a_host_150_ms_late_with_every_tick_is_told_host_too_slow_with_the_figure(
        free_running_board):
    m = rcl.open(port=free_running_board)
    try:
        late_host(m, 0.150)
        with pytest.raises(rcl.ForthError) as e:
            m.evaluate("RERB 2 MPH 3.4 FEET FORWARD")
        found = re.fullmatch(r"Host too slow: answered tick (\d+) after (\d+) ms", e.value.message)
        assert found, e.value.message
        assert int(found.group(2)) >= 150
        assert e.value.screen().startswith(" Host too slow")
        m.board.run_tick = type(m.board).run_tick.__get__(m.board)   # on time again
        assert m.evaluate("2 2 + .") == "4 "                 # the session goes on
    finally:
        m.board.close()


def test_a_late_host_on_a_lockstep_board_moves_as_on_time_and_is_never_told_it_is_too_slow():
    # A lockstep board waits for its host: lateness costs nothing there.
    m = rcl.open(port="rclsim://?rate=4")
    try:
        late_host(m, 0.060)
        assert m.evaluate("RERB 2 INCHES FORWARD") == ""
        assert m.board.late_answer is None
    finally:
        m.board.close()
