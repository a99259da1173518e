"""Pictures of a trace (rcl.track.Track), drawn with matplotlib (the
optional extra "plot" of pyproject.toml); the same for the simulated board and for what a
host saw of a real one.

    +-----------------+  speed: each wheel's counts per tick as in/s, the
    |                 |         commanded speed dashed, each move's
    |  path, top view |         acceleration end ^ and deceleration start v
    |  (equal scale)  |  position: along each move, commanded (dashed)
    |  start o end [] |         against the encoders
    |  arrows, stops, |  following error: commanded minus encoder, with
    |  beeps, trips   |         RCL's limit; a trip is marked x
    +-----------------+

Every artist a test may look for carries a gid (`path-1` for trip 1,
`start`, `end`, `beeps`, `stops`, `speed-left`, `acc-end`, `dec-start`,
`ferr-left`, `ferr-limit`, `tripped` and `tripped-path` for every move
stopped before its end), which SVG output keeps as the id
of the artist's group.
"""
import io
import math
import os

from rcl.errors import RclError
from rcl.safefile import write_atomically
from rcl.track import COUNTS_PER_INCH

FORMATS = ("png", "svg", "pdf")
# Not "pip install 'rcl[plot]'": on the package index "rcl" is another project.
EXTRA = ("matplotlib is not installed: plots need it, pip install matplotlib "
         "(or, in rcl's clone, pip install -e '.[plot]')")
WHEEL_COLOURS = {"left": "tab:blue", "right": "tab:orange"}
DPI = 80
FERR_LIMIT = 100              # counts: RCL's FERR-LIMIT at power-on


class PlotError(RclError):
    """A plot cannot be made (no matplotlib, an unknown file type, no data)."""


def require_matplotlib():
    """Raise PlotError naming the extra when matplotlib is missing."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise PlotError(EXTRA) from None


def check_name(path):
    """The file type from the name: png, svg or pdf, else PlotError."""
    ext = os.path.splitext(path)[1].lower().lstrip(".")
    if ext not in FORMATS:
        raise PlotError("a plot is a .png, .svg or .pdf file, not %r" % path)
    return ext


def draw(track, path, title=None, ferr_limit=FERR_LIMIT):
    """Draw the track to path (png, svg or pdf by its name); -> the Figure."""
    ext = check_name(path)
    fig = figure(track, title, ferr_limit)
    try:
        write_atomically(path, lambda f: save(fig, f, ext))
    except OSError as e:
        raise PlotError("%s: %s" % (path, e.strerror)) from None
    return fig


def save(fig, f, ext):
    """PNG in 256 colours (a plot has few: a third of the size), others as is."""
    if ext != "png":
        fig.savefig(f, format=ext)
        return
    from PIL import Image                 # matplotlib's own dependency
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    buf.seek(0)
    Image.open(buf).convert("RGB").quantize(256).save(f, format="png", optimize=True)


def figure(track, title=None, ferr_limit=FERR_LIMIT):
    """-> a matplotlib Figure of the track (no window, no pyplot)."""
    require_matplotlib()
    from matplotlib.figure import Figure
    if track.n < 2:
        raise PlotError("nothing to plot: the trace holds %d row(s)" % track.n)
    # A day of several trips is unreadable on one time axis: its first trip
    # in detail, and the whole day as one summary panel below.
    trips = track.trips()
    day = len(trips) > 1
    detail = track.part(*first_trip_rows(track)) if day else track
    fig = Figure(figsize=(13, 9.5 if day else 7.5), layout="constrained")
    grid = fig.add_gridspec(4 if day else 3, 2, width_ratios=(1.05, 1))
    path_axes = fig.add_subplot(grid[:, 0])
    speed_axes = fig.add_subplot(grid[0, 1])
    pos_axes = fig.add_subplot(grid[1, 1], sharex=speed_axes)
    ferr_axes = fig.add_subplot(grid[2, 1], sharex=speed_axes)
    times, cuts = detail.motion_time()
    if day:                                   # the trip's own clock, from 0
        times, cuts = [t - times[0] for t in times], [c - times[0] for c in cuts]
    draw_path(path_axes, track, ferr_limit)
    draw_speeds(speed_axes, detail, times)
    label_times(speed_axes, detail, times)
    draw_positions(pos_axes, detail, times)
    draw_following(ferr_axes, detail, times, ferr_limit)
    for ax in (speed_axes, pos_axes, ferr_axes):
        mark_cuts(ax, detail, times, cuts)
        if day:
            ax.set_title("trip 1 of %d: %s" % (len(trips), ax.get_title()))
    ferr_axes.set_xlabel(("time in trip 1, s" if day else "time, s")
                         + ("  (waits cut to 2 s at the dotted lines)" if cuts else ""))
    if day:
        draw_day(fig.add_subplot(grid[3, 1]), track, ferr_limit)
    if title:
        fig.suptitle(title)
    return fig


def first_trip_rows(track):
    """(first, last) rows of the first trip, with the row before its first
    move (where it starts from) and up to the row before the next trip."""
    trips = track.trips()
    return max(0, trips[0][0] - 1), trips[1][0] - 1


# ------------------------------------------------------------------ path
def trip_colour(k):
    return "C%d" % (k % 10)


def draw_path(ax, track, limit=FERR_LIMIT):
    """Top view in feet at equal scale: each trip its colour, heading
    arrows, start and end, stops and beeps."""
    x = [v / 12 for v in track.x]
    y = [v / 12 for v in track.y]
    trips = track.trips()
    every = max(2.0, max(max(x) - min(x), max(y) - min(y)) / 25)
    for k, (first, last) in enumerate(trips):
        # each trip drawn from the row after the last one's to its next start
        first = 0 if k == 0 else trips[k - 1][1]
        last = trips[k + 1][0] if k + 1 < len(trips) else track.n - 1
        line, = ax.plot(x[first:last + 1], y[first:last + 1], color=trip_colour(k), lw=1.4,
                        label="trip %d" % (k + 1) if len(trips) > 1 else "path")
        line.set_gid("path-%d" % (k + 1))
        draw_arrows(ax, track, x, y, first, last, trip_colour(k), every)
    if len(trips) > 1:
        mark_trip_ends(ax, track, x, y, trips)
    label_moves(ax, track, x, y, words=len(trips) == 1)
    start = ax.plot(x[0], y[0], "o", ms=10, mfc="none", mec="green", mew=2, label="start")[0]
    start.set_gid("start")
    end = ax.plot(x[-1], y[-1], "s", ms=9, mfc="none", mec="red", mew=2,
                  label="end, %s from the start" % feet(math.hypot(x[-1] - x[0], y[-1] - y[0])))[0]
    end.set_gid("end")
    ax.plot([x[0], x[-1]], [y[0], y[-1]], ":", color="red", lw=1)
    draw_stops(ax, track, x, y)
    beeps = track.beeps()
    if beeps:
        b = ax.plot([x[i] for i in beeps], [y[i] for i in beeps], "*", color="crimson", ms=9,
                    label="beeps (%d)" % len(beeps))[0]
        b.set_gid("beeps")
    early = tripped(track, limit)
    if early:
        ax.plot([x[i] for i, _ in early], [y[i] for i, _ in early], "X", color="red", ms=14,
                label="stopped before its end (%d)" % len(early))[0].set_gid("tripped-path")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x, feet")
    ax.set_ylabel("y, feet")
    ax.set_title("path, top view" + ("" if track.pose_known else " (dead-reckoned)"))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", fontsize=8, ncol=2 if len(trips) > 3 else 1)


def short_word(word):
    """The last two words of a move's chain (`TURN-LEFT > LEFT`): the
    command and what called it; the outer ones are the program itself."""
    return " > ".join(word.split(" > ")[-2:]) if word else ""


def label_moves(ax, track, x, y, words=True):
    """Each move numbered in its trip, from 1, with its words (`words`;
    a day's path has only the numbers: trip k's fifth move is the 5 in
    trip k's colour); a straight move at its middle, a turn where it
    turns. Each label's gid is `move-TRIP-N`."""
    for move, (k, n) in zip(track.moves, track.move_numbers()):
        a, b = max(move.first - 1, 0), move.last
        turn = math.hypot(x[b] - x[a], y[b] - y[a]) < 0.25
        i = a if turn else (a + b) // 2
        text = "%d %s" % (n, short_word(move.word)) if words else str(n)
        ax.annotate(text.strip(), (x[i], y[i]), xytext=(4, 4 if turn else -10),
                    textcoords="offset points", fontsize=7 if words else 6,
                    color=trip_colour(k - 1)).set_gid("move-%d-%d" % (k, n))


def label_times(ax, track, times):
    """On a time panel, each move's number in its trip and words, at its start."""
    low, high = ax.get_ylim()
    for move, (_, n) in zip(track.moves, track.move_numbers()):
        ax.text(times[move.first], low + 0.02 * (high - low),
                ("%d %s" % (n, short_word(move.word))).strip(), rotation=90,
                fontsize=6, va="bottom", ha="right", color="dimgrey")


def mark_trip_ends(ax, track, x, y, trips):
    """Each trip's end, numbered; the first one's distance from the start."""
    for k, (_, last) in enumerate(trips):
        ax.plot(x[last], y[last], "s", ms=6, color=trip_colour(k), mec="black")
        ax.annotate(str(k + 1), (x[last], y[last]), xytext=(4, -12),
                    textcoords="offset points", fontsize=8, color=trip_colour(k))
    last = trips[0][1]
    d = math.hypot(x[last] - x[0], y[last] - y[0])
    ax.annotate("trip 1 ends %s from the start" % feet(d), (x[last], y[last]),
                xytext=(x[last], min(y) - 0.25 * (max(y) - min(y) + 1)), ha="center",
                fontsize=9, arrowprops={"arrowstyle": "->", "color": "black"})


def feet(d):
    return "%.1f ft" % d if d >= 2 else "%.1f in" % (12 * d)


def room_for_legend(ax, share=0.45):
    """Raise the top of the axes so the legend sits above the data."""
    low, high = ax.get_ylim()
    ax.set_ylim(low, high + share * (high - low))


def finish_panel(ax, ylabel, title, columns=3):
    """A right-hand panel's labels, grid and legend above its data."""
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    room_for_legend(ax)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=7, ncol=columns)


def draw_arrows(ax, track, x, y, first, last, colour, every):
    """The heading, an arrow every `every` feet of travel."""
    px, py, hd, gone = [], [], [], every / 2
    for i in range(first + 1, last + 1):
        gone += math.hypot(x[i] - x[i - 1], y[i] - y[i - 1])
        if gone >= every:
            px.append(x[i])
            py.append(y[i])
            hd.append(math.radians(track.heading[i]))
            gone = 0.0
    if px:
        ax.quiver(px, py, [math.cos(h) for h in hd], [math.sin(h) for h in hd],
                  color=colour, angles="xy", scale=40, width=0.004, headwidth=4, alpha=0.8)


def draw_stops(ax, track, x, y):
    stops = track.stops()
    if not stops:
        return
    sizes = [40 + 40 * math.log2(1 + s / 30) for _, s in stops]
    sc = ax.scatter([x[i] for i, _ in stops], [y[i] for i, _ in stops], s=sizes,
                    facecolors="none", edgecolors="black", linewidths=1.2,
                    label="stops of 10 s or more (size: length)", zorder=3)
    sc.set_gid("stops")


# --------------------------------------------------------------- speeds
def in_s(values):
    return [v / COUNTS_PER_INCH for v in values]


def draw_speeds(ax, track, times):
    """Each wheel's speed and command, the breakpoints of every move."""
    for wheel, colour in WHEEL_COLOURS.items():
        line, = ax.plot(times, in_s(track.speed(wheel)), color=colour, lw=1,
                        label="%s wheel" % wheel, drawstyle="steps-pre")
        line.set_gid("speed-" + wheel)
        ax.plot(times, in_s(track.reference(wheel)), "--", color=colour, lw=0.8,
                label="%s commanded" % wheel, drawstyle="steps-post")
    acc, dec = breakpoint_points(track, times)
    ax.plot(*acc, "^", color="green", ms=6, label="acceleration ends")[0].set_gid("acc-end")
    ax.plot(*dec, "v", color="purple", ms=6, label="deceleration begins")[0].set_gid("dec-start")
    finish_panel(ax, "speed, in/s", "wheel speeds and each move's breakpoints")


def breakpoint_points(track, times):
    """([t], [in/s]) of every acceleration end and deceleration start, on
    the commanded speed of each wheel that moved."""
    acc, dec = ([], []), ([], [])
    for wheel in WHEEL_COLOURS:
        ref = in_s(track.reference(wheel))
        for move in track.moves:
            bp = move.breakpoints[wheel]
            if bp is None:
                continue
            for (ts, vs), i in ((acc, bp[0]), (dec, bp[1])):
                ts.append(times[i])
                vs.append(ref[i])
    return acc, dec


# ---------------------------------------------- position and following
def draw_positions(ax, track, times):
    """Along each move, counts from its start: commanded against encoder."""
    for wheel, colour in WHEEL_COLOURS.items():
        q, c, ref = track.commanded(wheel), track.col[wheel], track.reference(wheel)
        for k, move in enumerate(track.moves):
            rows = range(move.first, move.last + 1)
            sign = -1 if ref[move.first] < 0 else 1
            t = [times[i] for i in rows]
            ax.plot(t, [sign * (q[i] - c[move.first]) for i in rows], "--", color=colour, lw=0.8,
                    label="%s commanded" % wheel if k == 0 else None)
            ax.plot(t, [sign * (c[i] - c[move.first]) for i in rows], color=colour, lw=1,
                    label="%s encoder" % wheel if k == 0 else None)
    finish_panel(ax, "counts along the move", "commanded position against the encoders", columns=2)


def draw_following(ax, track, times, limit):
    """Commanded minus encoder, RCL's limit, and where it tripped."""
    for wheel, colour in WHEEL_COLOURS.items():
        err = track.following_error(wheel)
        t, e = gapped(err, times)
        line, = ax.plot(t, e, color=colour, lw=1, label="%s wheel" % wheel)
        line.set_gid("ferr-" + wheel)
    lim = ax.axhline(limit, color="red", ls="--", lw=1, label="FERR-LIMIT %d counts" % limit)
    lim.set_gid("ferr-limit")
    ax.axhline(-limit, color="red", ls="--", lw=1)
    trips = tripped(track, limit)
    if trips:
        errs = {w: dict(track.following_error(w)) for w in WHEEL_COLOURS}
        m = ax.plot([times[i] for i, _ in trips], [errs[w][i] for i, w in trips], "X",
                    color="red", ms=12, label="stopped before its end")[0]
        m.set_gid("tripped")
    finish_panel(ax, "following error, counts", "commanded minus encoder (following error)")


def gapped(err, times):
    """Lines for each move, broken between moves (None ends a line)."""
    t, e, last = [], [], None
    for i, v in err:
        if last is not None and i != last + 1:
            t.append(None)
            e.append(None)
        t.append(times[i])
        e.append(v)
        last = i
    return [float("nan") if v is None else v for v in t], \
        [float("nan") if v is None else v for v in e]


def tripped(track, limit):
    """(row, wheel) of every move stopped before its end, one mark a move:
    where its following error first passed the limit in the trace, else
    (RCL saw it pass within the tick, or another error or Ctrl-C stopped
    it) its last row, on the wheel further behind."""
    errs = {w: dict(track.following_error(w)) for w in WHEEL_COLOURS}
    cut = set(track.cut_short())
    out = []
    for move in track.moves:
        over = [(i, w) for w in WHEEL_COLOURS for i in range(move.first, move.last + 1)
                if abs(errs[w].get(i, 0)) > limit]
        if over:
            out.append(min(over))
        elif move.last in cut:
            out.append((move.last, max(WHEEL_COLOURS,
                                       key=lambda w: abs(errs[w].get(move.last, 0)))))
    return out


# ------------------------------------------------------------ the day
def draw_day(ax, track, limit):
    """Each move of the day as one point: its largest following error
    (either wheel), at its start in hours, coloured by trip; the limit,
    and every move stopped before its end."""
    errs = {w: dict(track.following_error(w)) for w in WHEEL_COLOURS}
    for k, (first, last) in enumerate(track.trips()):
        moves = [mv for mv in track.moves if first <= mv.first <= last]
        ts = [track.t[mv.first] / 3600 for mv in moves]
        peaks = [max(abs(errs[w].get(i, 0)) for w in WHEEL_COLOURS
                     for i in range(mv.first, mv.last + 1)) for mv in moves]
        ax.plot(ts, peaks, "o", ms=3, color=trip_colour(k),
                label="trip %d" % (k + 1))[0].set_gid("day-%d" % (k + 1))
    ax.axhline(limit, color="red", ls="--", lw=1, label="FERR-LIMIT %d counts" % limit)
    early = tripped(track, limit)
    if early:
        ax.plot([track.t[i] / 3600 for i, _ in early],
                [abs(errs[w][i]) for i, w in early], "X", color="red", ms=10,
                label="stopped before its end")[0].set_gid("day-tripped")
    ax.set_ylim(0, max(limit * 1.1, ax.get_ylim()[1]))
    ax.set_xlabel("hours since the start")
    finish_panel(ax, "largest error, counts",
                 "the day: each move's largest following error", columns=5)


def mark_cuts(ax, track, times, cuts):
    for c in cuts:
        ax.axvline(c, color="grey", ls=":", lw=0.6)
    trips = track.trips()
    if len(trips) > 1:
        for k, (first, _) in enumerate(trips):
            ax.axvline(times[first], color=trip_colour(k), lw=2, alpha=0.5)
