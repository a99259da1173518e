"""The link's session as a state machine (rcl/hw/session.py, docs/link.md
"The session"), its reasons for a lost link, its request record, usb://
URLs, and the host judging a silent board only at the moments it has read
everything waiting (rcl/hw/liveness.py): a host thread kept from running
on a busy machine is not a silent board."""
import collections
import os
import pathlib
import subprocess
import sys
import threading
import time

import pytest

import rcl
from rcl.hw.protocol import LinkError
from rcl.hw.session import (ASKING, TRANSITIONS, Cause, IllegalTransition, Loss, Request,
                            Session,
                            State)

S = State
DOCS = pathlib.Path(__file__).resolve().parent.parent / "docs"


def path_to(state):
    """The moves from CLOSED to `state` (breadth first)."""
    came = {S.CLOSED: None}
    todo = collections.deque([S.CLOSED])
    while todo:
        here = todo.popleft()
        for there in TRANSITIONS[here]:
            if there not in came:
                came[there] = here
                todo.append(there)
    steps = []
    while state is not S.CLOSED:
        steps.append(state)
        state = came[state]
    return steps[::-1]


def session_in(state):
    s = Session()
    for step in path_to(state):
        s.go(step)
    assert s.state is state
    return s


# ------------------------------------------------------- the state machine
def test_every_state_is_reached_from_closed_and_leads_back_to_it():
    for state in S:
        assert path_to(state) or state is S.CLOSED
        # and CLOSED is reachable from it: no state traps the link
        seen, todo = {state}, [state]
        while todo:
            for there in TRANSITIONS[todo.pop()]:
                if there not in seen:
                    seen.add(there)
                    todo.append(there)
        assert S.CLOSED in seen, state


@pytest.mark.parametrize("start,end", [(a, b) for a in S for b in sorted(TRANSITIONS[a],
                                                                       key=lambda s: s.name)],
                         ids=lambda s: s.name)
def test_each_transition_is_taken(start, end):
    s = session_in(start)
    s.go(end)
    assert s.state is end and s.history[-1] == (start, end)


@pytest.mark.parametrize("start,end", [(a, b) for a in S for b in S if b not in TRANSITIONS[a]],
                         ids=lambda s: s.name)
def test_each_illegal_transition_is_refused_and_changes_nothing(start, end):
    s = session_in(start)
    moves = len(s.history)
    with pytest.raises(IllegalTransition) as e:
        s.go(end)
    assert str(e.value) == "link session: %s -> %s" % (start.name, end.name)
    assert s.state is start and len(s.history) == moves
    with pytest.raises(IllegalTransition):          # tested and moved in one step: refused too
        s.leave({start}, end)
    assert s.state is start and len(s.history) == moves


def test_leave_moves_only_from_the_states_it_names():
    s = session_in(S.RUNNING)
    assert not s.leave({S.HELLO_SENT}, S.LOST) and s.state is S.RUNNING
    assert s.leave({S.IDENTIFIED, S.RUNNING}, S.LOST) and s.state is S.LOST


def test_the_document_draws_every_state_and_transition():
    text = (DOCS / "link.md").read_text()
    for start, ends in TRANSITIONS.items():
        for end in ends:
            assert "| %s | %s |" % (start.name, end.name) in text, (start, end)
    assert ASKING == {S.IDENTIFIED, S.RUNNING, S.LEAVING}


# ------------------------------------------------ a LinkBoard's own session
def test_a_links_life_walks_the_documented_states():
    m = rcl.open(port="rclsim://?rate=4")
    board, server = m.board, m.board.port.server
    try:
        assert list(board.session.history) == [(S.CLOSED, S.OPENING), (S.OPENING, S.HELLO_SENT),
                                         (S.HELLO_SENT, S.IDENTIFIED),
                                         (S.IDENTIFIED, S.RUNNING)]
        assert board.status().startswith("link up: rcl-board")
        server.cut_link()
        end = time.monotonic() + 30
        while not board.lost and time.monotonic() < end:
            time.sleep(0.01)
        assert board.session.state is S.LOST and board.loss.cause is Cause.SILENT
        assert board.why == "no frame from the board for 250 ms"
        assert board.status().startswith("link lost (no frame from the board for 250 ms)")
        server.cut_link(False)
        assert m.evaluate("RECONNECT").startswith(" Link up")
        assert list(board.session.history)[-3:] == [(S.LOST, S.HELLO_SENT),
                                              (S.HELLO_SENT, S.IDENTIFIED),
                                              (S.IDENTIFIED, S.RUNNING)]
        assert board.loss is None and board.why == ""
    finally:
        board.close()
    assert list(board.session.history)[-2:] == [(S.RUNNING, S.LEAVING), (S.LEAVING, S.CLOSED)]
    assert server.board.motor_latch == 0
    board.close()                                    # twice: nothing more happens
    assert board.session.state is S.CLOSED


def test_leave_runs_first_before_the_move_and_only_when_it_moves():
    s, seen = session_in(S.RUNNING), []
    assert s.leave({S.RUNNING}, S.LOST, first=lambda: seen.append(s.state))
    assert seen == [S.RUNNING] and s.state is S.LOST
    assert not s.leave({S.RUNNING}, S.LOST, first=lambda: seen.append("again"))
    assert seen == [S.RUNNING]


def test_a_lost_link_asks_the_running_word_to_stop_before_it_says_lost():
    # The reader thread loses the link while a word waits for a tick: the
    # word, finding the link lost, must find its stop asked for already, or
    # it runs on without a board (100 HALTs: Control loop stalled, seen in CI).
    m = rcl.open(port="rclsim://?rate=4")
    board, asked = m.board, []
    request_stop = m.request_stop

    def watched(error):
        asked.append((board.lost, error.message, error.why))
        request_stop(error)
    m.request_stop = watched
    try:
        m.in_forth += 1                              # (a word runs)
        board.lose(Loss(Cause.FRAME_GONE, "board frame 9 was not sent again"))
        m.in_forth -= 1
        assert asked == [(False, "Link lost", "board frame 9 was not sent again")] and board.lost
        assert board.why == "board frame 9 was not sent again"
        assert m.break_pending and m.deadline == -1
        board.lose(Loss(Cause.SILENT, "later"))      # said once: no second stop
        assert len(asked) == 1 and board.why == "board frame 9 was not sent again"
    finally:
        board.close()


def readers():
    return {t for t in threading.enumerate() if t.name == "rcl-link-reader" and t.is_alive()}


def test_an_open_that_fails_leaves_no_port_or_thread_behind_and_a_second_try_says_the_same():
    # rcl.open on a line where no board answers: LinkError. What it opened
    # (the port, held exclusively, and its reader thread) is closed, so the
    # next try gets the same answer, not " port busy " (a busy run's retry
    # after a session lost while loading RCL met exactly that)
    master, slave = os.openpty()
    path, before = os.ttyname(slave), readers()
    try:
        for _ in range(2):
            with pytest.raises(LinkError) as e:
                rcl.open(port=path)
            assert str(e.value).startswith("No answer from a board on %s" % path)
        assert readers() <= before
    finally:
        os.close(master)
        os.close(slave)


def test_a_closed_connection_is_a_lost_link_of_cause_port():
    served = subprocess.Popen(
        [sys.executable, "-m", "rcl.hw.boardcli", "--tcp", "127.0.0.1:0"],
        stdout=subprocess.PIPE, stdin=subprocess.DEVNULL, text=True)
    try:
        where = served.stdout.readline().strip().rsplit(" ", 1)[1]
        m = rcl.open(port="socket://" + where)
    finally:
        served.terminate()                           # the board's end closes
        served.wait(10)
    board = m.board
    try:
        end = time.monotonic() + 30
        while not board.lost and time.monotonic() < end:
            time.sleep(0.01)
        assert board.session.state is S.LOST
        assert board.loss.cause is Cause.PORT and board.why.startswith("port: ")
        assert m.evaluate("RECONNECT").startswith(" Link lost: ")   # nothing listens there
        assert board.loss.cause is Cause.PORT
    finally:
        board.close()
    assert board.session.state is S.CLOSED


def test_the_request_in_flight_is_a_record_of_its_answer():
    m = rcl.open(port="rclsim://?rate=4")
    board = m.board
    try:
        board.post("IN8", port=0x8A)
        req = board.pending
        assert isinstance(req, Request) and req.name == "IN8" and req.reply is None
        assert req.seq == (board.seq - 1) or (req.seq == 255 and board.seq == 1)
        reply = board.settle()
        assert board.pending is None and req.reply is reply and reply["ack"] == req.seq
        assert reply["value"] == m.sim.board.in8(0x8A)
    finally:
        board.close()


# ------------------------------------------------------------ usb:// URLs
def test_usb_sim_as_a_url_drives_the_simulated_usb_board():
    m = rcl.open(port="usb://sim")
    try:
        assert m.board.port.portstr == "usb:1209:0001"
        m.evaluate("RERB 2 INCHES FORWARD")
        plain = rcl.open()
        plain.evaluate("RERB 2 INCHES FORWARD")
        assert all(abs(a - b) <= 2 for a, b in zip(m.sim.wheel_counts, plain.sim.wheel_counts))
    finally:
        m.board.close()


@pytest.mark.parametrize("url", ["usb://robot", "usb://", "usb://12345:1", "usb://1209:0001:2",
                                 "usb://1_2:34"])
def test_a_bad_usb_url_is_refused_with_the_format(url):
    with pytest.raises(LinkError) as e:
        rcl.open(port=url)
    assert str(e.value).startswith(url + ": a USB board is usb://VID:PID")
    assert "usb://sim" in str(e.value)


def test_a_usb_device_that_is_not_there_is_said_plainly():
    with pytest.raises(LinkError) as e:
        rcl.open(port="usb://1209:fffe")
    assert "1209:fffe" in str(e.value)


def rcl_cli(*args):
    return subprocess.run([sys.executable, "-m", "rcl", *args], input="",
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("spelling", [("--port", "usb://sim"), ("--usb", "sim")])
def test_rcl_drives_the_usb_board_by_url_and_by_the_usb_synonym(spelling):
    run = rcl_cli(*spelling, "-e", "HEX 8A PC@ . BYE")
    assert run.returncode == 0, run.stderr
    assert run.stdout.split()[-1] == rcl.open().evaluate("HEX 8A PC@ .").split()[0]


@pytest.mark.parametrize("spelling", [("--port", "usb://robot"), ("--usb", "robot")])
def test_rcl_refuses_a_bad_usb_url_plainly(spelling):
    run = rcl_cli(*spelling, "-e", "BYE")
    assert run.returncode == 2
    assert "rcl: usb://robot: a USB board is usb://VID:PID" in run.stderr
    assert "Traceback" not in run.stderr


# A simulated board whose line goes silent, for good, after it has acted
# on 40 requests: RCL is loading (it asks 84 in all), whatever the clock.
CUT_WHILE_LOADING = """
from rcl.hw.server import BoardServer
act = BoardServer.act
def cut_while_loading(server, f):
    if server.stats["acted"] >= 40:
        server.cut_link()
    return act(server, f)
BoardServer.act = cut_while_loading
"""


def test_a_link_lost_while_rcl_loads_says_why_in_the_error_rcl_open_raises():
    namespace = {}
    exec(CUT_WHILE_LOADING, namespace)
    try:
        with pytest.raises(rcl.ForthError) as e:
            rcl.open(port="rclsim://")
    finally:
        from rcl.hw.server import BoardServer
        BoardServer.act = namespace["act"]
    assert e.value.code == -292 and e.value.file is not None
    assert e.value.message == "Link lost (no frame from the board for 250 ms)"


def test_rcl_says_the_link_was_lost_while_loading_rcl_and_why():
    run = subprocess.run(
        [sys.executable, "-c", CUT_WHILE_LOADING + "import rcl.cli, sys\n"
         "sys.exit(rcl.cli.main(['--port', 'rclsim://', '-e', 'BYE']))"],
        input="", capture_output=True, text=True, timeout=120)
    assert run.returncode == 2 and "Traceback" not in run.stderr
    assert run.stderr.startswith("rcl: loading RCL onto the board: ")
    assert run.stderr.endswith(": Link lost (no frame from the board for 250 ms)\n")


# --------------------------------------- a busy host is not a silent board
@pytest.fixture
def wall_judged():
    """A simulated board in this process, whose silence the host judges as
    over a real line (TCP, a pty, USB, a serial port): on the wall clock
    less its own stalls, not in the board's time. The board, in this
    process, cannot be kept from running apart from the host, so what is
    tested is the host's judgement alone, whatever the machine's load."""
    from rcl.hw.liveness import Liveness
    m = rcl.open(port="rclsim://?rate=4")
    m.board.live = Liveness()                   # (the reader takes it at its next read)
    yield m
    m.board.close()


LEGS = "RERB 6 INCHES FORWARD 90 DEGREES LEFT 6 INCHES FORWARD"


def lockstep_counts(program):
    """A lockstep board's counts depend on the frames only (test_link.py)."""
    m = rcl.open(port="rclsim://?rate=8")
    try:
        return m.evaluate(program + " 300 MS ?CNT1 D. ?CNT2 D.")
    finally:
        m.board.close()


def test_a_reader_thread_stalled_after_its_read_does_not_take_the_stall_for_silence(wall_judged):
    # The reader reads what waits, then (a busy machine, the GIL, a write
    # lock) is kept from running for 400 ms before it would judge: the
    # board's frames of that time wait on the line unread. Silence is
    # judged at the read, not after the stall.
    m = wall_judged
    board = m.board
    dispatch, stalled = board.dispatch, []

    def stalling(f, live):
        dispatch(f, live)
        if f.name == "TICK" and board.ticks > 20 and not stalled:
            stalled.append(f["tick"])
            time.sleep(0.4)
    board.dispatch = stalling
    try:
        assert m.evaluate(LEGS + " 300 MS ?CNT1 D. ?CNT2 D.") == lockstep_counts(LEGS)
        assert stalled and not board.lost and board.session.state is S.RUNNING
    finally:
        board.close()


def test_a_reader_kept_from_reading_for_over_a_second_does_not_give_a_request_up(wall_judged):
    # The whole process stalled 1.2 s just as a request went out (the
    # reader inside its read, the Forth thread waiting for the answer):
    # when it runs again the answer is on the line. A request's second is
    # counted as of the reader's last read, so it is read, not given up.
    m = wall_judged
    board = m.board
    read, post = board.port.read, board.post
    armed, stalling = [], threading.Event()

    def slow(size=1):
        if armed:
            armed.pop()
            stalling.set()
            time.sleep(1.2)
        return read(size)

    def posting(name, /, **values):
        if name == "IN8" and not stalling.is_set():
            armed.append(True)
            assert stalling.wait(10)          # the reader is held before the request goes
        return post(name, **values)
    board.port.read, board.post = slow, posting
    try:
        expected = rcl.open().evaluate("HEX 8A PC@ . DECIMAL")
        assert m.evaluate("HEX 8A PC@ . DECIMAL") == expected
        assert stalling.is_set() and not board.lost and board.session.state is S.RUNNING
    finally:
        board.close()


def test_a_link_host_compiles_rcl_ahead_so_no_tick_of_a_move_waits_for_the_compiler():
    # A word compiled at its first call costs a tick's answer tens of ms
    # under load: past the board's patience, the wheels drive on the old
    # command (the Uno image overshot by 1-2 counts from a fresh rcl).
    m = rcl.open(port="rclsim://?rate=4")
    compiled, compile_ = [], m.compile

    def watched(addr):
        compiled.append(m.dictionary.name_of((addr - 2) & 0xFFFF))
        return compile_(addr)
    m.compile = watched
    try:
        assert m.evaluate("RERB 2 MPH 3 INCHES FORWARD") == "" and compiled == []
        m.invalidate()                               # (compiled code forgotten: the move compiles)
        assert m.evaluate("RERB 2 MPH 3 INCHES FORWARD") == ""
        assert {"(MOVE)", "(CONTROL)", "ADVANCE", "STOPPED"} <= set(compiled)
    finally:
        m.board.close()


def test_a_tick_handler_of_many_writes_sends_them_all_in_order():
    # 25 writes in one tick take two TICK_DONE frames (19 a frame, as a
    # 64-byte payload holds); 20 in one frame were refused by the encoder,
    # and the host then waited for ever
    m = rcl.open(port="rclsim://?rate=4")
    server = m.board.port.server
    try:
        m.evaluate(": MANY  25 0 DO  I 137 PC!  LOOP ;  ' MANY IS CONTROL  50 MS")
        aux = [v for _, port, v in list(server.board.port_log) if port == 137]
        whole = len(aux) // 25
        assert whole >= 4 and aux[:25 * whole] == list(range(25)) * whole
    finally:
        m.board.close()


def test_a_frame_that_cannot_be_made_uses_no_sequence_number():
    # (a script of 17 operations is 68 bytes, over a frame's 64): refused
    # here, and the next request is still the one the board expects, not
    # one it ignores for ever
    from rcl.hw.protocol import ProtocolError
    m = rcl.open(port="rclsim://?rate=4")
    try:
        seq = m.board.seq
        with pytest.raises(ProtocolError):
            m.board.request("RUN", ops=[(1, 0x8A, 0)] * 17)
        assert m.board.seq == seq and m.board.pending is None
        assert m.evaluate("HEX 8A PC@ . DECIMAL") == rcl.open().evaluate("HEX 8A PC@ . DECIMAL")
        assert not m.board.lost
    finally:
        m.board.close()
