"""Leaving, and the smaller hazards: BYE, end of input, SIGTERM and SIGHUP
leave the robot in its safe state; the abort hook is the kernel's DEFER and
the motors are stopped after it too; EMPTY and FORGET stop at RCL's fence;
bad files, characters and output streams get a clear message."""
import io
import os
import signal
import subprocess
import sys

import pytest

import rcl
from rcl import cli

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MOTOR_ON = "M1-ON M1-GO OR M2-ON OR M2-GO OR ENABLE  ARM-ON ENABLE"


def motors_off(m):
    motor, aux = m.sim.relays
    return motor & 0x3F == 0 and aux & 0x0F == 0


def run_cli(monkeypatch, stdin_text, *argv):
    """rcl's main in this process, on a pipe; -> (status, output, machine)."""
    machines = []
    make = cli.make_machine

    def keep(args, write):
        machines.append(make(args, write))
        return machines[-1]
    monkeypatch.setattr(cli, "make_machine", keep)
    monkeypatch.setattr(sys, "stdin", io.StringIO(stdin_text))
    out = io.StringIO()
    monkeypatch.setattr(sys, "stdout", out)
    status = cli.main(list(argv))
    return status, out.getvalue(), machines[0]


# ------------------------------------------------------------------ leaving
def test_bye_leaves_a_python_callers_robot_stopped():
    m = rcl.open()
    with pytest.raises(rcl.Bye):
        m.evaluate(MOTOR_ON + "  BYE")
    assert motors_off(m)


def test_the_end_of_piped_input_leaves_the_robot_stopped(monkeypatch):
    status, _, m = run_cli(monkeypatch, MOTOR_ON + "\n")
    assert status == 0 and motors_off(m)


def test_bye_in_a_pipe_leaves_the_robot_stopped(monkeypatch):
    status, _, m = run_cli(monkeypatch, MOTOR_ON + " BYE\n1 .\n")
    assert status == 0 and motors_off(m)


@pytest.mark.parametrize("signame", ["SIGTERM", "SIGHUP"])
def test_a_signal_during_a_move_stops_the_robot_and_leaves(monkeypatch, signame):
    signum = getattr(signal, signame)
    sent = []

    def send_during_the_move(board):
        if board.ticks == 50 and not sent:
            sent.append(board.machine.masked)
            os.kill(os.getpid(), signum)       # lands inside the tick handler
    previous = signal.getsignal(signum)
    machines = []
    make = cli.make_machine

    def keep(args, write):
        m = make(args, write)
        m.sim.board.observers = [send_during_the_move]
        machines.append(m)
        return m
    monkeypatch.setattr(cli, "make_machine", keep)
    monkeypatch.setattr(sys, "stdin", io.StringIO("RERB 2 MPH 10 FEET FORWARD\n1 .\n"))
    monkeypatch.setattr(sys, "stdout", io.StringIO())
    status = cli.main([])
    m = machines[0]
    assert status == 128 + signum
    assert sent and motors_off(m)
    assert sys.stdout.getvalue() == ""                     # the next line never ran
    assert signal.getsignal(signum) == previous


def test_sigterm_while_rcl_waits_for_input_stops_it_at_once():
    proc = subprocess.Popen([sys.executable, "-m", "rcl", "-e", "1 ."],
                            stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, cwd=ROOT, text=True)
    proc.stdin.write(MOTOR_ON + "\n")
    proc.stdin.flush()
    proc.stdout.read(2)                                    # "1 " : it is running
    proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 128 + signal.SIGTERM
    assert "Traceback" not in err


# -------------------------------------------------------------- the abort hook
def test_a_word_named_on_abort_is_not_the_abort_hook():
    m = rcl.open()
    m.evaluate("VARIABLE RAN  : ON-ABORT  1 RAN !  " + MOTOR_ON + " ;")
    with pytest.raises(rcl.ForthError):
        m.evaluate(MOTOR_ON + "  UNKNOWN-WORD")
    assert m.evaluate("RAN ?") == "0 " and motors_off(m)


def test_the_motors_are_stopped_after_the_abort_hook_whatever_it_does():
    m = rcl.open()
    m.evaluate(": RESTART  " + MOTOR_ON + " ;  ' RESTART IS ON-ABORT")
    with pytest.raises(rcl.ForthError):
        m.evaluate(MOTOR_ON + "  UNKNOWN-WORD")
    assert motors_off(m)


def test_an_abort_hook_that_never_ends_gets_a_virtual_second():
    m = rcl.open()
    m.evaluate(": FOREVER  BEGIN AGAIN ;  ' FOREVER IS ON-ABORT")
    start = m.clock
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate(MOTOR_ON + "  UNKNOWN-WORD")
    assert e.value.word == "UNKNOWN-WORD"                  # the error, not the hook's
    assert motors_off(m)
    assert (m.clock - start) / 36e9 < 1.1


# ------------------------------------------------------------------- the fence
def test_empty_forgets_the_users_words_and_keeps_rcl():
    m = rcl.open()
    m.evaluate(": MINE  1 ;  EMPTY")
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("MINE")
    assert e.value.word == "MINE"
    m.evaluate("RERB 1 FEET FORWARD  100 MS")
    assert m.sim.wheel_counts[0] > 330


@pytest.mark.parametrize("word", ["(CONTROL)", "FORWARD", "CONTROL", "INSTALL", "FIXED"])
def test_forget_of_an_rcl_word_is_below_the_fence(word):
    m = rcl.open()
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("FORGET " + word)
    assert e.value.message == "Below fence"
    m.evaluate(": ANYTHING  1 2 3 ;  RERB 1 FEET FORWARD")
    assert m.sim.wheel_counts[0] > 330


# ---------------------------------------------------- files, characters, output
def test_including_a_directory_says_so(tmp_path):
    m = rcl.open()
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("INCLUDE " + str(tmp_path))
    assert e.value.message == "Is a directory"


def test_a_character_outside_latin_1_is_refused_and_fs_question_mark_stays():
    m = rcl.Forth()
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate(": \N{GREEK SMALL LETTER PI}  3 ;")
    assert e.value.message == "Not a Latin-1 character: '\N{GREEK SMALL LETTER PI}'"
    assert m.evaluate("VARIABLE X  5 X !  X ?") == "5 "
    assert m.evaluate(": CAF\N{LATIN SMALL LETTER E WITH ACUTE}  7 ;  CAF\N{LATIN SMALL LETTER E WITH ACUTE} .") == "7 "


def rcl_process(*args, **kwargs):
    return subprocess.run([sys.executable, "-m", "rcl"] + list(args), cwd=ROOT,
                          capture_output=True, text=True, timeout=60, **kwargs)


def test_standard_output_closed_is_said_on_stderr():
    done = subprocess.run([sys.executable, "-m", "rcl", "-e", "1 ."], cwd=ROOT,
                          stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                          timeout=60, preexec_fn=lambda: os.close(1))
    assert done.returncode == 1
    assert done.stderr == "rcl: cannot write standard output: standard output is closed\n"


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full here")
def test_standard_output_full_is_said_on_stderr():
    with open("/dev/full", "w") as full:
        done = subprocess.run([sys.executable, "-m", "rcl", "-e", "1 ."], cwd=ROOT,
                              stdout=full, stderr=subprocess.PIPE, text=True, timeout=60)
    assert done.returncode == 1
    assert done.stderr == "rcl: cannot write standard output: No space left on device\n"


def test_a_saved_system_keeps_rcl_below_the_fence(tmp_path):
    image = tmp_path / "robot.img"
    m = rcl.open()
    m.evaluate(": MINE  1 ;  SAVE-SYSTEM " + str(image))
    m = rcl.open(image=str(image))
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("FORGET (CONTROL)")
    assert e.value.message == "Below fence"
    assert m.evaluate("MINE .") == "1 "                    # the user's word is above it
    m.evaluate("EMPTY  RERB 1 FEET FORWARD  100 MS")
    assert m.sim.wheel_counts[0] > 330


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads any file")
def test_an_unreadable_file_says_permission_denied(tmp_path):
    source = tmp_path / "secret.fs"
    source.write_text("1 .\n")
    source.chmod(0)
    m = rcl.Forth()
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("INCLUDE " + str(source))
    assert e.value.message == "Permission denied"


CTRL_C_DURING_IMPORT = """
import importlib.abc, os, runpy, signal, sys
AT = sys.argv[1]
class CtrlC(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == AT:
            os.kill(os.getpid(), signal.SIGINT)   # taken at the next bytecode
        return None
sys.meta_path.insert(0, CtrlC())
sys.argv = ["rcl"]
runpy.run_module("rcl", run_name="__main__", alter_sys=True)
"""


@pytest.mark.parametrize("module", ["rcl.forth.machine", "rcl.words.core",
                                    "rcl.sim.board", "rcl.repl", "rcl.startcache"])
def test_ctrl_c_while_rcl_starts_leaves_quietly(module, tmp_path):
    """Ctrl-C as rcl loads each part (the 0.45 s before the prompt): exit
    status 130, no Python traceback."""
    env = dict(os.environ, PYTHONPATH=ROOT, RCL_CACHE_DIR=str(tmp_path))
    done = subprocess.run([sys.executable, "-c", CTRL_C_DURING_IMPORT, module],
                          stdin=subprocess.PIPE, capture_output=True, text=True,
                          env=env, timeout=60)
    assert "Traceback" not in done.stderr
    assert done.returncode == 130
