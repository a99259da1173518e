"""`rcl --trace FILE.csv` and `rcl --plot FILE.png`: record the board from
the start of the run, and at its end (whatever ends it) write the CSV and
draw the plot.

    Recording(m, trace_path, plot_path)   checks names and matplotlib first,
                                          starts the machine's trace (TRACE-ON's)
    ... files, -e, the prompt or the pipe ...
    finish() -> [error text]              CSV moved into place, plot drawn

The CSV streams into a temporary file beside FILE.csv and takes its name
at the end, so an earlier FILE.csv is never left half-written. On the way
it gains its last column, `word`: on each move's rows, the words that
commanded the move (the move log's, rcl/words/moves.py).
"""
import csv
import os

from rcl.errors import RclError
from rcl.safefile import temporary_beside
from rcl.track import WORD, Words
from rcl.words.tracing import marks_of, start_trace, stop_trace, tracer


class RecordingError(RclError):
    """The command line asks for a recording that cannot be made."""


class Recording:
    def __init__(self, m, trace_path=None, plot_path=None, title=None):
        self.m, self.trace_path, self.plot_path = m, trace_path, plot_path
        self.title = title
        self.tmp = self.file = None
        if plot_path:
            from rcl import plot
            try:
                plot.check_name(plot_path)
                plot.require_matplotlib()
            except plot.PlotError as e:
                raise RecordingError("--plot: %s" % e) from None
            folder = os.path.dirname(os.path.abspath(plot_path))
            if not os.path.isdir(folder):
                raise RecordingError("--plot: no folder %s to write %s in" % (folder, plot_path))
        if trace_path:
            self.file = self.open_temporary(trace_path)
        try:
            start_trace(m, self.file)
        except RclError:
            self.discard()
            raise RecordingError("--trace and --plot need a board that keeps a trace "
                                 "(the simulated board, not --bare)") from None

    def open_temporary(self, path):
        try:
            fd, self.tmp = temporary_beside(path)
        except OSError as e:
            raise RecordingError("--trace: cannot write %s: %s" % (path, e.strerror)) from None
        return os.fdopen(fd, "w", newline="")

    def discard(self):
        if self.file is not None:
            self.file.close()
            os.unlink(self.tmp)
            self.file = None

    def finish(self):
        """Stop the trace, put the CSV in place, draw the plot; -> errors."""
        errors = []
        stop_trace(self.m)
        if self.file is not None:
            try:
                self.file.close()
                add_words(self.tmp, marks_of(tracer(self.m)))
                os.replace(self.tmp, self.trace_path)
            except OSError as e:
                errors.append("--trace: %s: %s" % (self.trace_path, e.strerror))
            except ValueError as e:              # a row the trace did not write
                errors.append("--trace: %s: %s" % (self.trace_path, e))
            self.file = None
        if self.plot_path:
            from rcl.words.tracing import plot_to
            try:
                plot_to(self.m, self.plot_path, self.title)
            except RclError as e:
                errors.append("--plot: %s" % (getattr(e, "message", None) or e))
        return errors


def add_words(path, marks):
    """Rewrite the CSV at path with the `word` column added, a row at a
    time (a day's trace is large)."""
    tmp = path + ".words"
    with open(path, newline="") as src, open(tmp, "w", newline="") as dst:
        rows, out = csv.reader(src), csv.writer(dst)
        fields = next(rows, [])
        out.writerow(fields + [WORD])
        t, motor, words = fields.index("t"), fields.index("motor"), Words(marks)
        for row in rows:
            row.append(words(float(row[t]), float(row[motor])))
            out.writerow(row)
    os.replace(tmp, path)
