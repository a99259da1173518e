"""Pictures of a trace: the figure's own data and the SVG's paths say what
the picture shows (the path at equal scale, each move's breakpoints, the
following error and where it tripped); the Forth words and the command
line make them; without matplotlib a clear message names the extra."""
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

import rcl
from rcl import plot
from rcl.sim.observe import Trace
from rcl.track import Track, load_csv

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SQUARE = os.path.join(rcl.SCREENS, "examples", "listing1.fs")
needs_matplotlib = pytest.mark.skipif(
    __import__("importlib.util").util.find_spec("matplotlib") is None,
    reason="matplotlib is not installed (pip install matplotlib)")
SVG = "{http://www.w3.org/2000/svg}"


@pytest.fixture(scope="module")
def square():
    m = rcl.open()
    rec = Trace(m.sim.board, keep=True)
    m.include(SQUARE)
    m.sim.run(0.5)
    return Track.of(rec)


@pytest.fixture(scope="module")
def stalled():
    m = rcl.open()
    rec = Trace(m.sim.board, keep=True)
    m.sim.stall("left")
    with pytest.raises(rcl.ForthError, match="Following error"):
        m.evaluate("RERB 2 MPH 3.4 FEET FORWARD")
    return Track.of(rec)


def artist(fig, gid):
    found = [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == gid]
    assert found, "no artist %r in the figure" % gid
    return found[0]


def svg_points(path, gid):
    """The vertices of the first <path> in the group with that id (SVG user
    units, y down)."""
    root = ET.parse(path).getroot()
    group = next(g for g in root.iter(SVG + "g") if g.get("id") == gid)
    d = next(group.iter(SVG + "path")).get("d").replace("M", " ").replace("L", " ").split()
    nums = [float(v) for v in d if v not in ("z", "Z")]
    return list(zip(nums[0::2], nums[1::2]))


# ------------------------------------------------------- the figure's data
@needs_matplotlib
def test_the_path_drawn_ends_where_the_robot_ended_in_feet(square):
    line = artist(plot.figure(square), "path-1")
    x, y = line.get_data()
    assert len(x) == square.n
    assert (x[-1], y[-1]) == pytest.approx((square.x[-1] / 12, square.y[-1] / 12))
    assert max(x) == pytest.approx(3.5, abs=0.05)          # 3.5 FEET a side


@needs_matplotlib
def test_start_and_end_are_marked_at_the_first_and_last_pose(square):
    fig = plot.figure(square)
    assert artist(fig, "start").get_data() == ([0.0], [0.0])
    ex, ey = artist(fig, "end").get_data()
    assert math.hypot(ex[0], ey[0]) * 12 < 0.5             # the square closes


@needs_matplotlib
def test_every_move_of_the_square_has_its_breakpoints_marked_on_its_command(square):
    fig = plot.figure(square)
    acc_t, acc_v = artist(fig, "acc-end").get_data()
    dec_t, dec_v = artist(fig, "dec-start").get_data()
    assert len(acc_t) == len(dec_t) == 2 * 8              # two wheels, eight moves
    # 25.5 IPS is the forward moves' top speed (count 173: 722.5 counts/s)
    sides = [v for v in acc_v if v > 22]                   # the turns peak at 20.6
    assert len(sides) == 8 and all(v == pytest.approx(25.43, abs=0.05) for v in sides)
    assert all(d >= a for a, d in zip(acc_t, dec_t))


@needs_matplotlib
def test_the_following_error_line_is_commanded_minus_encoder_under_the_limit(square):
    fig = plot.figure(square)
    _, err = artist(fig, "ferr-left").get_data()
    errs = [e for e in err if e == e]                       # NaN breaks between moves
    assert 5 < max(errs) < 30
    assert artist(fig, "ferr-limit").get_ydata()[0] == 100


@needs_matplotlib
def test_a_stalled_wheel_shows_its_error_passing_the_limit_where_it_tripped(stalled):
    fig = plot.figure(stalled)
    t, e = artist(fig, "tripped").get_data()
    assert len(t) == 1 and 100 < e[0] < 115                 # stopped at the first tick over


@needs_matplotlib
def test_a_move_rcl_stopped_is_marked_as_the_stalled_one_is_even_under_the_limit():
    m = rcl.open()
    rec = Trace(m.sim.board, keep=True)
    with pytest.raises(rcl.ForthError, match="Following error"):
        m.evaluate("1 G 4 MPH 5 FEET FORWARD")              # 1 G: twice the motors' torque
    track = Track.of(rec)
    fig = plot.figure(track)
    times, _ = track.motion_time()
    t, e = artist(fig, "tripped").get_data()
    assert list(t) == [times[track.moves[0].last]] and 80 < e[0] <= 100
    x, _ = artist(fig, "tripped-path").get_data()
    assert list(x) == [track.x[track.moves[0].last] / 12]


@needs_matplotlib
def test_the_stalled_wheel_is_marked_on_the_path_too(stalled):
    x, _ = artist(plot.figure(stalled), "tripped-path").get_data()
    assert len(x) == 1


@pytest.fixture(scope="module")
def two_trips():
    """Two trips as MAILBOT's day has eight: moves more than trip_gap apart."""
    m = rcl.open()
    rec = Trace(m.sim.board, keep=True)
    m.evaluate("RERB 2 MPH 1 FEET FORWARD 90 DEGREES LEFT  3 SECONDS  2 FEET FORWARD")
    m.sim.run(0.5)
    return Track.of(rec, trip_gap=2.0)


@needs_matplotlib
def test_a_day_shows_its_first_trip_in_detail_and_each_move_in_a_summary(two_trips):
    track = two_trips
    (first, last), (second, _) = track.trips()
    fig = plot.figure(track)
    assert len(fig.axes) == 5                       # path, trip 1's three panels, the day
    t, _ = artist(fig, "speed-left").get_data()
    assert len(t) == second - max(0, first - 1)     # trip 1's rows only
    assert fig.axes[1].get_title().startswith("trip 1 of 2: ")
    # the day: one point a move, at its start in hours, its largest error
    one_t, one_e = artist(fig, "day-1").get_data()
    two_t, two_e = artist(fig, "day-2").get_data()
    assert (len(one_t), len(two_t)) == (2, 1)
    assert two_t[0] == pytest.approx(track.t[track.moves[2].first] / 3600)
    peak = max(abs(e) for w in ("left", "right") for i, e in track.following_error(w)
               if track.moves[2].first <= i <= track.moves[2].last)
    assert two_e[0] == pytest.approx(peak) and 5 < peak < 30


@needs_matplotlib
def test_one_trip_keeps_the_three_time_panels(square):
    assert len(plot.figure(square).axes) == 4


# ----------------------------------------------------------------- files
@needs_matplotlib
def test_the_svg_of_the_square_is_as_wide_as_it_is_tall(square, tmp_path):
    path = str(tmp_path / "square.svg")
    plot.draw(square, path)
    pts = svg_points(path, "path-1")
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    width, height = max(xs) - min(xs), max(ys) - min(ys)
    assert width == pytest.approx(height, rel=0.03)         # equal scale
    assert ys[0] > ys[len(ys) // 4]                         # y up: the first side...


@needs_matplotlib
def test_a_png_is_written_whole_and_small(square, tmp_path):
    path = tmp_path / "square.png"
    plot.draw(square, str(path))
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) < 150_000
    assert [p.name for p in tmp_path.iterdir()] == ["square.png"]   # no temporary left


def test_an_unknown_picture_type_is_refused_by_name(square):
    with pytest.raises(plot.PlotError, match="png, .svg or .pdf"):
        plot.draw(square, "square.gif")


def test_without_matplotlib_the_message_gives_a_command_that_installs_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)    # import fails
    command = r"pip install matplotlib .*pip install -e '\.\[plot\]'"
    with pytest.raises(plot.PlotError, match=command):
        plot.require_matplotlib()


# ------------------------------------------------------------ Forth words
@needs_matplotlib
def test_plot_at_the_prompt_draws_what_was_traced_so_far(tmp_path):
    m = rcl.open()
    m.evaluate("TRACE-ON RERB 1 FEET FORWARD TRACE-OFF 1 FEET FORWARD")
    out = tmp_path / "one.svg"
    m.evaluate("PLOT %s" % out)
    xs = [p[0] for p in svg_points(str(out), "path-1")]
    assert max(xs) > min(xs)
    fig = plot.figure(Track.of(m.tracer))
    x, _ = artist(fig, "path-1").get_data()
    assert len(x) == len(m.tracer.rows)                      # only the traced move
    assert max(x) == pytest.approx(1.0, abs=0.02)


def test_save_trace_writes_the_rows_as_csv(tmp_path):
    m = rcl.open()
    m.evaluate("TRACE-ON RERB 1 FEET FORWARD")
    out = tmp_path / "one.csv"
    m.evaluate("SAVE-TRACE %s" % out)
    track = load_csv(str(out))
    assert len(track.moves) == 1 and track.n == len(m.tracer.rows)


def test_plot_without_a_trace_says_how_to_start_one():
    m = rcl.open()
    with pytest.raises(rcl.ForthError, match="TRACE-ON first"):
        m.evaluate("PLOT x.png")


def test_a_bare_machine_has_no_trace_to_start():
    with pytest.raises(rcl.ForthError, match="keeps no trace"):
        rcl.Forth().evaluate("TRACE-ON")


# ---------------------------------------------------------- command line
def rcl_cli(*args, cwd):
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, "-m", "rcl", *args], input="",
                          capture_output=True, text=True, timeout=120, cwd=cwd, env=env)
    assert "Traceback" not in done.stdout + done.stderr
    return done


@needs_matplotlib
def test_rcl_trace_and_plot_write_the_square_at_the_end(tmp_path):
    done = rcl_cli(SQUARE, "--trace", "sq.csv", "--plot", "sq.svg", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    track = load_csv(str(tmp_path / "sq.csv"))
    assert len(track.moves) == 8
    assert math.hypot(track.x[-1], track.y[-1]) < 0.5
    pts = svg_points(str(tmp_path / "sq.svg"), "path-1")
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    assert max(xs) - min(xs) == pytest.approx(max(ys) - min(ys), rel=0.03)


def test_rcl_plot_refuses_an_unknown_type_before_running(tmp_path):
    done = rcl_cli("--plot", "sq.gif", "-e", "1 .", cwd=tmp_path)
    assert done.returncode == 2 and done.stdout == ""
    assert "a plot is a .png, .svg or .pdf file" in done.stderr


def test_rcl_trace_needs_a_board(tmp_path):
    done = rcl_cli("--bare", "--trace", "t.csv", cwd=tmp_path)
    assert done.returncode == 2 and "not --bare" in done.stderr
    assert list(tmp_path.iterdir()) == []


def test_rcl_plot_without_matplotlib_gives_the_command_that_installs_it_and_runs_nothing(tmp_path):
    fake = tmp_path / "hide" / "matplotlib"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("raise ImportError('hidden for the test')\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(fake.parent), ROOT]))
    done = subprocess.run([sys.executable, "-m", "rcl", "--plot", "sq.png", "-e", "1 ."],
                          input="", capture_output=True, text=True, timeout=60,
                          cwd=tmp_path, env=env)
    assert done.returncode == 2 and done.stdout == ""
    # "rcl" on the package index is another project: the command is this one's
    assert "pip install matplotlib" in done.stderr and "rcl[plot]" not in done.stderr
    assert "pip install -e '.[plot]'" in done.stderr and "Traceback" not in done.stderr


def test_plot_draws_the_limit_rcl_has_now():
    from rcl.words.tracing import ferr_limit
    m = rcl.open()
    m.evaluate("50 FERR-LIMIT !")
    assert ferr_limit(m) == 50
    assert ferr_limit(rcl.Forth()) == 100                  # no RCL: its power-on value


@needs_matplotlib
def test_the_limit_line_follows_the_limit_given_and_the_square_stays_under_50(square):
    fig = plot.figure(square, ferr_limit=50)
    assert artist(fig, "ferr-limit").get_ydata()[0] == 50
    assert not [a for ax in fig.axes for a in ax.get_children() if a.get_gid() == "tripped"]


# ------------------------------------------------- which word moved it
def labels(fig):
    return {t.get_gid(): t.get_text() for ax in fig.axes for t in ax.texts
            if (t.get_gid() or "").startswith("move-")}


@pytest.fixture(scope="module")
def traced_square():
    m = rcl.open()
    m.evaluate("TRACE-ON")
    m.include(SQUARE)
    m.sim.run(0.5)
    return Track.of(m.tracer, marks=m.tracer.marks)


@needs_matplotlib
def test_each_move_of_the_square_is_labelled_with_its_number_and_word(traced_square):
    found = labels(plot.figure(traced_square))
    assert found == {"move-1-%d" % n: "%d %s" % (n, "FORWARD" if n % 2 else "LEFT")
                     for n in range(1, 9)}


@needs_matplotlib
def test_a_straight_move_is_labelled_at_its_middle(traced_square):
    fig = plot.figure(traced_square)
    label = next(t for t in fig.axes[0].texts if t.get_gid() == "move-1-1")
    x, y = label.xy
    assert x == pytest.approx(3.5 / 2, abs=0.1) and y == pytest.approx(0, abs=0.05)


@pytest.fixture(scope="module")
def two_traced_trips():
    m = rcl.open()
    m.evaluate(": HOP  1 FEET FORWARD 90 DEGREES LEFT ;  TRACE-ON  RERB 2 MPH HOP "
               "3 SECONDS  2 FEET FORWARD HOP")
    m.sim.run(0.5)
    return Track.of(m.tracer, trip_gap=2.0, marks=m.tracer.marks)


@needs_matplotlib
def test_a_days_path_numbers_each_move_in_its_trip(two_traced_trips):
    found = labels(plot.figure(two_traced_trips))
    assert found == {"move-1-1": "1", "move-1-2": "2", "move-2-1": "1", "move-2-2": "2",
                     "move-2-3": "3"}
    assert [mv.word for mv in two_traced_trips.moves] == [
        "HOP > FORWARD", "HOP > LEFT", "FORWARD", "HOP > FORWARD", "HOP > LEFT"]


@needs_matplotlib
def test_the_trip_in_detail_names_each_moves_words_on_its_time_axis(two_traced_trips):
    fig = plot.figure(two_traced_trips)
    texts = [t.get_text() for t in fig.axes[1].texts]
    assert texts == ["1 HOP > FORWARD", "2 HOP > LEFT"]
