"""The page's Python side (rcl.web.session) and the site's build (rcl.web.build,
rcl-web) on this Python: no browser, no node. The browser runs this same
session inside Pyodide (tests/test_web_page.py)."""
import json
import os
import subprocess
import sys
import zipfile

import pytest

import rcl
from rcl.sim.observe import Trace
from rcl.web import build
from rcl.web.session import Session

COMMAND = "RERB 2 MPH 3.4 FEET FORWARD"


def session(**kw):
    sent = []
    s = Session(lambda kind, data: sent.append((kind, data)), rate=0, **kw)
    s.banner()
    return s, sent


def test_the_first_command_observed_by_the_page_ends_with_rcl_opens_counts():
    s, sent = session()
    assert s.submit(COMMAND) == ""
    m = rcl.open()
    trace = Trace(m.board, keep=True)
    m.evaluate(COMMAND)
    assert s.m.sim.wheel_counts == m.sim.wheel_counts              # watching changes nothing
    path = [v for kind, data in sent if kind == "frame" for v in data["path"]]
    assert [v for r in trace.rows for v in r[1:3]] == path         # the board's own trace, in order
    last = [data for kind, data in sent if kind == "frame"][-1]
    assert (last["x"], last["y"]) == s.m.sim.pose[:2] and "figure" not in last
    s.settle()                                                     # after the prompt: Fig. 1
    last = [data for kind, data in sent if kind == "frame"][-1]
    assert last["figure"]["acc"] and last["figure"]["limit"] == 100   # Fig. 1: FERR-LIMIT


def test_a_frame_says_the_wall_clock_and_how_far_the_rate_is_behind():
    s = Session(lambda kind, data: None, rate=1000)
    s.banner()
    s.evaluate("RERB 2 MPH 3.4 FEET FORWARD")
    pacer, state = s.m.board.pacer, s.state()
    assert state["rate"] == 1000 and state["wall"] > 0
    assert pacer.ticks > 100 and state["behind"] == pacer.lateness[-1] >= 0   # paced tick by tick


def test_the_screen_is_the_terminals_ok_errors_and_the_open_definitions_prompt():
    s, sent = session()
    assert s.evaluate("2 3 + .") == " 5  ok"
    assert s.submit(": SQ  DUP *") == "SQ] "
    assert s.submit(";") == ""
    assert s.evaluate("7 SQ .") == " 49  ok"
    assert s.evaluate("FOO") == " FOO  ? "
    assert "FOO" in "".join(data for kind, data in sent if kind == "out")


def test_tab_completes_the_words_of_the_search_order():
    s, _ = session()
    assert "FORWARD" in s.complete("forw")
    assert s.complete("") == []


def test_save_system_is_offered_to_the_page_as_a_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    s, sent = session(folder=str(tmp_path))
    s.submit("SAVE-SYSTEM mine.img")
    assert ("files", ["mine.img"]) in sent
    again = Session(lambda kind, data: None, rate=0, image=str(tmp_path / "mine.img"))
    assert again.evaluate("2 3 + .") == " 5  ok"


def test_the_programs_are_the_articles_listings_and_the_screens():
    s, _ = session()
    names = dict(s.programs())
    assert "examples/listing1.fs" in names and "rcl.fs" in names
    assert "3.5 FEET FORWARD 90 DEGREES LEFT" in names["examples/listing1.fs"]


def test_the_wheel_holds_rcl_its_kernel_and_screens_but_not_the_page(tmp_path):
    name = build.build_wheel(str(tmp_path))
    with zipfile.ZipFile(tmp_path / name) as z:
        files = set(z.namelist())
        record = z.read("rcl-%s.dist-info/RECORD" % rcl.__version__).decode()
    assert {"rcl/__init__.py", "rcl/web/session.py", "rcl/screens/rcl.fs",
            "rcl/screens/examples/listing1.fs"} <= files
    assert any(f.startswith("rcl/kernel/") for f in files)
    assert not any(f.endswith((".js", ".html")) or "node_modules" in f for f in files)
    assert all(f in record for f in files)


def rcl_web(*args, path=None):
    env = dict(os.environ)
    if path is not None:
        env["PATH"] = path
    return subprocess.run([sys.executable, "-m", "rcl.web.cli", *args], capture_output=True,
                          text=True, timeout=120, env=env)


def test_rcl_web_build_says_node_and_npm_are_needed_when_missing(tmp_path):
    done = rcl_web("build", str(tmp_path / "site"), path=str(tmp_path))
    assert done.returncode == 1
    assert "needs node and npm" in done.stderr and "Traceback" not in done.stderr


def test_rcl_web_serve_refuses_a_folder_without_a_built_site(tmp_path):
    done = rcl_web("serve", str(tmp_path), "--no-browser")
    assert done.returncode == 2
    assert "rcl-web build" in done.stderr and "Traceback" not in done.stderr


def test_the_page_gets_frames_as_json_text_with_the_same_pen_points():
    sent = []
    s = Session(lambda kind, data: sent.append((kind, data)), rate=0, frames_as_json=True)
    s.banner()
    s.submit(COMMAND)
    s.settle()
    frames = [json.loads(data) for kind, data in sent if kind == "frame"]
    m = rcl.open()
    trace = Trace(m.board, keep=True)
    m.evaluate(COMMAND)
    assert [v for f in frames for v in f["path"]] == [v for r in trace.rows for v in r[1:3]]
    assert frames[-1]["figure"]["limit"] == 100


def test_a_stop_taken_at_a_tick_sends_the_motors_off_before_interrupted():
    """The page's stop flag, seen by the session at a tick's end in the
    middle of `1 MILES FORWARD`: a frame with every relay open goes out
    before ` Interrupted`, the word ends there, and the next move works."""
    sent, ticks, stops = [], [], []

    def stop_asked():
        # The page's flag: set once, when the wheels have driven 100 ticks
        # and the page has drawn them driving (frames go out by the wall
        # clock: at full speed 100 ticks could all fall between two).
        if s is None or not s.m.board.motor_latch or stops:
            return False
        ticks.append(1)
        if len(ticks) >= 100 and any(kind == "frame" and data["motor"] == 0x35
                                     for kind, data in sent):
            stops.append(1)
            return True
        return False
    s = None
    s = Session(lambda kind, data: sent.append((kind, data)), rate=0, stop_asked=stop_asked)
    s.banner()
    s.submit("1 MILES FORWARD")
    frames = [i for i, (kind, data) in enumerate(sent) if kind == "frame"]
    driven = [i for i in frames if sent[i][1]["motor"] == 0x35]     # M1/M2 ON and GO: both wheels driven
    said = [i for i, (kind, data) in enumerate(sent) if kind == "out" and "Interrupted" in data]
    assert driven and len(said) == 1
    off = [i for i in frames if driven[-1] < i < said[0]]
    assert off and sent[off[0]][1]["motor"] == 0 and sent[off[0]][1]["aux"] == 0
    assert sent[off[0]][1]["t"] <= s.m.sim.seconds
    assert s.m.board.motor_latch == 0
    stopped = s.m.sim.pose[0]
    assert 0 < stopped < 12 * 5280 / 10                     # far short of the mile
    assert s.evaluate(COMMAND) == "  ok"
    assert s.m.sim.pose[0] - stopped == pytest.approx(40.8, abs=0.5)   # the 3.4 feet from there


def test_dbg_reads_single_keys_from_the_page_and_a_stop_there_interrupts():
    """DBG's keys come through the page's read_key (no Enter); a stop while
    it waits answers Ctrl-C (3), which interrupts as at the terminal's KEY."""
    keys = [13, ord("c")]
    s = Session(lambda kind, data: None, rate=0, read_key=lambda: keys.pop(0))
    s.banner()
    s.evaluate(": THREE  1 . 2 . 3 . ;")
    out = s.evaluate("DBG THREE").splitlines()
    assert out[1] == "DBG THREE   Enter step  I into  O over  F finish  C continue  Q stop"
    assert out[2].startswith("  (typed)  THREE > .  ( 1 )  00:00:00")
    assert out[3:5] == ["1 ", "  (typed)  THREE > .  ( 2 )  00:00:00  x 0.0 y 0.0 in  heading 0.0"]
    assert out[5] == "2 3 " and out[6].startswith("  done  ( )") and out[6].endswith(" ok")
    keys[:] = [3]
    assert s.evaluate("DBG THREE").splitlines()[-1].rstrip().endswith(" Interrupted")
    assert s.evaluate("2 3 + .") == " 5  ok"


def test_a_stop_that_comes_as_the_line_ends_is_not_left_for_the_next():
    """The page's stop flag seen after the line (Fig. 1 worked out after the
    prompt, an idle catch-up) is not taken: the next line runs."""
    flag = [False]
    s = Session(lambda kind, data: None, rate=1000, stop_asked=lambda: flag[0])
    s.banner()
    assert s.submit(COMMAND) == ""
    flag[0] = True
    s.settle()                                  # Fig. 1 of the line: taken between ticks
    s.catch_up()
    assert not s.m.break_pending
    flag[0] = False
    assert s.evaluate("2 3 + .") == " 5  ok"
