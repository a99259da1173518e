"""DBG and BREAK: from the console script, as a user runs them: on a pty
(pexpect, as the other pty tests do) and from a pipe. The keys go
through KEY's path: one key at the prompt, the next character from a
pipe. The timeouts only bound a hung child; nothing is asserted about
speed."""
import csv
import os
import re
import subprocess
import sys

import pytest

pexpect = pytest.importorskip("pexpect")

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMEOUT = 60
MOTOR_BITS = 0x35               # M1-ON M2-ON M1-GO M2-GO: MOTOR latch bits 0, 2, 4, 5
ESCAPES = re.compile(r"\x1b7.*?\x1b8|\x1b\[[0-9;?]*[A-Za-z]|\r", re.S)
# TRIP's first row (listing5.fs line 19) and its BACKWARD, run plainly,
# observed by a BREAK: that costs no time
TRIP1 = ": TRIP1  WARNING RERB 20 IPS 3 FEET BACKWARD BREAK: TURN-AROUND ;\n"


def spawn(tmp_path, *args, term="dumb"):
    env = dict(os.environ, HOME=str(tmp_path), XDG_DATA_HOME=str(tmp_path / "data"),
               PYTHONPATH=ROOT, TERM=term, PROMPT_TOOLKIT_NO_CPR="1")
    child = pexpect.spawn(sys.executable, ["-m", "rcl", *args], env=env, encoding="utf-8",
                          timeout=TIMEOUT, dimensions=(24, 200))
    child.expect("BYE to leave")
    return child


BOARD = r"\d\d:\d\d:\d\d  x -?\d+\.\d y -?\d+\.\d in  heading \d+\.\d"


def step_line(child, board=True):
    """The next step line of the view: (place, chain > word, time and pose).
    (Each line of the view starts with a new line; the last one waits for
    its key without one.)"""
    child.expect(r"\n  (\S+:\d+)  (\S+(?: > \S+)*)  \([^)]*\)(  %s)%s" % (
        BOARD, "" if board else "?"))
    return child.match.group(1), child.match.group(2), child.match.group(3).strip()


@pytest.fixture
def trip_files(tmp_path):
    path = tmp_path / "trip1.fs"
    path.write_text(TRIP1)
    return ["examples/listing5.fs", str(path)]


def test_stepping_trip_on_the_console(tmp_path, trip_files):
    # the plain run: TRIP's first row, compiled, seen at its end
    plain = spawn(tmp_path, *trip_files)
    plain.sendline("TRIP1")
    plain.expect_exact(" BREAK:")
    place, word, plain_end = step_line(plain)
    assert (place, word) == ("trip1.fs:1", "TRIP1 > TURN-AROUND")
    plain.send("q")
    plain.expect_exact(" Stopped ")
    plain.close(force=True)

    trace = tmp_path / "t.csv"
    child = spawn(tmp_path, "--trace", str(trace), *trip_files)
    child.sendline("DBG TRIP")
    child.expect_exact("DBG TRIP   Enter step  I into  O over  F finish  C continue  Q stop")
    seen = [step_line(child)]
    for _ in range(8):
        child.send("o")
        if seen[-1][1] == "TRIP > BACKWARD":
            child.expect(r"\n  BACKWARD ended at (%s)" % BOARD)
            stepped_end = child.match.group(1)
        seen.append(step_line(child))
    assert [(place, word) for place, word, _ in seen] == [
        ("listing5.fs:19", "TRIP > WARNING"), ("listing5.fs:19", "TRIP > RERB"),
        ("listing5.fs:19", "TRIP > IPS"), ("listing5.fs:19", "TRIP > FEET"),
        ("listing5.fs:20", "TRIP > BACKWARD"), ("listing5.fs:20", "TRIP > TURN-AROUND"),
        ("listing5.fs:20", "TRIP > AHEAD"), ("listing5.fs:21", "TRIP > TURN-RIGHT"),
        ("listing5.fs:21", "TRIP > AHEAD")]
    # the same time of day and pose as the plain run's at that point
    assert stepped_end == plain_end
    assert re.match(r"00:00:\d\d  x -3[56]\.\d y -?0\.\d in  heading (0|359)\.\d$", stepped_end)

    # into AHEAD, over FEET, into FORWARD and (MOVE), over each word to
    # its wait, into the wait (AWAIT) and over two of its HALTs: the
    # wheels run two ticks; Q there
    for key, word in zip("ioii", ["FEET", "FORWARD", "(MOVE)", "?CONTROL"]):
        child.send(key)
        assert step_line(child)[1].split(" > ")[-1] == word
    for _ in range(60):
        child.send("o")
        if step_line(child)[1] == "TRIP > AHEAD > FORWARD > (MOVE) > WAIT-MOVE":
            break
    for key, word in zip("ioi", ["MOVING", "AWAIT", "PICK"]):
        child.send(key)
        assert step_line(child)[1].split(" > ")[-1] == word
    halts = 0
    while halts < 2:
        child.send("o")
        halts += step_line(child)[1].endswith("> HALT")
    child.send("oq")
    child.expect_exact(" Stopped ")
    child.sendline("#clock")
    child.expect(r"clock ([\d.]+) s")
    stopped_at = float(child.match.group(1))
    child.sendline("100 MS")                  # ticks that trace the stopped motors
    child.expect_exact(" ok")
    child.sendline("BYE")
    child.expect(pexpect.EOF)
    with open(trace) as f:
        rows = [(float(r["t"]), int(r["motor"])) for r in csv.DictReader(f)]
    # both wheels on up to the stop, off from the first tick after it (a
    # tick is 10.0005 ms), not at BYE
    on = max(i for i, (t, motor) in enumerate(rows) if motor & MOTOR_BITS == MOTOR_BITS)
    assert stopped_at - 0.05 < rows[on][0] < stopped_at
    assert rows[on + 1][0] <= stopped_at + 0.0101
    assert all(motor & MOTOR_BITS == 0 for t, motor in rows[on + 1:]), rows[on:]


def test_ctrl_c_while_the_view_waits_interrupts_and_the_prompt_goes_on(tmp_path):
    child = spawn(tmp_path, term="xterm")
    child.sendline(": FOO  1 2 + ;")
    child.expect_exact(" ok")
    child.sendline("DBG FOO")
    child.expect_exact("FOO > +")
    child.sendintr()
    child.expect_exact(" Interrupted ")
    child.sendline("2 3 + .")
    child.expect_exact("5  ok")
    child.close(force=True)


def test_ctrl_c_in_a_move_stepped_over_interrupts_it_and_the_next_move_runs(tmp_path):
    child = spawn(tmp_path, term="xterm")
    child.sendline(": LONG  RERB 1 MPH 10 MILES FORWARD ;")
    child.expect_exact(" ok")
    child.sendline("DBG LONG")
    child.expect_exact("LONG > RERB")
    child.send("c")
    child.expect_exact("moving")             # the status line: the move is under way
    child.sendintr()
    child.expect_exact(" Interrupted ")
    child.sendline("RERB 1 FEET FORWARD")
    child.expect_exact(" ok")
    child.close(force=True)


@pytest.mark.parametrize("term", ["xterm", "dumb"])
def test_break_stops_at_the_prompt_and_breaks_off_runs_through(tmp_path, term):
    child = spawn(tmp_path, term=term)
    child.sendline(': FOO  1 BREAK" half way" 2 + . ;')
    child.expect_exact(" ok")
    child.sendline("FOO")
    child.expect_exact(' BREAK" half way"')
    child.expect_exact("FOO > +  ( 1 2 )")
    child.send("c")
    child.expect_exact("3 ")
    child.expect_exact("  done  ( )")
    child.expect_exact(" ok")
    child.sendline("BREAKS OFF FOO")
    child.expect(r"\n(.*)3  ok")
    assert "half way" not in ESCAPES.sub("", child.match.group(1))
    child.close(force=True)


def run_pipe(text, *args):
    done = subprocess.run([sys.executable, "-m", "rcl", *args], input=text.encode(),
                          capture_output=True, timeout=120,
                          env=dict(os.environ, PYTHONPATH=ROOT))
    return done.returncode, done.stdout.decode()


def test_break_stops_in_a_pipe_and_takes_its_keys_from_it():
    status, out = run_pipe(': FOO  1 BREAK" here" 2 + . ;\nFOO\nc\n.( next)\n'
                           "BREAKS OFF FOO\n", "--bare")
    assert status == 0
    assert out.split("\n")[1:5] == [' BREAK" here"', "  (typed)  FOO > +  ( 1 2 )",
                                     "3 ", "  done  ( )"]
    assert out.count("BREAK") == 1 and "next" in out and out.count("3 ") == 2


def test_dbg_from_a_pipe_steps_on_each_new_line():
    status, out = run_pipe(": SQ DUP * ;\n3 DBG SQ\n\n\n.\n", "--bare")
    assert status == 0
    assert "  (typed)  SQ > DUP  ( 3 )" in out and "  (typed)  SQ > *  ( 3 3 )" in out
    assert "done  ( 9 )" in out and "9 " in out
