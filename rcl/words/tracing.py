"""Seeing what the robot did: TRACE-ON TRACE-OFF SAVE-TRACE PLOT.

The words reach the board only through its observation hook,
`board.trace(file)` (rcl/board.py), and draw with rcl.plot from the rows
it keeps, so the same words serve any board that keeps a trace.

    TRACE-ON                 start a fresh trace (a row per tick that changed)
    ... moves ...
    PLOT square.png          draw what the trace holds so far (.png .svg .pdf)
    SAVE-TRACE square.csv    the rows as CSV, as `rcl --trace` writes them
    TRACE-OFF                stop recording (what was kept stays for PLOT)

While a trace records, the move log (rcl/words/moves.py) keeps each
move's start and words beside it (`marks`): SAVE-TRACE and `rcl --trace`
add them as the CSV's last column, `word` (on the rows of each move, the
chain that commanded it), and PLOT labels the moves with them.
"""
import csv

from rcl.errors import ForthError
from rcl.forth import state
from rcl.forth.primitives import CALL, prim
from rcl.safefile import write_atomically
from rcl.words.compiling import parse_word


# The trace being recorded, if any: the session's.
state.session("tracer", lambda m: None)


def tracer(m):
    return m.tracer


def start_trace(m, file=None):
    """Start the machine's trace (a fresh one); -> the recorder."""
    stop_trace(m)
    rec = m.board.trace(file)
    if rec is None:
        raise ForthError(-21, "This board keeps no trace")
    rec.marks = m.moves.marks = []        # each move's (start, words) from now
    m.tracer = rec
    return rec


def stop_trace(m):
    rec = tracer(m)
    if rec is not None:
        rec.stop()
        m.moves.marks = None


def marks_of(rec):
    return getattr(rec, "marks", None) or []


def rows_with_words(rec):
    """The recorder's fields and rows with the `word` column added."""
    from rcl.track import WORD, word_column
    fields = list(rec.FIELDS)
    rows = rec.rows
    words = word_column([r[0] for r in rows], [r[fields.index("motor")] for r in rows],
                        marks_of(rec))
    return fields + [WORD], [tuple(r) + (w,) for r, w in zip(rows, words)]


def kept(m):
    rec = tracer(m)
    if rec is None:
        raise ForthError(-21, "No trace: TRACE-ON first")
    return rec


def ferr_limit(m):
    """RCL's FERR-LIMIT now, for the plot's limit line (100 if not loaded)."""
    from rcl.plot import FERR_LIMIT
    hit = m.dictionary.find("FERR-LIMIT")
    return m.memory.fetch((hit[0] + 2) & 0xFFFF) if hit else FERR_LIMIT


def plot_to(m, name, title=None):
    """Draw the trace kept so far to the file `name`."""
    from rcl import plot
    from rcl.track import Track
    rec = kept(m)
    try:
        plot.draw(Track.of(rec, marks=marks_of(rec)), name, title, ferr_limit=ferr_limit(m))
    except plot.PlotError as e:
        raise ForthError(-37, str(e)) from None


@prim("TRACE-ON", "( -- ) start a fresh trace of the board", kind=CALL)
def trace_on(m):
    start_trace(m)


@prim("TRACE-OFF", "( -- ) stop tracing; PLOT still draws what was kept", kind=CALL)
def trace_off(m):
    stop_trace(m)


@prim("PLOT", "( -- ) draw the trace so far to the file named next", kind=CALL)
def plot_word(m):
    plot_to(m, parse_word(m))


@prim("SAVE-TRACE", "( -- ) write the trace so far as CSV to the file named next",
      kind=CALL)
def save_trace(m):
    name, rec = parse_word(m), kept(m)

    def write(f):
        fields, rows = rows_with_words(rec)
        out = csv.writer(f)
        out.writerow(fields)
        out.writerows(rows)
    try:
        write_atomically(name, write, binary=False)
    except OSError as e:
        raise ForthError(-37, "%s: %s" % (name, e.strerror)) from None
