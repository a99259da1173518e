"""Stepping through colon definitions one word at a time (DBG, BREAK:).

No terminal here: a Stepper advances by one command and returns a Step,
a plain record of what the view shows. rcl/words/debugging.py maps keys
to commands and draws the record as text; a web console can drive the
same Stepper and draw the same record its own way.

    s = Stepper(m)
    s.start(xt)             DBG: enter the colon word xt        -> Step
    s.resume(ip, label)     BREAK: step the rest of the running
                            definition from ip                  -> Step
    s.advance(command)      STEP INTO OVER FINISH CONTINUE      -> Step
    s.done, s.ip            over, and the address its last EXIT popped

How it runs. The definitions being stepped are interpreted a cell at a
time by the reference loop's own rules (inner.run_from): the same clock
costs, interrupt checks and return-stack protocol, so a stepped word does
exactly what it does when it runs. A word stepped over runs as it always
runs (m.call: its compiled code), interrupts and moves included, so a
move (FORWARD waits for the control loop) is one step. Literals and
control operations (branches, DO and LOOP, EXIT) run between the steps:
a step stops before each word called.

    TRIP's body:  | WARNING | RERB | (RLIT) 20 | IPS | (RLIT) 3 | FEET | BACKWARD | ...
                    ^ step    ^ step  (runs)     ^ step  (runs)   ^ step  ^ step

Each frame is a definition being stepped and the return-stack depth at
its entry, as run_from's `base`: the frame is over at the EXIT that
takes the return stack below it.
"""
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

from rcl.board import NullBoard
from rcl.errors import ForthError
from rcl.forth.inner import CONTROL_BY_CF, N, RSTACK_CELLS, SENTINEL, decode_args
from rcl.forth.memory import MASK, signed
from rcl.forth.primitives import LITERAL, REGISTRY

STEP, INTO, OVER, FINISH, CONTINUE = "step", "into", "over", "finish", "continue"
BREAKS = ("(BREAK)", '(BREAK")')       # the cells BREAK: and BREAK" compile


@dataclass
class Step:
    """What the stepping view shows: the word about to run (None when the
    stepped definition is over), where its call was compiled from, the
    definitions being stepped (outermost first), the data stack (signed,
    bottom first), the word the last step ran and whether it moved the
    robot, and on a board its time of day and pose (x, y in inches,
    heading in degrees). `label`: the BREAK" text the view stopped at."""
    word: Optional[str]
    file: Optional[str] = None
    line: Optional[int] = None
    chain: List[str] = field(default_factory=list)
    stack: List[int] = field(default_factory=list)
    ran: Optional[str] = None
    moved: bool = False
    time: Optional[str] = None
    pose: Optional[Tuple[float, float, float]] = None
    label: Optional[str] = None


class Stepper:
    """Steps the colon definitions of machine m (see the module's text)."""

    def __init__(self, m):
        self.m = m
        self.frames = []          # [(xt, base)], outermost first
        self.ip = SENTINEL
        self.user_from = m.memory.fetch(m.a_fence)   # STEP goes into words above it
        self.label = None

    @property
    def done(self):
        return not self.frames

    # ------------------------------------------------------------ entering
    def start(self, xt):
        """Enter the colon word xt as if called from Python (DBG)."""
        xt = self.resolve(xt)
        if self.code_field(xt) != N["(DOCOL)"]:
            return None
        self.enter(xt, SENTINEL)
        self.run_silent()
        return self.view(None)

    def resume(self, ip, label=None):
        """Step the definition running at ip, from ip on (a BREAK: in it
        was reached): its frame starts where its return address lies,
        under the DO loops open at ip (frame_depth). None if no colon
        definition holds ip."""
        m = self.m
        xt = self.containing(ip)
        if xt is None or self.code_field(xt) != N["(DOCOL)"]:
            return None                    # (BREAK) run from the prompt: no code to step
        base = len(m.rs) - frame_depth(m, xt, ip)
        self.frames.append((xt, max(base, 0)))
        self.ip = ip
        self.label = label
        self.run_silent()
        return self.view(None)

    def enter(self, xt, ret):
        """A colon call stepped into: what m.call and m.enter do, but the
        body is stepped here instead of run compiled."""
        m = self.m
        if m.clock >= m.deadline:
            m.housekeep()
        m.clock += m.cost[N["(DOCOL)"]]
        m.rs.append(ret)
        if len(m.rs) > RSTACK_CELLS:
            m.rs_overflow()
        self.frames.append((xt, len(m.rs)))
        self.ip = (xt + 2) & MASK

    # ------------------------------------------------------------ advancing
    def advance(self, command):
        """Carry out one command; -> the Step the view shows next."""
        if self.done:
            return self.view(None)
        self.label = None
        before = board_view(self.m)[1]
        name = self.word_name(self.ip)
        if command == CONTINUE:
            self.run_until(0)
        elif command == FINISH:
            self.run_until(len(self.frames) - 1)
        elif command in (STEP, INTO) and self.steps_into(command):
            self.enter(self.fetch(self.ip), (self.ip + 2) & MASK)
        else:
            self.run_cell()
        self.run_silent()
        return self.view(name, before)

    def steps_into(self, command):
        """INTO goes into any colon word; STEP only into the user's own
        (defined above the fence), over the system's and RCL's."""
        xt = self.fetch(self.ip)
        if self.code_field(xt) != N["(DOCOL)"]:
            return False
        return command == INTO or xt >= self.user_from

    def run_until(self, depth):
        """Run cell by cell until only `depth` frames are left, or a BREAK:
        in a stepped definition is reached (then stop after it)."""
        while len(self.frames) > depth:
            stop = self.at_break()
            self.run_cell()
            if stop:
                return

    def run_silent(self):
        """Run the literals and control operations up to the next word."""
        while self.frames and self.silent_cell():
            self.run_cell()

    def run_cell(self):
        """One cell, as inner.run_from runs it (a BREAK: cell of a stepped
        definition costs its call and does nothing more: the view is here)."""
        m, ip = self.m, self.ip
        xt = self.fetch(ip)
        cf = self.code_field(xt)
        nxt = (ip + 2) & MASK
        op = CONTROL_BY_CF.get(cf)
        p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
        if op is None and p is not None and p.kind is LITERAL:
            if m.clock >= m.deadline:
                m.housekeep()
            m.clock += m.cost[cf]
            args, self.ip = decode_args(m, p, nxt)
            p.fn(m, *args)
            return
        if op is not None:
            if m.clock >= m.deadline:
                m.housekeep()
            m.clock += m.cost[cf]
            self.ip = op.run(m, nxt)
            if op.leaves:
                self.leave()
            return
        if p is not None and p.name in BREAKS:
            self.pass_break(cf, p)
            self.ip = nxt
            return
        self.ip = m.call(xt, nxt)
        self.leave()

    def pass_break(self, cf, p):
        """A BREAK: cell inside the stepped code: its time, its text off the
        stack (BREAK"), and the view names it."""
        m = self.m
        if m.clock >= m.deadline:
            m.housekeep()
        m.clock += m.cost[cf]
        self.label = break_label(break_text(m) if p.name == '(BREAK")' else None)

    def leave(self):
        """Frames whose EXIT (or R> DROP) took the return stack below them."""
        while self.frames and len(self.m.rs) < self.frames[-1][1]:
            self.frames.pop()

    # ------------------------------------------------------------- looking
    def fetch(self, addr):
        return self.m.memory.fetch(addr)

    def code_field(self, xt):
        return self.fetch(xt)

    def resolve(self, xt):
        """A DEFER's action (DBG of a deferred word steps what it runs)."""
        while self.code_field(xt) == N["(DODEFER)"]:
            xt = self.fetch((xt + 2) & MASK)
        return xt

    def silent_cell(self):
        """Does the cell at ip run without a step (a literal, a control
        operation other than EXECUTE, a BREAK: passed: the view names it)?"""
        cf = self.code_field(self.fetch(self.ip))
        op = CONTROL_BY_CF.get(cf)
        if op is not None:
            return op.name != "EXECUTE"
        p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
        return p is not None and (p.kind is LITERAL or p.name in BREAKS)

    def at_break(self):
        cf = self.code_field(self.fetch(self.ip))
        p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
        return p is not None and p.name in BREAKS

    def word_name(self, ip):
        xt = self.fetch(ip)
        return self.m.dictionary.name_of(xt) or "at %d" % xt

    def containing(self, ip):
        """The word whose code holds the cell before ip, or None."""
        from rcl.forth import wordloc
        return None if ip == SENTINEL else wordloc.containing(self.m, (ip - 2) & MASK)

    def view(self, ran, before=None):
        m = self.m
        time, pose = board_view(m)
        moved = pose is not None and before is not None and moved_by(before, pose)
        step = Step(word=None, chain=[m.dictionary.name_of(xt) or "at %d" % xt
                                      for xt, _ in self.frames],
                    stack=list(m.stack), ran=ran, moved=moved, time=time, pose=pose,
                    label=self.label)
        if self.frames:
            step.word = self.word_name(self.ip)
            step.file, step.line = m.locations.at(self.ip)
        return step


# -------------------------------------------------- breaks, frames, the board
def moved_by(before, after):
    """Did the robot move: a quarter inch, or half a degree? (Less is a
    wheel rolling to rest after the last move, not this step's doing.)"""
    (x0, y0, h0), (x1, y1, h1) = before, after
    turned = abs((h1 - h0 + 180) % 360 - 180)
    return (x1 - x0) ** 2 + (y1 - y0) ** 2 >= 0.25 ** 2 or turned >= 0.5


def break_label(text=None):
    """How the view names a BREAK: (or a BREAK" text")."""
    return "BREAK:" if text is None else 'BREAK" %s"' % text


def break_text(m):
    """The text BREAK" compiled, off the data stack (addr u)."""
    if len(m.s) < 2:                       # (BREAK") run by hand
        raise ForthError(-4)
    n, a = m.s.pop(), m.s.pop()
    return m.memory.text(a, n)


def frame_depth(m, xt, ip):
    """Return-stack cells the definition xt has pushed since its entry
    when it reaches ip: the DO loops and locals open there, counted along
    its code from the start (structured code nests them in the text).
    0 when xt's code cannot be followed to ip."""
    from rcl.forth.decode import decode
    if m.memory.fetch(xt) != N["(DOCOL)"]:
        return 0
    depth, a = 0, (xt + 2) & MASK
    loops = {"(DO)": 3, "(?DO)": 3, "(LOOP)": -3, "(+LOOP)": -3}
    for _ in range(4096):
        if a == ip:
            return max(depth, 0)
        if a > ip:
            return 0
        ins = decode(m, a)
        depth += loops.get(ins.op, 0)
        if ins.prim is not None and ins.prim.name == "(LOCALS)":
            depth += sum(ins.args)
        depth += {">R": 1, "R>": -1, "2>R": 2, "2R>": -2}.get(
            m.dictionary.name_of(ins.xt) or "", 0)
        a = ins.next
    return 0


def board_view(m):
    """(time of day 'HH:MM:SS', pose) on a board, (None, None) without one.
    The pose is the simulated robot's, else RCL's own dead reckoning."""
    if isinstance(m.board, NullBoard):
        return None, None
    try:
        ticks, per_day = m.board.time_of_day()
    except Exception:                      # a board that cannot say
        return None, None
    s = int(ticks * 86400 / max(per_day, 1))
    time = "%02d:%02d:%02d" % (s // 3600 % 24, s // 60 % 60, s % 60)
    sim = getattr(m, "sim", None)
    pose = tuple(sim.pose) if sim is not None else rcl_pose(m)
    return time, pose


def rcl_pose(m):
    """RCL's POSE-X, POSE-Y (2VARIABLEs, thousandths of an inch) and
    POSE-HEADING (tenths of a degree), if RCL is loaded."""
    values = []
    for name, double in (("POSE-X", True), ("POSE-Y", True), ("POSE-HEADING", False)):
        hit = m.dictionary.find(name)
        if hit is None:
            return None
        body = (hit[0] + 2) & MASK
        v = m.memory.fetch(body)
        if double:                         # F83's 2!: high cell first
            v = (v << 16) | m.memory.fetch((body + 2) & MASK)
            v = v - (1 << 32) if v >> 31 else v
        values.append(v)
    return (values[0] / 1000, values[1] / 1000, signed(values[2]) / 10)

