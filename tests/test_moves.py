"""Which word moved the robot: the move log (rcl/words/moves.py), .MOVES,
the trace's `word` column and the plot's labels, in RCL's own numbers
(docs/guide.md section 13: Listing 1 at 0.1 G and 25.5 IPS, a side
of 3.5 FEET is 1193 counts a wheel, ramps to 239 and slows from 954; a
90 DEGREES turn is 313 counts, 156 and 157, peak 7029 crpm).
"""
import csv
import os
import pathlib
import subprocess
import sys

import pytest

import rcl
from rcl.track import Track, load_csv
from rcl.words import moves as movelog

EXAMPLES = pathlib.Path(rcl.SCREENS) / "examples"
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="module")
def square():
    m = rcl.open()
    m.include(EXAMPLES / "listing1.fs")
    return m


@pytest.fixture(scope="module")
def trip():
    m = rcl.open()
    m.include(EXAMPLES / "listing4.fs")
    m.include(EXAMPLES / "listing5.fs")
    m.evaluate("8 AM TICKS! TRACE-ON TRIP TRACE-OFF")
    return m


def test_listing_1_logs_eight_moves_forward_and_left(square):
    assert [mv.label for mv in square.moves.moves] == ["FORWARD", "LEFT"] * 4


def test_a_side_of_listing_1_is_rcls_1193_counts_at_25_5_ips(square):
    side = square.moves.moves[0]
    assert side.distance == (35000, "FEET") and side.direction == "forward"
    assert side.counts == 1193
    assert side.speed == (255000, "IPS") and side.top_crpm == 8693
    assert (side.acc_at, side.dec_at) == (239, 954)
    assert side.how == "done"


def test_a_turn_of_listing_1_is_313_counts_a_triangle_peaking_at_7029_crpm(square):
    turn = square.moves.moves[1]
    assert turn.distance == (900000, "DEGREES") and turn.direction == "left"
    assert turn.counts == 313 and turn.top_crpm == 7029
    assert (turn.acc_at, turn.dec_at) == (156, 157)


def test_each_move_starts_where_the_board_saw_the_robot(square):
    first, second = square.moves.moves[0], square.moves.moves[1]
    assert first.start[3] == (0.0, 0.0, 0.0)
    # 1193 counts are 42.0 in; the relays open 2 counts (RUN-ON) short of
    # it and the braked wheels roll on into the next move's start.
    assert first.end[3][0] == pytest.approx(42.0 - 2 / 28.409, abs=0.1)
    assert second.start[3][0] == pytest.approx(42.0, abs=0.2)
    assert second.start[3][0] >= first.end[3][0]


def test_dot_moves_lists_them_with_rcls_numbers(square):
    text = square.evaluate(".MOVES")
    assert "   1 FORWARD\n       3.5 FEET forward, 1193 counts a wheel, at 25.5 IPS " \
           "(8693 crpm), breakpoints 239 954\n" in text
    assert "   2 LEFT\n       90 DEGREES left, 313 counts a wheel, at 25.5 IPS " \
           "(7029 crpm), breakpoints 156 157\n" in text
    assert text.count(", done\n") == 8
    assert "   8 LEFT" in text and "   9 " not in text


def test_dot_moves_without_moves_says_so():
    assert rcl.open().evaluate(".MOVES") == "\nNo moves yet\n"


def test_the_chain_names_the_words_that_commanded_a_move_and_where(trip):
    turns = [mv for mv in trip.moves.moves if mv.label == "TRIP > TURN-LEFT > LEFT"]
    assert len(turns) == 4
    first = trip.moves.moves[0]
    assert first.label == "TRIP > BACKWARD" and first.distance == (30000, "FEET")
    # the line of TRIP that led to each move, in listing5.fs
    assert (pathlib.Path(first.where[0]).name, first.where[1]) == ("listing5.fs", 20)
    assert [mv.where[1] for mv in turns] == [21, 22, 29, 30]
    ahead = trip.moves.moves[2]
    assert ahead.label == "TRIP > AHEAD > FORWARD" and ahead.distance == (25000, "FEET")


def test_trip_logs_its_26_moves_in_listing_5s_order(trip):
    labels = [mv.label.split(" > ", 1)[1] for mv in trip.moves.moves]
    assert len(labels) == 26
    assert labels[:5] == ["BACKWARD", "TURN-AROUND > LEFT", "AHEAD > FORWARD",
                          "TURN-RIGHT > RIGHT", "AHEAD > FORWARD"]


def test_the_log_keeps_the_last_moves_only():
    assert movelog.LOG_SIZE == 1000
    m = rcl.open()
    m.moves = movelog.MoveLog(size=3)
    m.evaluate("1 INCHES FORWARD FORWARD FORWARD FORWARD FORWARD")
    assert m.moves.count == 5 and [mv.number for mv in m.moves.moves] == [3, 4, 5]


def test_a_move_stopped_by_a_following_error_says_so():
    m = rcl.open()
    m.sim.stall("left")
    with pytest.raises(rcl.ForthError):
        m.evaluate("3 FEET FORWARD")
    assert m.moves.moves[-1].how == "following error, left"


def test_a_move_ctrl_c_stopped_is_logged_as_stopped():
    m = rcl.open()
    board, start = m.sim.board, m.sim.board.ticks

    def break_in(b):                    # Ctrl-C 50 ticks into the move
        if b.ticks == start + 50:
            m.request_break()
    board.observers.append(break_in)
    with pytest.raises(rcl.ForthError, match="Interrupted"):
        m.evaluate("3 FEET FORWARD")
    mv = m.moves.moves[-1]
    assert mv.how == "stopped" and mv.end[0] - mv.start[0] == pytest.approx(0.5, abs=0.02)


def test_on_a_board_over_a_link_the_log_has_rcls_numbers_and_no_pose():
    m = rcl.open(port="rclsim://?rate=8")
    try:
        m.evaluate("RERB 2 MPH 6 INCHES FORWARD")
        mv = m.moves.moves[-1]
        # docs/guide.md section 13: 6 INCHES is 170 counts, a triangle peaking at 5189 crpm
        assert (mv.label, mv.counts, mv.top_crpm, mv.how) == ("FORWARD", 170, 5189, "done")
        assert mv.start[3] is None and mv.start[1] is None
        text = m.evaluate(".MOVES")
        assert "6 INCHES forward, 170 counts a wheel, at 2 MPH" in text and " t " in text
    finally:
        m.board.close()


def test_a_negative_distance_is_logged_the_way_the_robot_went():
    m = rcl.open()
    m.evaluate("-6 INCHES FORWARD")
    mv = m.moves.moves[-1]
    assert (mv.label, mv.direction, mv.distance) == ("FORWARD", "backward", (60000, "INCHES"))


def test_arm_moves_are_logged_with_rcls_ticks():
    m = rcl.open()
    m.include(EXAMPLES / "arm.fs")                  # ARM 3.1 INCHES DOWN 2 INCHES UP
    down, up = m.moves.moves
    assert (down.label, down.direction, down.distance, down.ticks) == \
        ("DOWN", "down", (31000, "INCHES"), 310)
    assert (up.label, up.direction, up.distance, up.ticks) == ("UP", "up", (20000, "INCHES"), 200)
    assert down.how == up.how == "done"
    assert "3.1 INCHES down, 310 ticks at most" in m.evaluate(".MOVES")


# ------------------------------------------------------------- the trace
def test_the_trace_names_the_words_of_each_move(trip):
    track = Track.of(trip.tracer, marks=trip.tracer.marks)
    assert len(track.moves) == 26
    assert [mv.word for mv in track.moves] == [mv.label for mv in trip.moves.moves]


def test_save_trace_writes_the_word_column_and_track_reads_it_back(trip, tmp_path):
    path = tmp_path / "trip.csv"
    trip.evaluate("SAVE-TRACE %s" % path)
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0][-1] == "word"
    track = load_csv(str(path))
    assert [mv.word for mv in track.moves][:3] == [
        "TRIP > BACKWARD", "TRIP > TURN-AROUND > LEFT", "TRIP > AHEAD > FORWARD"]
    between = [r[-1] for r in rows[1:] if not int(float(r[8])) & 0x30]
    assert set(between) == {""}


def test_rcl_trace_carries_the_word_column(tmp_path):
    path = tmp_path / "square.csv"
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, "-m", "rcl", "--trace", str(path),
                           str(EXAMPLES / "listing1.fs")], input="", text=True,
                          capture_output=True, timeout=300, env=env)
    assert done.returncode == 0 and "Traceback" not in done.stderr, done.stderr
    track = load_csv(str(path))
    assert [mv.word for mv in track.moves] == ["FORWARD", "LEFT"] * 4
