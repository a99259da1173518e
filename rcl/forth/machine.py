"""The Forth machine: memory, dictionary, inner and outer interpreter, and
the Python face (`evaluate`, `session`, `stack`, `include`).

Boot lays down the system variables, the FORTH and ROOT word lists, a
header for every registered primitive, then loads the kernel screens
(rcl/kernel/*.fs: the words easier said in Forth). The booted image is
kept per process, so a new machine is a copy of bytes, not a re-boot.
"""
import contextlib
import os
import signal
import sys
import threading

from rcl.board import NullBoard
from rcl.errors import Bye, ForthError, open_source
from rcl.forth import inner, state
from rcl.forth.compile_deps import CodeDeps
from rcl.forth.compiler import compile_code
from rcl.forth.decode import TooLarge
from rcl.forth.dictionary import IMMEDIATE, Dictionary
from rcl.forth.inner import Inner
from rcl.forth.memory import (DICT_START, MASK, USER_AREA, WATCH_CODE,
                              WATCH_HEADER, Memory, signed)
from rcl.forth.outer import Outer
from rcl.forth.primitives import CLOCK_HZ, REGISTRY
from rcl.forth.wordloc import Locations
from rcl import words as _words  # noqa: F401  (registers every word set)

# Forth calls nest as Python calls in compiled code: leave room for the
# return stack's 1000 cells (ForthError -5 beyond) before Python's own limit.
sys.setrecursionlimit(max(sys.getrecursionlimit(), 8000))

KERNEL_DIR = os.path.join(os.path.dirname(os.path.dirname(__file__)), "kernel")

# System variables, one cell each from USER_AREA; the order is the layout.
USER_VARIABLES = ["DP", "BASE", "STATE", "DPL", ">IN", "BLK", "#TIB", "SPAN",
                  "SCR", "HLD", "WARNING", "CAPS", "RCL-LITERALS", "FENCE",
                  "LAST", "CURRENT", "#ORDER", "VOC-LINK", "CSP", "TMP",
                  "WIDE-NUMBER", "CONTEXT"]   # CONTEXT is last: it takes 8 cells
CLEAR_CODE = bytes(range(256)).translate(bytes(b & ~WATCH_CODE for b in range(256)))

# The machine's own system state (rcl/forth/state.py): the xts the compiler
# and the kernel lay down (CODE records them), the FORTH and ROOT word
# lists, the files INCLUDE and REQUIRE have seen.
state.system("xt_of", lambda m: {}, lambda m: dict(m.xt_of),
             lambda m, d: setattr(m, "xt_of", {str(k): int(v) for k, v in d.items()}))
state.system("forth_wid", lambda m: 0)
state.system("root_wid", lambda m: 0)
state.system("included", lambda m: set(), lambda m: sorted(m.included),
             lambda m, d: setattr(m, "included", set(d)))
# The file:line each address of the dictionary came from (wordloc.py): the
# system's, as its code is (a saved system's backtraces name its files).
state.system("locations", lambda m: Locations(), lambda m: m.locations.plain(),
             lambda m, d: setattr(m, "locations", Locations.from_plain(d)))


def attr_name(var):
    return "a_" + {"DP": "dp", ">IN": "in", "#TIB": "ntib", "#ORDER": "norder",
                   "VOC-LINK": "voclink", "RCL-LITERALS": "rcllit",
                   "WIDE-NUMBER": "wide"}.get(
        var, var.lower().replace("-", ""))


class Forth(Inner, Outer):
    """A bare F83 machine. See docs/API.md."""

    _image = None                      # the booted memory, shared per process

    def __init__(self, write=None, board=None, system=None):
        self.memory = Memory(self.watched)
        self.mem = self.memory.mem
        self.watch = self.memory.watch
        self.dictionary = Dictionary(self)
        for i, var in enumerate(USER_VARIABLES):
            setattr(self, attr_name(var), USER_AREA + 2 * i)
        self.write = write             # callable(str) for streamed output
        self.out = []
        self.step_limit = None         # primitives one evaluate() may run
        self.keys = []                 # typed-ahead key codes for KEY
        self.read_key = None           # callable() -> key code, at the prompt
        self.read_line = None          # callable() -> line, for ACCEPT
        self.key_ready = None          # callable() -> bool, for KEY?
        self.in_input = False          # waiting in read_key/read_line
        self.in_forth = 0              # evaluate/include calls under way
        self.in_safe_state = False     # running the abort hooks (after an error)
        self._init_inner()
        self.code_deps = CodeDeps()        # what each compiled function rests on
        self._init_outer()
        if system is None and type(self)._image is None:
            state.init(self)               # every word set's declared state, fresh
            self._boot()
            type(self)._image = state.snapshot(self)
        else:                              # the booted system, or the one given
            state.restore(self, type(self)._image if system is None else system)
        self.board = board if board is not None else NullBoard()
        self.board.attach(self)

    # --------------------------------------------------------------- boot
    def _boot(self):
        mem = self.memory
        mem.store(self.a_dp, DICT_START)
        mem.store(self.a_base, 10)
        mem.store(self.a_dpl, MASK)
        mem.store(self.a_warning, MASK)
        mem.store(self.a_caps, MASK)
        mem.store(self.a_rcllit, MASK)
        d = self.dictionary
        # FORTH: its header lands in the scratch list TMP, then FORTH's own
        # list takes over that header so FORTH finds itself.
        xt = d.create("FORTH", inner.N["(DOVOC)"], wid=self.a_tmp)
        self.forth_wid = d.new_wordlist()
        mem.store(self.forth_wid, mem.fetch(self.a_tmp))
        mem.store(self.a_current, self.forth_wid)
        d.set_order([self.forth_wid])
        self.xt_of["FORTH"] = xt
        self.xt_of["ROOT"] = d.create("ROOT", inner.N["(DOVOC)"])
        self.root_wid = d.new_wordlist()
        for var in USER_VARIABLES:
            x = d.create(var, inner.N["(DOCON)"])
            d.comma(getattr(self, attr_name(var)))
        for p in REGISTRY[1:]:
            if p.hidden:            # a runtime gets a header only if it asks (BREAK:'s)
                continue
            wid = self.root_wid if p.wordlist == "ROOT" else self.forth_wid
            x = d.create(p.name, p.number, wid=wid)
            self.xt_of[p.name] = x
            if p.immediate:
                d.set_flag(d.last, IMMEDIATE)
        d.set_order([self.forth_wid, self.root_wid])
        mem.store(self.a_warning, 0)
        for name in sorted(os.listdir(KERNEL_DIR)):
            if name.endswith(".fs"):
                self.include(os.path.join(KERNEL_DIR, name))
        mem.store(self.a_warning, MASK)
        mem.store(self.a_fence, d.here)
        self.xt_of["ON-ABORT"] = d.find("ON-ABORT")[0]
        self.xt_of["SAFE-STATE"] = d.find("SAFE-STATE")[0]
        self.xt_of["BREAKS"] = d.find("BREAKS")[0]
        self.invalidate()
        self.clock = 0                     # power-on: a copied image starts at 0 too
        self.reschedule()

    # -------------------------------------------------------------- caches
    def compile(self, addr):
        if not self.compiled:
            return lambda m: m.run_from(addr, len(m.rs))
        try:
            f = compile_code(self, addr)
        except TooLarge:                   # a wild EXECUTE: the reference loop runs it
            f = lambda m: m.run_from(addr, len(m.rs))    # noqa: E731
            self.fn[addr] = f
            return f
        self.fn[addr] = f
        self.code_deps.add(self, addr, f)
        return f

    def compile_ahead(self):
        """Compile every colon definition in the dictionary now, not at its
        first call. For a host that answers a board's ticks in real time
        (a link): a move's first tick would otherwise compile the words it
        reaches (tens of ms under load), answer late, and the board drive
        on the old command meanwhile. -> how many were compiled."""
        fetch, d, n = self.memory.fetch, self.dictionary, 0
        for wid in d.wordlists():
            for lfa in d.lfas(wid):
                xt = (lfa + 2) & MASK
                body = (xt + 2) & MASK
                if fetch(xt) == inner.DOCOL and body not in self.fn:
                    self.compile(body)
                    n += 1
        return n

    def invalidate(self, lo=None, hi=None):
        """Forget the compiled code resting on memory from lo to hi (all
        of it without a range: memory or the costs changed under it)."""
        if lo is not None:
            self.code_deps.hit(self, lo, hi - lo)
            return
        self.code_deps.drop_all(self)
        self.fn.clear()
        self.watch[:] = self.watch.translate(CLEAR_CODE)

    def watched(self, addr, n=2):
        """A store of n bytes from addr hit compiled code or a header."""
        w = 0
        for i in range(n):
            w |= self.watch[(addr + i) & MASK]
        if w & WATCH_CODE:
            self.code_deps.hit(self, addr, n)
        if w & WATCH_HEADER:
            self.dictionary.header_stored(addr)

    def warning_on(self):
        return self.memory.fetch(self.a_warning) != 0

    # -------------------------------------------------------------- output
    def type(self, text):
        if self.write is not None:
            self.write(text)
        else:
            self.out.append(text)

    def take_output(self):
        text = "".join(self.out)
        self.out = []
        return text

    # ---------------------------------------------------------- Python face
    @property
    def stack(self):
        """The data stack as signed ints, bottom first."""
        return [signed(v) for v in self.s]

    @property
    def seconds(self):
        return self.clock / CLOCK_HZ

    def evaluate(self, text):
        """Interpret text as typed lines; -> what it printed.

        With `step_limit` set, a call running more than that many primitives'
        worth of virtual time aborts with ` Step limit `."""
        self.sources[0].lines = iter(text.split("\n"))
        if self.step_limit is not None:
            self.clock_limit = self.clock + self.step_limit * self.cost[inner.DOCOL]
            self.reschedule()
        try:
            with self.breakable():
                while self.refill():
                    self.guarded(self.interpret)
        finally:
            self.sources[0].lines = iter(())
            self.clock_limit = float("inf")
            self.reschedule()
        return self.take_output()

    def session(self, text):
        """What F83's screen shows for these lines typed at the prompt."""
        screen = []
        for line in text.split("\n"):
            try:
                out = self.evaluate(line)
                ok = "" if self.compiling else " ok"
                screen.append("%s %s%s\n" % (line, out, ok))
            except ForthError as e:
                screen.append("%s %s%s\n" % (line, e.output, e.screen()))
        return "".join(screen)

    def include(self, path):
        """Load a text file, as INCLUDE does."""
        f = open_source(path)
        self.included.add(os.path.abspath(path))     # as INCLUDE does: REQUIRE sees it
        with f, self.breakable():
            lines = (line.rstrip("\r\n") for line in f)
            return self.guarded(lambda: self.include_lines(lines, path))

    def wait_input(self, read):
        """read() for KEY or ACCEPT: never inside an interrupt handler, and
        Ctrl-C while it waits interrupts at once."""
        if self.masked:
            raise ForthError(-21, "Waits for input")
        if self.break_pending:             # a Ctrl-C just before the wait: taken now
            self.housekeep()
        self.in_input = True
        try:
            return read()
        finally:
            self.in_input = False

    @contextlib.contextmanager
    def breakable(self):
        """While Forth runs, Ctrl-C (SIGINT) becomes a break request, taken
        at the next primitive boundary of the foreground; waiting for input
        (`self.in_input`) it interrupts at once. Only where Python's own
        Ctrl-C handler is in place (the main thread, not nested)."""
        self.in_forth += 1
        try:
            if threading.current_thread() is not threading.main_thread() \
                    or signal.getsignal(signal.SIGINT) is not signal.default_int_handler:
                yield
                return

            def on_sigint(signum, frame):
                self.request_break()           # (kept if the raise is swallowed)
                if self.in_input:
                    raise KeyboardInterrupt
            signal.signal(signal.SIGINT, on_sigint)
            try:
                yield
            finally:
                signal.signal(signal.SIGINT, signal.default_int_handler)
        finally:
            self.in_forth -= 1

    def guarded(self, action):
        """Run action; any error aborts the machine and raises ForthError."""
        try:
            return action()
        except Bye as exc:                 # its output leaves with it, as an error's does
            exc.output = self.take_output()
            raise
        except (Exception, KeyboardInterrupt) as exc:   # never a traceback
            e = self.traced(exc)
            if e.code == -56:              # QUIT: back to the prompt, stack kept
                self.quit()
                return None
            self.fail(e)

    def fail(self, e):
        e = self.board.explain(e)          # a cause only the board knows (a late host)
        if e.file is None:                 # where in a file it happened
            for src in reversed(self.sources):
                if src.kind == "file":
                    e.file, e.line = src.name, src.line
                    break
        self.abort()
        e.output = self.take_output()
        raise e from None
