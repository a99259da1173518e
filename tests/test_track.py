"""What a trace says (rcl.track), in RCL's own numbers: moves, the
trapezoid's breakpoints, wheel speeds, the following error, trips. No
matplotlib needed."""
import io
import math

import pytest

import rcl
from rcl.sim.observe import Trace
from rcl.track import Track, TraceError, load_csv

EXAMPLES = rcl.SCREENS + "/examples/"


def traced(words, stall=None, then=0.5):
    m = rcl.open()
    rec = Trace(m.sim.board, keep=True)
    if stall:
        m.sim.stall(stall)
    try:
        m.evaluate(words)
    except rcl.ForthError:
        pass
    m.sim.run(then)
    return Track.of(rec), m


@pytest.fixture(scope="module")
def trapezoid():
    """RERB 2 MPH 3.4 FEET FORWARD: peak 1000 counts/s (count 125), the
    acceleration ends at 455 counts, deceleration begins at 704, end 1159
    (docs/guide.md section 13)."""
    return traced("RERB 2 MPH 3.4 FEET FORWARD")[0]


@pytest.fixture(scope="module")
def square():
    track, m = traced("INCLUDE %slisting1.fs" % EXAMPLES)
    return track, m


def along(track, wheel, row, move):
    """Commanded counts from the move's start at a row."""
    q = track.commanded(wheel)
    return q[row] - q[move.first]


def test_one_command_makes_one_move(trapezoid):
    assert len(trapezoid.moves) == 1


def test_the_acceleration_ends_at_455_commanded_counts(trapezoid):
    move = trapezoid.moves[0]
    for wheel in ("left", "right"):
        acc, _ = move.breakpoints[wheel]
        # the last raise of the speed comes within a tick (10 counts) of 455
        assert along(trapezoid, wheel, acc, move) == pytest.approx(455, abs=10)


def test_the_deceleration_begins_at_704_commanded_counts(trapezoid):
    move = trapezoid.moves[0]
    for wheel in ("left", "right"):
        _, dec = move.breakpoints[wheel]
        assert along(trapezoid, wheel, dec, move) == pytest.approx(704, abs=10)


def test_the_commanded_speed_between_the_breakpoints_is_1000_counts_a_second(trapezoid):
    acc, dec = trapezoid.moves[0].breakpoints["left"]
    ref = trapezoid.reference("left")
    assert {round(ref[i]) for i in range(acc, dec + 1)} == {1000}


def test_the_wheel_speed_from_counts_per_tick_peaks_at_1000_counts_a_second(trapezoid):
    assert max(trapezoid.speed("left")) == pytest.approx(1000, rel=0.02)


def test_the_move_ends_at_1159_counts(trapezoid):
    assert trapezoid.col["left"][trapezoid.moves[0].last] == pytest.approx(1159, abs=3)


def test_a_clean_move_lags_its_command_by_about_20_counts(trapezoid):
    err = [e for _, e in trapezoid.following_error("left")]
    assert 10 < max(err) < 30                     # the PLL's lag, well inside 100


def test_a_blocked_wheel_lags_past_the_limit_where_rcl_stopped():
    track, m = traced("RERB 2 MPH 3.4 FEET FORWARD", stall="left")
    err = track.following_error("left")
    over = [i for i, e in err if e > 100]
    assert over and track.moves[0].last - over[0] <= 1     # stopped at that tick
    assert track.moves[0].breakpoints["left"] is None      # it never decelerated


def test_moves_that_end_as_planned_are_not_cut_short(square, trapezoid):
    track, _ = square
    assert track.cut_short() == [] and trapezoid.cut_short() == []


def test_a_move_stopped_by_a_following_error_rcl_saw_within_the_tick_is_cut_short():
    # 1 G is twice the motors' 0.5 G: the wheels fall behind, and RCL stops
    # the move at its tick's count, over 100, while the trace's rows show
    # at most 97 (their commanded position is a tick behind RCL's EXPACC).
    track, _ = traced("1 G 4 MPH 5 FEET FORWARD")
    move = track.moves[0]
    assert max(e for _, e in track.following_error("left")) <= 100
    assert track.cut_short() == [move.last]


def test_the_square_is_eight_moves_that_end_where_they_began(square):
    track, m = square
    assert len(track.moves) == 8
    assert math.hypot(track.x[-1], track.y[-1]) < 0.5       # inches


def test_the_path_dead_reckoned_from_counts_alone_matches_the_pose(square):
    track, _ = square
    rows = list(zip(*[track.col[f] for f in Trace.FIELDS]))
    blind = Track([r[:1] + (None, None, None) + r[4:] for r in rows], Trace.FIELDS)
    assert not blind.pose_known
    worst = max(math.hypot(a - b, c - d) for a, b, c, d in
                zip(blind.x, track.x, blind.y, track.y))
    assert worst < 0.5                                      # inches over 14 ft


def test_moves_an_hour_apart_are_two_trips_and_the_wait_is_cut_short():
    track, _ = traced("RERB 2 MPH 3.4 FEET FORWARD 60 MINUTES  3.4 FEET BACKWARD")
    trips = track.trips()
    assert len(trips) == 2
    assert track.trip_of(trips[1][0]) == 1
    times, cuts = track.motion_time(cut=2.0)
    assert len(cuts) == 1 and times[-1] < 10                # an hour became 2 s


def test_a_long_wait_between_moves_is_a_stop():
    track, _ = traced("RERB 2 MPH 1 FEET FORWARD 30 SECONDS  FORWARD")
    (row, seconds), = track.stops()
    # Listing 3's MS is a calibrated loop: the 10 ms handler's share of
    # each tick stretches it (32.4 s), so compare with a wait on its own.
    m = rcl.open()
    t0 = m.sim.seconds
    m.evaluate("30 SECONDS")
    assert seconds == pytest.approx(m.sim.seconds - t0, abs=0.1)


def test_beeps_are_found_where_the_beeper_starts():
    track, m = traced("BEEP BEEP")
    assert len(track.beeps()) == 2


def test_a_csv_trace_reads_back_as_the_same_track(tmp_path, square):
    track, _ = square
    path = tmp_path / "square.csv"
    m = rcl.open()
    out = io.StringIO()
    rec = Trace(m.sim.board, out, keep=True)
    m.evaluate("RERB 1 FEET FORWARD")
    path.write_text(out.getvalue())
    back = load_csv(str(path))
    assert back.n == len(rec.rows)
    assert back.col["left"] == [float(r[4]) for r in rec.rows]
    assert len(back.moves) == 1


def test_a_file_that_is_not_a_trace_is_refused_with_its_name(tmp_path):
    bad = tmp_path / "notes.csv"
    bad.write_text("hello,world\n1,2\n")
    with pytest.raises(TraceError, match="notes.csv: not a trace"):
        load_csv(str(bad))
