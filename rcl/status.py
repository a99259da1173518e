"""The prompt's bottom status line: what the simulated robot is doing.

    09:41:07  x 40.7 y 0.0 in  heading 0.0  moving 62%  arm 8.00 jaw 0.00 in  stack 0  BEEP

On a narrow terminal the least useful fields shorten or go first (fit).

`text(m)` reads it off the machine and its board (never changing them); a
StatusLine keeps it on the terminal's last row, which a scroll region
(ESC [ 1 ; rows-1 r) takes out of the scrolling text, so output and the
prompt never write over it:

    row 1 .. rows-1    the session, scrolling as usual
    row rows           the status, redrawn in place (ESC 7, go there, ESC 8)

While a word runs a thread redraws it a few times a second; while the
prompt waits, the prompt redraws it after each of its own renders (same
thread as the prompt: the two never write at once). Every write to the
terminal goes through one lock.
"""
import os
import shutil
import threading

CELL = 0xFFFF
REFRESH_S = 0.2


# ------------------------------------------------------------------ content
def fetch_var(m, name, double=False):
    """A Forth variable's value, or None if the word does not exist."""
    hit = m.dictionary.find(name)
    if hit is None:
        return None
    body, fetch = (hit[0] + 2) & CELL, m.memory.fetch
    if double:                                   # F83's 2!: high cell first
        return (fetch(body) << 16) | fetch((body + 2) & CELL)
    return fetch(body)


def time_of_day(board):
    ticks, per_day = board.time_of_day()
    s = int(ticks * 86400 / per_day)
    return "%02d:%02d:%02d" % (s // 3600 % 24, s // 60 % 60, s % 60)


def move_text(m):
    """`moving 62%` while a base move runs (its commanded progress over its
    length), `arm moving` for the arm or gripper, else ''."""
    if fetch_var(m, "MOVING"):
        done = fetch_var(m, "Q-AT", True) or 0        # commanded progress, counts
        total = fetch_var(m, "END-AT", True) or 0
        return "moving %d%%" % min(100, 100 * done // total) if total else "moving"
    if fetch_var(m, "ARM-BITS"):
        return "arm moving"
    return ""


def sounding(board):
    return bool(board.beeps) and board.beeps[-1][1] is None


def tenths(value):
    """value to one decimal as the line shows it: never `-0.0`."""
    return "%.1f" % (round(value, 1) + 0.0)


def heading_text(degrees):
    """0.0 up to 359.9: 359.97 rounds to 0.0, not to 360.0."""
    return tenths(round(degrees, 1) % 360)


def fit(parts, width):
    """Join the parts with two blanks, within `width` columns when one is
    given. Each part is (rank, forms): its text from the longest form to
    the shortest, "" for a part that may go. While the line is too wide the
    part of lowest rank that has a shorter form takes it, so the least
    useful fields shorten or go first."""
    parts = [[rank, list(forms)] for rank, forms in parts]

    def line():
        return "  ".join(forms[0] for _, forms in parts if forms[0])
    while width is not None and len(line()) > width:
        shorter = [p for p in parts if len(p[1]) > 1]
        if not shorter:
            return line()[:width]
        min(shorter, key=lambda p: p[0])[1].pop(0)
    return line()


# What goes first when the line is too wide (the lowest rank first): the
# link's details, the arm and jaw, a beep, the move, the stack, the time.
LINK_DETAIL, ARM, BEEP, MOVE, STACK, TIME, POSE = range(7)


def linked_text(m, width=None):
    """On a board over a link, from what the host has without asking the
    board (this runs beside the word running, which owns the link): RCL's
    own pose (its dead reckoning after each move), the move, the stack, and
    the link's state."""
    x, y = (fetch_var(m, name, True) for name in ("POSE-X", "POSE-Y"))
    heading = fetch_var(m, "POSE-HEADING")
    link = m.board.status()
    parts = [(LINK_DETAIL, [link, link.partition(":")[0]])]
    if None not in (x, y, heading):
        signed = [v - (1 << 32) if v >> 31 else v for v in (x, y)]
        pose = "x %s y %s in  heading %s" % (tenths(signed[0] / 1000), tenths(signed[1] / 1000),
                                             heading_text(heading / 10))
        parts.append((LINK_DETAIL, [pose + " (RCL's)", pose]))
    parts += [(MOVE, [move_text(m), ""]), (STACK, ["stack %d" % len(m.s), ""])]
    return fit(parts, width)


def text(m, width=None):
    """The status line of machine m, within `width` columns if given: a
    simulated board's own observation (`.sim`), else what the host knows of
    a board over a link."""
    if not hasattr(m, "sim"):
        return linked_text(m, width)
    sim = m.sim
    x, y, heading = sim.pose
    parts = [(TIME, [time_of_day(sim.board), ""]),
             (POSE, ["x %s y %s in  heading %s" % (tenths(x), tenths(y), heading_text(heading))]),
             (MOVE, [move_text(m), ""]),
             (ARM, ["arm %.2f jaw %.2f in" % (sim.arm, sim.jaw), ""]),
             (STACK, ["stack %d" % len(m.s), ""]),
             (BEEP, ["BEEP" if sounding(sim.board) else "", ""])]
    return fit(parts, width)


# ------------------------------------------------------------------ drawing
class LockedStream:
    """The terminal stream, one writer at a time (output, prompt, status)."""

    def __init__(self, stream, lock):
        self.stream, self.lock = stream, lock

    def write(self, data):
        with self.lock:
            return self.stream.write(data)

    def flush(self):
        with self.lock:
            return self.stream.flush()

    def __getattr__(self, name):
        return getattr(self.stream, name)


class StatusLine:
    """The status on the terminal's last row of `stream`, for machine m.
    `bell`: ring the terminal bell when a beep starts."""

    def __init__(self, m, stream, lock, bell=True, on_idle=None):
        self.m, self.stream, self.lock, self.bell = m, stream, lock, bell
        self.on_idle = on_idle            # called before a drawing at the prompt
        self.rows = 0
        self.beeps_seen = self.beeps()
        self.running = None               # (stop event, thread) while a word runs

    def size(self):
        """The terminal's own size (not $LINES/$COLUMNS, which may be stale)."""
        try:
            size = os.get_terminal_size(self.stream.fileno())
        except (AttributeError, ValueError, OSError):
            size = shutil.get_terminal_size()
        return max(size.lines, 3), max(size.columns, 10)

    def start(self):
        """Take the last row: make room for it, then fence it off."""
        with self.lock:
            self.stream.write("\n\x1b[1A")       # the cursor is never on the last row
            self.stream.flush()
        self.draw()

    def draw(self):
        rows, cols = self.size()
        line = self.safe_text(cols - 1)
        ring = self.bell and self.new_beep()
        with self.lock:
            out = "\x1b7"
            if rows != self.rows:                # (re)set the scroll region; it homes the cursor
                out += "\x1b[1;%dr\x1b8\x1b7" % (rows - 1)
                self.rows = rows
            out += "\x1b[%d;1H\x1b[7m%s\x1b[0m\x1b[K\x1b8" % (rows, line)
            self.stream.write(out + ("\a" if ring else ""))
            self.stream.flush()

    def draw_idle(self):
        """At the prompt (the machine idle): let on_idle run, then draw."""
        if self.on_idle is not None:
            try:
                self.on_idle()
            except Exception:                    # the next line will show any error
                pass
        self.draw()

    def safe_text(self, width):
        try:
            return text(self.m, width)
        except Exception:                        # a half-changed state: skip this one
            return ""

    def beeps(self):
        """Beeps so far (a linked board's are not seen from here)."""
        sim = getattr(self.m, "sim", None)
        return len(sim.board.beeps) if sim is not None else 0

    def new_beep(self):
        n = self.beeps()
        rang, self.beeps_seen = n > self.beeps_seen, n
        return rang

    def stop(self):
        """Give the row back: the whole screen scrolls again, row cleared."""
        self.pause()
        rows, _ = self.size()
        with self.lock:
            self.stream.write("\x1b7\x1b[r\x1b8\x1b7\x1b[%d;1H\x1b[K\x1b8" % rows)
            self.stream.flush()

    # ------------------------------------------------ while a word runs
    def resume(self):
        if self.running is None:
            stop = threading.Event()
            thread = threading.Thread(target=self.keep_drawing, args=(stop,), daemon=True)
            self.running = (stop, thread)
            thread.start()

    def keep_drawing(self, stop):
        while not stop.wait(REFRESH_S):
            self.draw()

    def pause(self):
        if self.running is not None:
            stop, thread = self.running
            stop.set()                   # the prompt draws it next, after its render
            thread.join()
            self.running = None
