"""What a trace says: the board's rows turned into moves, wheel speeds,
breakpoints, commanded against encoder positions, stops, beeps and trips,
for rcl.plot to draw (or a test to check). No matplotlib here.

    rows (rcl.sim.observe.Trace, or its CSV)    one per tick that changed:
      t x y heading left right ref_left ref_right motor aux arm jaw beeper
      [word]  the words that commanded the move under way (the CSV's last
              column; for rows in memory, made from the move log's marks)
          |
    Track --> moves        a wheel's GO relay bit on, from set to clear,
                           and its word
          --> speed(w)     counts/s from the counts' change in each tick
          --> commanded(w) the reference frequency summed over the move:
                           where the PLL was told to be (RCL's EXPACC/1200)
          --> breakpoints  where the reference stops rising, starts falling
          --> stops, beeps, trips (moves apart by more than `trip_gap` s)
          --> cut_short    moves stopped before their end

A host that drives a real board over a link sees the same columns but the
pose (encoder counts per tick, the references it wrote, the relays): give
x, y and heading as None and the path is dead-reckoned from the counts.
"""
import csv
import math

from rcl.robot import (COUNTS_PER_INCH, M1_GO, M1_REV, M2_GO, M2_REV,
                       TRACK_IN)

FIELDS = ("t", "x", "y", "heading", "left", "right", "ref_left", "ref_right",
          "motor", "aux", "arm", "jaw", "beeper")
WHEELS = {"left": (M1_GO, M1_REV), "right": (M2_GO, M2_REV)}
TICK_S = 0.0100005            # RCL's tick: 6667 counts of 1.5 us
CREEP_HZ = 50.0               # V-CREEP's 600 crpm as encoder counts a second
WORD = "word"                 # the column naming the words that commanded each move
TEXT_FIELDS = (WORD,)


def memoized(method):
    """Each wheel's column is computed once per Track (the plot asks often)."""
    def cached(self, wheel):
        key = (method.__name__, wheel)
        if key not in self.memo:
            self.memo[key] = method(self, wheel)
        return self.memo[key]
    cached.__doc__ = method.__doc__
    cached.__name__ = method.__name__
    return cached


class TraceError(ValueError):
    """A trace that cannot be read (not a trace file, a bad row)."""


def load_csv(path):
    """-> Track of a CSV written by `rcl --trace` (or Trace(board, file))."""
    try:
        with open(path, newline="") as f:
            table = list(csv.reader(f))
    except OSError as e:
        raise TraceError("%s: %s" % (path, e.strerror)) from None
    if not table or "t" not in table[0]:
        raise TraceError("%s: not a trace (no header naming t, left, right ...)" % path)
    fields = table[0]
    text = [f in TEXT_FIELDS for f in fields]
    try:
        rows = [tuple(v if is_text else None if v == "" else float(v)
                      for v, is_text in zip(row, text)) for row in table[1:]]
    except ValueError as e:
        raise TraceError("%s: %s" % (path, e)) from None
    return Track(rows, fields)


class Words:
    """The words of the move under way at each row, rows in time order:
    `words(t, motor)` -> the label of the last of `marks` [(start s,
    label)] that started at or before t (a move starts between ticks, so
    before its first row) while a GO bit is on in `motor`, else ""."""

    def __init__(self, marks):
        self.marks, self.k = marks, -1

    def __call__(self, t, motor):
        marks = self.marks
        while self.k + 1 < len(marks) and marks[self.k + 1][0] <= t:
            self.k += 1
        return marks[self.k][1] if self.k >= 0 and int(motor) & (M1_GO | M2_GO) else ""


def word_column(t, motor, marks):
    """Per row, the words of its move (Words)."""
    words = Words(marks)
    return [words(ti, mi) for ti, mi in zip(t, motor)]


class Move:
    """Rows first..last (last: the row in which the GO bits cleared);
    `word`: the words that commanded it (`TRIP > TURN-LEFT > LEFT`), ""
    when the trace does not say."""

    def __init__(self, first, last, word=""):
        self.first, self.last, self.word = first, last, word
        self.breakpoints = {}     # wheel -> (row at acceleration end, row at deceleration start)

    def __repr__(self):
        return "Move(%d, %d)" % (self.first, self.last)


class Track:
    """Columns of a trace (lists, by field name) and what they add up to."""

    def __init__(self, rows, fields=FIELDS, trip_gap=600.0, marks=None):
        fields = list(fields)
        missing = [f for f in ("t", "left", "right", "ref_left", "ref_right", "motor")
                   if f not in fields]
        if missing:
            raise TraceError("a trace needs the columns %s" % ", ".join(missing))
        self.col = {f: [row[i] for row in rows] for i, f in enumerate(fields)}
        if WORD not in self.col and marks is not None:    # the move log's starts
            self.col[WORD] = word_column(self.col["t"], self.col["motor"], marks)
        self.n = len(rows)
        self.t = self.col["t"]
        self.trip_gap = trip_gap
        self.pose_known = "x" in self.col and all(v is not None for v in self.col["x"])
        self.x, self.y, self.heading = self.pose() if self.n else ([], [], [])
        self.memo = {}
        self.moves = self.find_moves()
        for move in self.moves:
            for wheel in WHEELS:
                move.breakpoints[wheel] = self.find_breakpoints(move, wheel)

    @classmethod
    def of(cls, trace, **kw):
        """-> Track of a Trace kept in memory (`keep=True`); `marks`, the
        move log's [(start s, label)], names each move's words."""
        return cls(trace.rows, trace.FIELDS, **kw)

    def part(self, first, last):
        """-> Track of rows first..last only (one trip of a day)."""
        fields = list(self.col)
        rows = list(zip(*(self.col[f][first:last + 1] for f in fields)))
        return Track(rows, fields, self.trip_gap)

    # ------------------------------------------------------------- pose
    def pose(self):
        """x, y (inches) and heading (degrees): as observed, else dead-reckoned."""
        if self.pose_known:
            return self.col["x"], self.col["y"], self.col["heading"]
        x, y, h = [0.0], [0.0], [0.0]
        left, right = self.col["left"], self.col["right"]
        for i in range(1, self.n):
            dl = (left[i] - left[i - 1]) / COUNTS_PER_INCH
            dr = (right[i] - right[i - 1]) / COUNTS_PER_INCH
            a = math.radians(h[-1]) + (dr - dl) / (2 * TRACK_IN)   # the mid-step heading
            x.append(x[-1] + (dl + dr) / 2 * math.cos(a))
            y.append(y[-1] + (dl + dr) / 2 * math.sin(a))
            h.append(h[-1] + math.degrees((dr - dl) / TRACK_IN))
        return x, y, h

    # ------------------------------------------------------------ moves
    def going(self, i, wheel=None):
        bits = WHEELS[wheel][0] if wheel else M1_GO | M2_GO
        return bool(int(self.col["motor"][i]) & bits)

    def find_moves(self):
        moves, first = [], None
        for i in range(self.n):
            if self.going(i) and first is None:
                first = i
            elif not self.going(i) and first is not None:
                moves.append(Move(first, i, self.word_at(first)))
                first = None
        if first is not None:
            moves.append(Move(first, self.n - 1, self.word_at(first)))
        return moves

    def word_at(self, i):
        words = self.col.get(WORD)
        return (words[i] or "") if words else ""

    def move_numbers(self):
        """(trip number, move number in its trip), both from 1, per move."""
        out = []
        for k, (first, last) in enumerate(self.trips()):
            n = 0
            for move in self.moves:
                if first <= move.first <= last:
                    n += 1
                    out.append((k + 1, n))
        return out

    def find_breakpoints(self, move, wheel):
        """(row where acceleration ends, row where deceleration begins): the
        first and last rows at the move's top reference; None for a move
        that never decelerated."""
        ref = self.col["ref_" + wheel]
        rows = [i for i in range(move.first, move.last) if self.going(i, wheel)]
        if not rows:
            return None
        top = max(ref[i] for i in rows)
        at_top = [i for i in rows if ref[i] == top]
        if not any(0 < ref[i] < top for i in rows if i > at_top[-1]):
            return None           # stopped before it could decelerate (a trip)
        return at_top[0], at_top[-1]

    # ----------------------------------------------------------- speeds
    @memoized
    def speed(self, wheel, window=3):
        """Counts per second over the last `window` ticks (an encoder count
        is a big step at these speeds). The rows are the ticks in which
        something changed: a count change after a quiet stretch took at
        most a tick."""
        c, t, out = self.col[wheel], self.t, [0.0]
        for i in range(1, self.n):
            j = max(0, i - window)
            while t[i] - t[j] > (i - j + 0.5) * TICK_S:      # not consecutive ticks
                j += 1
            if j == i:                  # after a gap: the change took at most a tick
                j = i - 1
                dt = min(t[i] - t[j], TICK_S)
            else:                       # consecutive ticks: the time between the rows
                dt = t[i] - t[j]
            out.append((c[i] - c[j]) / dt if dt > 0 else 0.0)
        return out

    @memoized
    def reference(self, wheel):
        """The commanded speed, counts/s, signed: the reference frequency
        while the wheel's GO bit is on (the 8253 makes a count per cycle)."""
        _, rev = WHEELS[wheel]
        ref = self.col["ref_" + wheel]
        return [(-ref[i] if int(self.col["motor"][i]) & rev else ref[i])
                if self.going(i, wheel) else 0.0 for i in range(self.n)]

    # ------------------------------------------------- following error
    @memoized
    def commanded(self, wheel):
        """Per row, where the wheel was told to be (counts): at each move's
        start its encoder count, then the reference summed tick by tick,
        as RCL's EXPACC sums it. Outside moves: the encoder count."""
        counts, ref = self.col[wheel], self.reference(wheel)
        q = list(counts)
        for move in self.moves:
            pos = counts[move.first]
            for i in range(move.first + 1, move.last + 1):
                pos += ref[i - 1] * (self.t[i] - self.t[i - 1])
                q[i] = pos
        return q

    @memoized
    def following_error(self, wheel):
        """(row, commanded minus encoder in the move's direction) for every
        row of every move: RCL stops everything when it passes FERR-LIMIT."""
        q, counts, out = self.commanded(wheel), self.col[wheel], []
        _, rev = WHEELS[wheel]
        for move in self.moves:
            sign = -1 if int(self.col["motor"][move.first]) & rev else 1
            out += [(i, sign * (q[i] - counts[i])) for i in range(move.first, move.last + 1)
                    if self.going(i, wheel) or i == move.last]
        return out

    # ------------------------------------------- stops, beeps and trips
    def cut_short(self):
        """Last rows of the moves stopped before their end (a following
        error, any error, Ctrl-C): the commanded speed was still above
        twice RCL's creep speed (V-CREEP, 600 crpm: 50 counts/s) in the
        move's last row with a GO bit on. A move that ends as planned has
        slowed to the creep speed by then, or never went faster."""
        out = []
        for move in self.moves:
            going = [i for i in range(move.first, move.last) if self.going(i)]
            if going and any(abs(self.reference(w)[going[-1]]) > 2 * CREEP_HZ for w in WHEELS):
                out.append(move.last)
        return out

    def stops(self, least=10.0):
        """(row, seconds) of each wait of `least` seconds or more between moves."""
        out = []
        for a, b in zip(self.moves, self.moves[1:]):
            wait = self.t[b.first] - self.t[a.last]
            if wait >= least:
                out.append((a.last, wait))
        return out

    def beeps(self):
        """Rows at which the beeper starts to sound."""
        b = self.col.get("beeper")
        if b is None:
            return []
        return [i for i in range(self.n) if b[i] and (i == 0 or not b[i - 1])]

    def trips(self):
        """(first row, last row) of each run of moves whose waits between
        them are shorter than trip_gap (MAILBOT's trips, an hour apart)."""
        if not self.moves:
            return [(0, max(self.n - 1, 0))] if self.n else []
        out, first = [], self.moves[0].first
        for a, b in zip(self.moves, self.moves[1:]):
            if self.t[b.first] - self.t[a.last] > self.trip_gap:
                out.append((first, a.last))
                first = b.first
        out.append((first, self.moves[-1].last))
        return out

    def trip_of(self, row):
        """Index of the trip a row belongs to (rows between trips: the one before)."""
        k = 0
        for j, (first, _) in enumerate(self.trips()):
            if row >= first:
                k = j
        return k

    # ------------------------------------------------------ time axis
    def motion_time(self, cut=2.0):
        """Per row, time with every stretch in which nothing changed for
        longer than `cut` seconds shortened to `cut` (a day's moves then
        share one axis); -> (times, where the cuts are on that axis)."""
        out, cuts, removed = [], [], 0.0
        for i in range(self.n):
            if i and self.t[i] - self.t[i - 1] > cut:
                removed += self.t[i] - self.t[i - 1] - cut
                cuts.append(out[-1] + cut / 2)
            out.append(self.t[i] - removed)
        return out, cuts
