"""The page's Python side: rcl's prompt for a browser tab, run by the
page's Web Worker inside Pyodide. Lines in; output, prompts and per-tick
observations out. As rcl/repl.py is for the terminal, and it is
rcl/repl.py's own shell (Repl) that runs each line: the ` ok`, the error
texts, the `NAME]` continuation prompt, abandoned definitions, #help.

    s = Session(send)              RCL loaded on a simulated board, as `rcl` does
    s.submit("2 3 + .")            -> the next line's prompt ('' or 'SQ] ')
    s.complete("FORW")             -> ["FORWARD", ...] for TAB
    s.set_rate(10)                 virtual time 10x the wall clock (0: flat out)

`send(kind, data)` is the page's: ("out", text) as the machine prints,
("frame", {...}) with the robot's positions from the ticks' rows since
the last frame (the pen) and the status line, ("files", [names]) when a
line wrote files (SAVE-SYSTEM). After a line's prompt has gone to the
page, `settle()` sends the frame with Fig. 1 of the line's end: a stop
is reported before that drawing is worked out.

A Stop (Ctrl-C, the Stop button) is the page's `stop_asked()`, which
takes the page's stop flag (shared memory) when it is set. The session
looks at it at the end of every tick, and the pacer's `sleep` wakes on
it: there, between two ticks, the board is in no middle of anything, so
the motors go off at once and a frame tells the page (its `motor` and
`aux`, the relay latches), before the machine's break is requested and
taken at its next primitive, where the error ends the word and its
` Interrupted` is printed. A stop the ticks do not see (Python running
without ticks, e.g. Fig. 1 being worked out) reaches the machine a little
later as Python's SIGINT (Pyodide's interrupt buffer, set by the page):
the machine breaks at its next primitive, motors first, as in the
terminal; whatever the path, a frame with the latches as they are goes
to the page before any text.
"""
import json
import os
import signal
import time

import rcl
from rcl import status
from rcl.board import CLOCK_HZ
from rcl.cli import BANNER, Output, version
from rcl.plot import FERR_LIMIT
from rcl.repl import Repl
from rcl.robot import ARM_ON, BEEPER, GRIP_ON
from rcl.sim.observe import Trace
from rcl.sim.pace import Pacer
from rcl.terminal import search_order_names
from rcl.track import COUNTS_PER_INCH, Track

FRAME_S = 1 / 30            # wall seconds between two frames sent to the page
FLAT_OUT_FRAME_S = 1 / 20   # as fast as possible: the run comes first (a frame is ~5 ms in the page)
STATUS_S = 1 / 5            # between two status lines worked out (rcl.status reads Forth variables)
FIGURE_S = 1 / 2            # between two Fig. 1 worked out (rcl.track: 30 ms a time natively)
FIGURE_ROWS = 600           # Fig. 1 shows the last rows: 6 s of motion
FIGURE_SHARE = 10           # Fig. 1 waits at least 10 times what it took last: at most a
                            # tenth of the worker's time, which then holds the view still
CATCH_UP_S = 0.1            # wall seconds an idle catch-up may take
SHORTEST_SLEEP_S = 0.002    # shorter waits are left to the next tick's
AUX_MOTORS = ARM_ON | GRIP_ON | BEEPER      # what stop_motors turns off in the aux latch


class PageStream:
    """What the machine prints, to the page as it comes; relays that
    changed since the last frame are told first (a stop's motors off
    reach the page before its ` Interrupted`)."""

    def __init__(self, send, session):
        self.send, self.session = send, session

    def write(self, text):
        if text:
            self.session.relays_first()
            self.send("out", text)

    def flush(self):
        pass

    def isatty(self):
        return False


CTRL_C = 3                  # what the page answers a read with when Stop or Ctrl-C came


class PageTerminal:
    """The page reads the lines: the shell only asks for a line when a word
    does (ACCEPT, KEY, DBG's keys), through the page's blocking `read_line`
    and `read_key`. A stop while a word waits there answers Ctrl-C, raised
    as the terminal's read raises it."""

    rewinds = False

    def __init__(self, read_line=None, read_key=None):
        self.read_line, self.read_key_fn = read_line, read_key

    def read(self, shown):
        if self.read_line is None:
            raise EOFError
        line = self.read_line(shown)
        if line is None:
            raise EOFError
        if line == chr(CTRL_C):
            raise KeyboardInterrupt
        return line

    def read_key(self, interrupted=None):
        # (interrupted: the terminal's way to see a lost Ctrl-C; the page's
        # stop flag ends this wait itself)
        key = self.read_key_fn() if self.read_key_fn is not None else None
        if key is None:
            raise rcl.ForthError(-39, "No input")
        if key == CTRL_C:
            raise KeyboardInterrupt
        return key


class FigureCut(Exception):
    """Ctrl-C while Fig. 1 was worked out: the stop comes first."""


class Frames(Trace):
    """The board's observation hook for the page: rcl.sim.observe.Trace's
    rows (one per tick in which something changed), sent in frames of
    about 30 a second of wall time with the status line."""

    def __init__(self, session):
        self.session = session
        self.sent = self.drawn = time.monotonic()
        self.took = 0.0                   # seconds the last Fig. 1 took
        self.recent = []                  # the rows Fig. 1 shows
        session.frames = self
        super().__init__(session.m.board, keep=True)

    def __call__(self, board):
        self.session.take_stop()
        before = len(self.rows)
        super().__call__(board)
        if len(self.rows) > before:
            self.recent.append(self.rows[-1])
            if len(self.recent) > 2 * FIGURE_ROWS:
                del self.recent[:-FIGURE_ROWS]
        if time.monotonic() - self.sent >= self.session.frame_s:
            self.session.frame()

    def figure(self):
        """Fig. 1 of the last rows, from rcl.track (what rcl.plot draws):
        time (idle stretches cut to 2 s), each wheel's speed and command
        in in/s, the breakpoints, the following error in counts."""
        self.drawn = start = time.monotonic()
        before = signal.getsignal(signal.SIGINT)

        def cut(signum, frame):           # Ctrl-C: the break as before, then this figure is dropped
            if callable(before):
                before(signum, frame)
            raise FigureCut
        try:
            signal.signal(signal.SIGINT, cut)
        except ValueError:                # not the main thread: nothing to cut short
            before = None
        try:
            return self.worked_out()
        except FigureCut:
            return None
        finally:
            if before is not None:
                signal.signal(signal.SIGINT, before)
            self.took = time.monotonic() - start
            self.session.cost["figure_s"] += self.took
            self.session.cost["figures"] += 1

    def stop_between_steps(self):
        """A Stop that came while Fig. 1 is worked out (always between two
        ticks) is taken at once, and the figure dropped."""
        if self.session.take_stop():
            raise FigureCut

    def worked_out(self):
        track = Track(self.recent[-FIGURE_ROWS:], self.FIELDS)
        if not track.n:
            return None
        self.stop_between_steps()
        times, cuts = track.motion_time()
        fig = {"t": times, "cuts": cuts, "limit": FERR_LIMIT, "acc": [], "dec": []}
        for wheel in ("left", "right"):
            self.stop_between_steps()
            fig["speed_" + wheel] = [v / COUNTS_PER_INCH for v in track.speed(wheel)]
            ref = track.reference(wheel)
            fig["ref_" + wheel] = [v / COUNTS_PER_INCH for v in ref]
            fig["ferr_" + wheel] = [[times[i], e] for i, e in track.following_error(wheel)]
            for move in track.moves:
                bp = move.breakpoints[wheel]
                if bp is not None:
                    fig["acc"].append([times[bp[0]], ref[bp[0]] / COUNTS_PER_INCH])
                    fig["dec"].append([times[bp[1]], ref[bp[1]] / COUNTS_PER_INCH])
        return fig


class RatePacer(Pacer):
    """rcl.sim.pace.Pacer at `rate` times the wall clock; the page's sleep.
    A wait too short to sleep well is skipped: the next tick's due time
    is absolute, so the pace is kept all the same."""

    started = 0                   # pacers made so far: a frame names the one that paced it

    def __init__(self, clock, rate, sleep, take_stop=lambda: False):
        RatePacer.started += 1
        self.number = RatePacer.started

        def wait(s):                  # a stop: no wait, and one that comes meanwhile ends it
            if s / rate >= SHORTEST_SLEEP_S and not take_stop():
                sleep(s / rate)
                take_stop()
        super().__init__(clock, wall=lambda: time.monotonic() * rate, sleep=wait)


class Session:
    def __init__(self, send, sleep=time.sleep, read_line=None, read_key=None,
                 image=None, rate=1.0, folder=None, frames_as_json=False, stop_asked=None):
        self.send, self.sleep = send, sleep
        self.stop_asked = stop_asked or (lambda: False)
        self.relays_sent = None           # (motor, aux) latches the page was last sent
        self.running = False              # a line runs (run): a stop can be taken
        self.as_json = frames_as_json     # the page's: one string crosses to JavaScript at once
        self.folder = folder or os.getcwd()
        self.m = self.frames = None       # (rcl.open's own output comes before either)
        self.out = Output(PageStream(send, self), flush_each=True)
        self.m = rcl.open(write=self.out.write, image=image)
        self.repl = Repl(self.m, self.out, term=PageTerminal(read_line, read_key))
        self.rate = None
        self.cost = {"frame_s": 0.0, "frames": 0, "figure_s": 0.0, "figures": 0}   # the bench's
        self.said, self.last_state = 0.0, None     # the status line's time, the state then
        self.set_rate(rate)
        Frames(self)
        self.files = self.listing()
        self.prompt = ""

    def banner(self):
        """The terminal's first line, and the first prompt."""
        self.out.write(BANNER % (version(), "simulated board, in a browser tab") + "\n")
        self.set_rate(self.rate)                  # the page's time starts now
        self.prompt = self.repl.begin_line()
        return self.prompt

    # ------------------------------------------------------------ lines
    def submit(self, line, shown=""):
        """Run one typed line as the terminal's prompt does (the page has
        echoed it after `shown`, the prompt); -> the next line's prompt."""
        self.run(line, shown)
        self.prompt = self.repl.begin_line()
        return self.prompt

    def run(self, line, shown):
        self.running = True                       # a stop is taken only now
        try:
            self.catch_up()
            self.out.redraw(" ")                  # F83's blank after the line
            self.out.tail = shown + line + " "
            self.repl.onecmd(line)
        finally:
            self.running = False
            self.frame(figure=False)              # the prompt first: Fig. 1 comes with settle()
            self.report_files()

    def settle(self):
        """The frame with Fig. 1 as the last line left it (sent after the
        prompt: working it out takes a while in the page)."""
        try:
            self.frame(force=True)
        except KeyboardInterrupt:           # a Stop that came as the word ended
            pass

    def evaluate(self, text):
        """window.rcl.evaluate: each line as if typed (the console shows
        it all but the last prompt, `self.prompt`); -> what the lines
        printed, ` ok` and error texts included."""
        printed, send = [], self.out.stream.send

        def keep(kind, data):
            printed.append(data)
            send(kind, data)
        for i, line in enumerate(text.split("\n")):
            send("out", (self.prompt if i else "") + line)
            printed.append("\n" if i else "")
            self.out.stream.send = keep
            try:
                self.run(line, self.prompt)
            finally:
                self.out.stream.send = send
            self.prompt = self.repl.begin_line()
        return "".join(printed)

    def complete(self, typed):
        """TAB: the words of the search order starting with `typed`."""
        key = typed.upper()
        return [name for name in search_order_names(self.m) if name.upper().startswith(key)] \
            if typed else []

    def catch_up(self):
        """Between lines the board's clock keeps pace with the page's, as
        the terminal's prompt does (Repl.catch_up), for at most
        CATCH_UP_S of wall time a call: a rate the machine cannot follow
        (an idle RCL board still runs its control loop each tick) moves
        the page's time on instead, so the next line never waits long."""
        pacer = self.m.board.pacer
        if pacer is None:
            return
        self.m.board.pacer = None                 # the stretch is due already
        try:
            end = time.monotonic() + CATCH_UP_S
            while time.monotonic() < end:
                behind = pacer.wall() - pacer.start_wall - \
                    (self.m.clock - pacer.start_clock) / CLOCK_HZ
                if behind <= 0:
                    break
                self.m.sim.run(min(behind, 0.5))
            else:
                pacer = RatePacer(self.m.clock, self.rate, self.sleep, self.take_stop)
        finally:
            self.m.board.pacer = pacer
        self.frame()

    # ------------------------------------------------------------- stop
    def take_stop(self):
        """At a tick's end or in the pacer's wait (between two ticks): a
        Stop the page asked for is taken here, motors first, the page told,
        then the machine's break; a break already pending (Python's SIGINT)
        gets its motors off here too. -> whether a stop is under way. Only
        while a line runs: a stop that came as it ended is not left pending
        for the next."""
        m = self.m
        if not self.running:
            return False
        asked = self.stop_asked()
        if not (asked or m.break_pending):
            return False
        if m.board.motor_latch or m.board.aux_latch & AUX_MOTORS:
            m.board.stop_motors()
            self.frame(figure=False)
        if asked:
            m.request_break()
        return True

    def relays_first(self):
        """Before any text: a frame when the relay latches changed since
        the last frame (what the page draws is never older than what it
        prints)."""
        if self.frames is not None and \
                (self.m.board.motor_latch, self.m.board.aux_latch) != self.relays_sent:
            self.frame(figure=False)

    # ------------------------------------------------------------- time
    def set_rate(self, rate):
        """Virtual seconds per wall second; 0: as fast as the machine goes."""
        rate = float(rate)
        self.rate = rate
        self.frame_s = FRAME_S if rate > 0 else FLAT_OUT_FRAME_S
        self.m.board.pacer = RatePacer(self.m.clock, rate, self.sleep, self.take_stop) \
            if rate > 0 else None

    # ----------------------------------------------------------- frames
    def pose(self, state):
        """The last state with the robot's pose, clock and pacing now."""
        sim, data = self.m.sim, dict(state)
        data["x"], data["y"], heading = sim.pose
        data["heading"], data["arm"], data["jaw"], data["t"] = heading % 360, sim.arm, sim.jaw, sim.seconds
        pacer = self.m.board.pacer
        data["wall"] = time.monotonic()
        data["behind"] = pacer.lateness[-1] if pacer is not None and pacer.lateness else 0.0
        data["pacer"] = pacer.number if pacer is not None else 0
        return data

    def state(self):
        """The robot now, as the status line and .POSE say it; the wall
        clock (seconds) and, at a rate, how far the virtual clock was
        behind it at the last tick (virtual seconds), and which pacer that
        was (a new one starts when the rate changes, or when the page's
        time had to move on: `catch_up`)."""
        sim = self.m.sim
        x, y, heading = sim.pose
        pacer = self.m.board.pacer
        return {"t": sim.seconds, "x": x, "y": y, "heading": heading % 360,
                "arm": sim.arm, "jaw": sim.jaw, "status": status.text(self.m),
                "rate": self.rate,
                "wall": time.monotonic(),
                "behind": pacer.lateness[-1] if pacer is not None and pacer.lateness else 0.0,
                "pacer": pacer.number if pacer is not None else 0}

    def frame(self, force=False, figure=True):
        """To the page: the robot now, the pen's points (x, y of each trace
        row since the last frame, flat), and Fig. 1 when due (force: now)."""
        start = self.frames.sent = time.monotonic()
        rows, self.frames.rows = self.frames.rows, []
        if force or start - self.said >= STATUS_S:
            self.said, self.last_state = start, self.state()
            data = dict(self.last_state)
        else:
            data = self.pose(self.last_state)
        board = self.m.board
        data["motor"], data["aux"] = self.relays_sent = (board.motor_latch, board.aux_latch)
        data["path"] = [v for r in rows for v in r[1:3]]
        data["cost"] = dict(self.cost)
        every = FIGURE_S if self.rate else 4 * FIGURE_S       # flat out: the run comes first
        every = max(every, FIGURE_SHARE * self.frames.took)   # and never much of the time
        if figure and (rows and start - self.frames.drawn >= every or force):
            data["figure"] = self.frames.figure()
        self.send("frame", json.dumps(data) if self.as_json else data)
        self.cost["frame_s"] += time.monotonic() - start
        self.cost["frames"] += 1

    # ------------------------------------------------------------ files
    def programs(self):
        """The article's listings and RCL's screens, to open in the page:
        [(name, text)], examples first."""
        root = self.m.screens_dir
        out = []
        for sub in ("examples", ""):
            folder = os.path.join(root, sub)
            for name in sorted(os.listdir(folder)):
                if name.endswith(".fs"):
                    with open(os.path.join(folder, name), encoding="latin-1") as f:
                        out.append([os.path.join(sub, name) if sub else name, f.read()])
        return out

    def listing(self):
        try:
            return {e.name: e.stat().st_mtime_ns for e in os.scandir(self.folder) if e.is_file()}
        except OSError:
            return {}

    def report_files(self):
        """Files a line wrote (SAVE-SYSTEM's image): the page offers them."""
        now = self.listing()
        changed = sorted(n for n, t in now.items() if self.files.get(n) != t)
        self.files = now
        if changed:
            self.send("files", changed)
