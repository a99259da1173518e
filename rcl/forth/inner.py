"""The inner interpreter: how threaded code runs, and where time is counted.

Threaded code is a sequence of cells, each an execution token (xt): the
address of a word's code field. The code field holds a primitive number
(< PRIM_LIMIT) or, for a DOES> child, the address of the code after DOES>.

    : SQ  DUP * ;          SQ's body:  | xt DUP | xt * | xt EXIT |
                                          ^ ip

Two ways to run it, with the same meaning:

* compiled (compiler.py): each definition becomes a Python function that
  runs from its first cell until its EXIT and returns the address EXIT
  popped. This is the fast path.
* `run_from` below: the reference loop, one cell at a time. Used where the
  compiled path cannot go (a return address that was tampered with, code
  that cannot be compiled).

The call protocol both follow: the caller pushes its return address on the
return stack and calls the callee's function; the callee's EXIT pops it and
returns it. If the popped address is not the one the caller pushed (the
callee played with R> and >R), the caller returns it in turn, and so on up
to `execute`, which carries on at that address with `run_from`. So the
return stack is always the truth.

Time: every primitive adds its cost to `clock` (units of 1/36 ns). Before a
primitive runs, if `clock >= deadline`, `housekeep` runs: it services a due
interrupt (the handler word runs to completion on its own stacks, masked)
and checks the stack limits and the step budget.

Asynchronous stops (Ctrl-C) never land in the middle of anything:
`request_break` only sets a flag and pulls the deadline in, so the stop is
taken by `housekeep` at the next primitive boundary of the foreground,
never inside an interrupt handler or a CODE word. An error inside a handler
is a tick fault: the board is told (it stops the motors and its tick), and
the foreground gets an error that names the handler.
"""
import math
import os

from rcl.errors import Bye, ForthError, Terminated, as_forth_error
from rcl.forth import control, primitives, state, wordloc
from rcl.forth.memory import MASK, PRIM_LIMIT
from rcl.forth.primitives import CALL, CONTROL, LITERAL, REGISTRY, RUNTIME, SIMPLE, prim

SENTINEL = 0                 # return address meaning "back to Python"
STACK_CELLS = 1000           # data stack limit (Stack Overflow beyond)
RSTACK_CELLS = 1000          # return stack limit
HOUSEKEEPING = 36_000_000 * 100   # check limits every 100 ms of virtual time
HANDLER_LIMIT = 36_000_000 * 1000  # a handler running 1 s of virtual time is broken
REACH = 8                    # no word indexes deeper into a stack without checking its depth
WORD_FILES = (os.path.join(os.path.dirname(os.path.dirname(__file__)), "words") + os.sep,)


# ---------------------------------------------------------------- runtimes
# What a defined word's code field does. fn(m, xt, ret) -> next ip.

@prim("(DOCOL)", kind=RUNTIME, hidden=True)
def docol(m, xt, ret):
    return m.enter((xt + 2) & MASK, ret)


@prim("(DOVAR)", kind=RUNTIME, hidden=True)
def dovar(m, xt, ret):
    m.s.append((xt + 2) & MASK)
    return ret


@prim("(DOCON)", kind=RUNTIME, hidden=True)
def docon(m, xt, ret):
    m.s.append(m.memory.fetch((xt + 2) & MASK))
    return ret


@prim("(DO2CON)", kind=RUNTIME, hidden=True)
def do2con(m, xt, ret):
    m.s.extend(m.memory.dfetch((xt + 2) & MASK))
    return ret


# A VALUE runs as a CONSTANT does; its own runtime lets TO tell them apart.
prim("(DOVALUE)", kind=RUNTIME, hidden=True)(docon)
prim("(DO2VALUE)", kind=RUNTIME, hidden=True)(do2con)


@prim("(DODEFER)", kind=RUNTIME, hidden=True)
def dodefer(m, xt, ret):
    return m.call(m.memory.fetch((xt + 2) & MASK), ret)


@prim("(DOVOC)", kind=RUNTIME, hidden=True)
def dovoc(m, xt, ret):
    m.dictionary.set_context_top((xt + 2) & MASK)
    return ret


@prim("(DOMARKER)", kind=RUNTIME, hidden=True)
def domarker(m, xt, ret):
    m.dictionary.restore_marker((xt + 2) & MASK)
    return ret


# ------------------------------------------------------- control primitives
# Their meaning is in control.py (for run_from and the compiler); fn stays None.

for _op in control.OPS:
    prim(_op.name, _op.effect, kind=CONTROL)(None)

CONTROL_BY_CF = {p.number: control.BY_NAME[p.name] for p in REGISTRY[1:] if p.kind is CONTROL}
N = {p.name: p.number for p in REGISTRY[1:]}
DOCOL = N["(DOCOL)"]


def default_costs(m=None):
    return [p.cost if p else 0 for p in REGISTRY]


def saved_costs(m):
    """The primitives' costs that differ from their declarations, by name."""
    defaults = default_costs()
    return {REGISTRY[i].name: c for i, c in enumerate(m.cost) if i and c != defaults[i]}


def load_costs(m, costs):
    from rcl.forth.primitives import BY_NAME
    m.cost = default_costs()
    for name, c in costs.items():
        if name in BY_NAME:
            m.cost[BY_NAME[name].number] = int(c)


# clock units per primitive (set_cost changes one): kept with the system
state.system("cost", default_costs, saved_costs, load_costs)


def rt_push(m, v):
    m.s.append(v)


class Inner:
    """The inner-interpreter half of the machine (mixed into Forth)."""

    def _init_inner(self):
        self.s = []
        self.rs = []
        self.irq_s = []
        self.irq_rs = []
        self.clock = 0
        self.deadline = HOUSEKEEPING
        self.hk_next = HOUSEKEEPING
        self.clock_limit = math.inf
        self.masked = False
        self.irq = None          # interrupt source: .due and .service(machine)
        self.fn = {}             # code address -> compiled function
        self.interrupts = 0
        self.compiled = True     # False: run everything through run_from
        self.waiting_until = None
        self.break_pending = False   # Ctrl-C seen, to be taken at a primitive boundary
        self.leave_signal = None     # and a signal asked to quit
        self.stop_error = None       # or an error to raise there (request_stop)
        self.handler_deadline = math.inf
        # A wait's fast-forward, if the board behind the machine has one (a
        # simulated board gives itself at attach): an object with
        #   wait_started()            a wait (spend_waiting) begins
        #   repeat_idle_ticks(clock, n, c, limit) -> (clock, n left)
        #                             n primitives of c units from clock, while
        #                             every tick's handler only reads, counted
        #                             in arithmetic, stopping before a handler
        #                             would reach limit (the step budget); the
        #                             machine moves its clock there (n left ==
        #                             n: declined)
        #   skip_to_tick(target)      the time of day run to one tick short
        #                             of BIOS tick target at once (or not)
        # Each may decline; the result is the same as waiting tick by tick.
        self.fast_forward = None

    # ---------------------------------------------------------- calling
    def enter(self, addr, ret):
        """Run the threaded code at addr as a call returning to ret."""
        rs = self.rs
        rs.append(ret)
        if len(rs) > RSTACK_CELLS:
            self.rs_overflow()
        f = self.fn.get(addr) or self.compile(addr)
        return f(self)

    def set_cost(self, name, microseconds):
        """Make primitive `name` cost this many microseconds of virtual time."""
        from rcl.board import CLOCK_HZ
        from rcl.forth.primitives import BY_NAME
        self.cost[BY_NAME[name].number] = round(microseconds * CLOCK_HZ / 1_000_000)
        self.invalidate()

    def call(self, xt, ret):
        """Run the word xt as if called from threaded code; -> next ip."""
        mem = self.mem
        cf = mem[xt] | (mem[(xt + 1) & MASK] << 8)
        if self.clock >= self.deadline:
            self.housekeep()
        if cf >= PRIM_LIMIT:                       # a DOES> child
            self.clock += self.cost[N["(DOCOL)"]]
            self.s.append((xt + 2) & MASK)
            return self.enter(cf, ret)
        p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
        if p is None:
            raise ForthError(-260)
        self.clock += self.cost[cf]
        if p.kind is RUNTIME:
            return p.fn(self, xt, ret)
        if p.kind is SIMPLE or p.kind is CALL:
            p.fn(self)
            return ret
        if p.name == "EXECUTE":
            return self.call(self.s.pop(), ret)
        raise ForthError(-14, "Compile only", p.name)

    def execute(self, xt):
        """Run xt from Python until it returns."""
        r = self.call(xt, SENTINEL)
        if r != SENTINEL:
            self.run_from(r)

    def forth_error(self, exc):
        """The Forth error for exc, raised while Forth ran. An IndexError is
        a stack underflow only when it came from a word's own code (a
        primitive, a control operation, compiled code) and a stack really
        ran short (or the word said so: a bare `raise IndexError`); any
        other is a bug of ours, reported as an internal error."""
        if not isinstance(exc, IndexError):
            return as_forth_error(exc)
        tb = exc.__traceback__
        while tb is not None and tb.tb_next is not None:
            tb = tb.tb_next
        if tb is not None and word_code(tb.tb_frame.f_code):
            if not exc.args or len(self.s) < REACH:
                return ForthError(-4)
            if len(self.rs) < REACH:
                return ForthError(-6)
        return ForthError(-4095, "Internal error: IndexError: %s" % exc)

    def traced(self, exc):
        """forth_error(exc) for an error about to be reported, with the words
        it ran through (wordloc.py), worked out now from the return stack and
        exc's traceback, once. (CATCH does not pay for this.)"""
        e = self.forth_error(exc)
        if e.backtrace is None:
            try:
                e.backtrace = wordloc.backtrace(self, self.rs, exc.__traceback__)
            except Exception:                    # a broken dictionary: no backtrace
                e.backtrace = []
        return e

    def rs_overflow(self):
        del self.rs[:]
        raise ForthError(-5)

    # ------------------------------------------------- reference interpreter
    def run_from(self, ip, base=None):
        """Interpret threaded code from ip, one cell at a time.

        Stops when ip reaches SENTINEL, or, with `base`, at the EXIT that
        leaves the return stack below `base` (returning the popped ip).
        """
        rs, fetch = self.rs, self.memory.fetch
        while base is not None or ip != SENTINEL:
            xt = fetch(ip)
            ip = (ip + 2) & MASK
            cf = fetch(xt)
            op = CONTROL_BY_CF.get(cf)
            if op is None:
                p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
                if p is not None and p.kind is LITERAL:
                    if self.clock >= self.deadline:
                        self.housekeep()
                    self.clock += self.cost[cf]
                    args, ip = decode_args(self, p, ip)
                    p.fn(self, *args)
                else:
                    ip = self.call(xt, ip)
                    if base is not None and len(rs) < base:
                        return ip            # the callee took our frame off (R> DROP)
                continue
            if self.clock >= self.deadline:
                self.housekeep()
            self.clock += self.cost[cf]
            ip = op.run(self, ip)
            if op.leaves and base is not None and len(rs) < base:
                return ip
        return ip

    # ------------------------------------------------ time and interrupts
    def housekeep(self):
        """Clock passed the deadline: limits, then any due interrupt, then a
        pending break (only in the foreground)."""
        if self.masked and self.clock >= self.handler_deadline:
            raise ForthError(-291, "Runs too long")
        if len(self.s) > STACK_CELLS:
            del self.s[:]
            raise ForthError(-3)
        if len(self.rs) > RSTACK_CELLS:
            self.rs_overflow()
        if self.clock >= self.clock_limit and not self.masked:   # the foreground's budget
            self.clock_limit = math.inf
            raise ForthError(-259)
        if self.clock >= self.hk_next:
            self.hk_next = self.clock + HOUSEKEEPING
        src = self.irq
        if src is not None and not self.masked and src.due is not None \
                and self.clock >= src.due:
            self.interrupt(src)
        if self.break_pending and not self.masked:
            self.break_pending = False
            self.reschedule()
            # Motors first: before the error climbs the stack and its
            # backtrace is built (the abort's safe state stops them again).
            self.board.stop_motors()
            if self.leave_signal:
                raise Terminated(self.leave_signal)
            error, self.stop_error = self.stop_error, None
            raise error or ForthError(-28, "Interrupted")
        self.reschedule()

    def request_break(self, leave=None):
        """Ctrl-C (or, with leave, the number of a signal to quit on): stop
        the foreground at its next primitive boundary. Safe to call from a
        signal handler at any moment: it only sets flags and pulls the
        deadline in."""
        self.leave_signal = self.leave_signal or leave
        self.break_pending = True
        self.deadline = -1

    def request_stop(self, error):
        """A board lost what it needs (its link): raise `error` in the
        foreground at its next primitive boundary, as a break is taken."""
        self.stop_error = self.stop_error or error
        self.request_break()

    def catch_up(self, t):
        """A board has accounted for the time up to t itself (idle ticks
        counted in arithmetic, or a board's own clock on a link): the clock
        moves there, never back, and the next deadline is recomputed."""
        self.clock = max(self.clock, t)
        self.reschedule()

    def attach(self, source):
        """Plug in an interrupt source: an object with `due` (the clock value
        at which it next wants service, or None) and `service(machine)`,
        which runs with interrupts masked on the handler's own stacks and
        must move `due` on. A board is such a source."""
        self.irq = source
        self.reschedule()

    def run_handler(self, xt):
        """From a source's service(): run the Forth word xt to completion.
        Any error in it is a tick fault: the board makes itself safe (motors
        and tick off) and the error, naming the handler, goes on to the
        foreground, whatever word that was running."""
        # The handler's second starts here, not at the interrupt: a board on
        # a link may first move the clock on to its tick's time (catch_up).
        self.handler_deadline = self.clock + HANDLER_LIMIT
        self.reschedule()
        try:
            self.execute(xt)
        except BaseException as exc:        # noqa: B036  (Bye and Ctrl-C included)
            raise self.tick_fault(xt, exc) from None

    def tick_fault(self, xt, exc):
        """The error to report for exception exc inside handler xt."""
        try:
            self.board.tick_failed()
        finally:
            self.board.stop_motors()
        e = self.forth_error(exc) if not isinstance(exc, Bye) else ForthError(-290, "BYE")
        text = {-1: "ABORT", -56: "QUIT"}.get(e.code) or e.display()
        return ForthError(-290, "%s in the tick handler %s; tick stopped, INSTALL "
                          "restarts it" % (text, self.handler_name(xt)))

    def handler_name(self, xt):
        """The handler's name, and the word a DEFER handler runs, if known."""
        name = self.dictionary.name_of(xt) or "at %d" % xt
        if self.mem[xt] | (self.mem[(xt + 1) & MASK] << 8) == N["(DODEFER)"]:
            action = self.memory.fetch((xt + 2) & MASK)
            name += " (%s)" % (self.dictionary.name_of(action) or "at %d" % action)
        return name

    def reschedule(self):
        """Recompute the deadline after an interrupt source changed."""
        # (comparisons rather than min(): this runs several times a tick)
        d = self.hk_next
        if self.masked:
            limit = self.handler_deadline
        else:
            limit = self.clock_limit
            src = self.irq
            if src is not None and src.due is not None and src.due < limit:
                limit = src.due
        self.deadline = limit if limit < d else d
        if self.break_pending and not self.masked:
            # A pending break is taken at once. Tested after the write: a stop
            # another thread (a link's reader) asks meanwhile set -1 first.
            self.deadline = -1

    def interrupt(self, src):
        """Service src with interrupts masked and the handler's own stacks."""
        saved = self.s, self.rs
        self.s, self.rs = self.irq_s, self.irq_rs
        self.masked = True
        self.handler_deadline = self.clock + HANDLER_LIMIT
        self.deadline = min(self.hk_next, self.handler_deadline)
        self.interrupts += 1
        try:
            src.service(self)
        finally:
            del self.irq_s[:], self.irq_rs[:]
            self.s, self.rs = saved
            self.masked = False
            self.handler_deadline = math.inf
            self.reschedule()

    def spend(self, n):
        """The foreground spends n primitives' worth of default-cost time, as
        a busy loop would: interrupts fall due and are serviced between its
        primitives exactly where the loop's would be, and their time does
        not count toward n."""
        c = self.cost[DOCOL]
        while n > 0:
            if self.clock >= self.deadline:
                self.housekeep()
                continue
            k = -(-(int(self.deadline) - self.clock) // c)   # primitives until due
            if k >= n:
                self.clock += n * c
                return
            self.clock += k * c
            n -= k

    def spend_waiting(self, n, idle):
        """spend(n) for a waiting word. With a fast-forward, while the Forth
        word `idle` answers true (asked outside time: it is the rule of the
        tick handler's program, that it would only read), the fast-forward
        may count the ticks out in arithmetic instead: the same clock, ticks
        and time of day. It is handed all it needs and says how far it got;
        a tick's worth runs the ordinary way whenever it declines (which also
        times the handler for it)."""
        ff = self.fast_forward
        if ff is None:
            self.spend(n)
            return
        c = self.cost[DOCOL]
        ff.wait_started()
        while n > 0:
            if self.ask(idle):
                clock, left = ff.repeat_idle_ticks(self.clock, n, c, self.clock_limit)
                self.catch_up(clock)
                if left < n:
                    n = left
                    continue
            k = min(n, max(1, -(-(int(self.deadline) - self.clock) // c)))
            self.spend(k)
            n -= k
            if n and self.clock >= self.deadline:
                self.housekeep()

    def ask(self, xt):
        """Run the Forth word xt outside virtual time; -> the cell it leaves.
        Its primitives' time is given back and no interrupt is serviced
        meanwhile, so a question (IDLE?) changes nothing a program sees."""
        clock, deadline = self.clock, self.deadline
        self.deadline = math.inf
        try:
            self.execute(xt)
            return self.s.pop()
        finally:
            self.clock = clock
            self.deadline = deadline
            if self.break_pending:           # (asked meanwhile: stands, as in reschedule)
                self.deadline = -1

    def advance_to(self, t):
        """Skip the clock forward to t, servicing every interrupt due on the
        way exactly when it falls due (for waiting words). While it waits,
        `waiting_until` tells an interrupt source how far nothing else runs."""
        self.waiting_until = t
        self.hk_next = max(self.hk_next, t)     # nothing to check while waiting
        self.reschedule()
        try:
            while self.deadline <= t:
                self.clock = max(self.clock, int(self.deadline))
                self.housekeep()
        finally:
            self.waiting_until = None
        self.clock = max(self.clock, t)


def word_code(code):
    """Is this Python code a word's: a primitive, control.py, this module
    (the reference loop) or compiled code?"""
    name = code.co_filename
    return (name == COMPILED or name.startswith(WORD_FILES)
            or name in (__file__, control.__file__))


COMPILED = primitives.COMPILED   # the file name compiled code (and a body made from a template) is given


def decode_args(m, p, ip):
    """The inline arguments of literal primitive p at ip -> (args, next ip)."""
    if p.decode is not None:
        return p.decode(m, ip)
    fetch = m.memory.fetch
    args = tuple(fetch((ip + 2 * i) & MASK) for i in range(p.args))
    return args, (ip + 2 * p.args) & MASK
