"""The inside of a block in Python: simple primitives with the data stack
kept in locals. The compiler's straight-line half (compiler.py assembles
blocks into a function and writes their jumps and calls; compile_loops.py
makes a one-block DO loop a Python `while`).

`op_simple(ins, ind)` writes one instruction of a block's fast path. The
data stack is not touched as it goes: `vs` is a list of atoms (Python
names such as `t3`, or constants such as `5`) standing for the top cells.
`take(n)` gives an operation its inputs from `vs`, loading from the real
stack (`s.pop()`) only what `vs` does not hold; an inline template's
outputs become new atoms, or numbers when its inputs are all numbers
(`2 3 +` is `5`). `flush` writes `vs` back (`s.append`, `s.extend`) where
the block ends and before anything that looks at the real stack; when the
last thing done to the real stack was a pop, that pop becomes a peek and
its cell takes the deepest atom (a pop and a push cost twice a store):

    : SQ+1  DUP * 1+ ;      t1 = s[-1]              # DUP takes 1 (a pop, made a peek)
                            t2 = (t1 * t1) & 0xFFFF # *
                            t3 = (t2 + 1) & 0xFFFF  # 1+
                            s[-1] = t3              # flush at the block's end

A comparison's flag that only a branch uses is never made: `branch_test`
drops its line and the branch tests the comparison itself (`2 < IF`:
`if not ((t2 ^ 0x8000) < (2 ^ 0x8000)): b = 2`).

A primitive with no template is called as Python (`P3(m)`), after a flush
and with the clock handed back to m.clock (`clock_out`): in the middle of
a block it sees exactly the clock the reference loop would show.

An RCL literal's DPL is stored only before a word that may read it
(`flush_dpl`; in a Python `while` loop, once while nothing changes it:
compile_loops.py). A locals frame (rcl/words/localvars.py) is the return
stack's `vs`: its cells stay Python names (`rs_known`) and the line that
pushes them (`rs_pending`) is emitted only before something that may look
at the return stack (`forget_rs`). `slow_entry` gives the same
instruction's (cost, function, arguments) for the exact slow path.

All the generator knows on one path through a block (the atoms in `vs`, a
DPL not yet stored, the locals frame, the pasted calls still open, the
clock still ahead) is a `BlockState`, `self.blk`, made fresh for each
path; a Python while's is a `LoopState`, `self.lp` (compile_loops.py).
A store that hits compiled code may change the very code being run: the
line after it checks (`statement`, compiler.py's `stale_check`).
"""
import ast

from rcl.forth.inner import RSTACK_CELLS
from rcl.forth.control import INDEX, LIMIT, frame_cell, index_of
from rcl.forth.decode import stack_need
from rcl.forth.memory import MASK

# A DO loop run as a Python while keeps its frame's index' and limit' in
# _i and _lim (compile_loops.py): these lines move them, I is computed so.
LOAD_FRAME = "_lim = %s; _i = %s" % (frame_cell(LIMIT), frame_cell(INDEX))
STORE_INDEX = "%s = _i" % frame_cell(INDEX)
LOAD_INDEX = "_i = %s" % frame_cell(INDEX)
I_LOCAL = index_of("_i", "_lim")

# An RCL literal typed beyond a signed cell: DPL -1 and WIDE-NUMBER on.
WIDE_DPL = "wide"


def forth_of(m, ins):
    """The Forth an instruction came from, as a comment shows it: a
    number for a literal, a word's name for a call, the primitive's name."""
    return ins.kind.forth(m, ins)


def watch_test(line):
    """(test, call) for a template line `if test: m.watched(a)`, else None."""
    try:
        tree = ast.parse(line.strip())
    except SyntaxError:
        return None
    node = tree.body[0] if len(tree.body) == 1 else None
    if not isinstance(node, ast.If) or node.orelse or len(node.body) != 1:
        return None
    call = node.body[0]
    if not (isinstance(call, ast.Expr) and isinstance(call.value, ast.Call)
            and ast.unparse(call.value.func) == "m.watched"):
        return None
    text = line.strip()
    return ast.get_source_segment(text, node.test), ast.get_source_segment(text, call)


class BlockState:
    """What the code generator knows on one path through a block (its fast
    path, or the terminator after its slow path): made fresh for each."""
    __slots__ = ("vs", "dpl", "index_atom", "rest", "rs_known", "rs_pending", "open_calls",
                 "rs_unknown", "last_pop", "open_rets", "inlined", "at_next", "docol_checked",
                 "later")

    def __init__(self, vs=(), rest=0, index_atom=None, docol_checked=False):
        self.vs = list(vs)           # atoms standing for the top data-stack cells
        self.dpl = None              # a literal's DPL not yet stored
        self.index_atom = index_atom  # the atom holding I, while the loop frame stays put
        self.rest = rest             # clock units clk holds beyond the primitive being emitted
        self.later = ()              # the block's instructions after that one
        self.rs_known = None         # atoms known to be the top return-stack cells (locals)
        self.rs_pending = None       # a line pushing them, not yet emitted (see forget_rs)
        self.open_calls = 0          # inlined calls entered and not left, in the fast path
        self.rs_unknown = False      # Python code ran in this block: see call_check
        self.last_pop = None         # (lines, index, temp, indent) of a pop flush may make a peek
        self.open_rets = []          # return addresses of the inlined calls entered
        self.inlined = []            # their call cells (the backtrace's note, compiler.INLINED)
        self.at_next = None          # where the instruction being written is followed
        self.docol_checked = docol_checked   # the block's check covered its call's (DOCOL)


class BlockGen:
    """Mixed into the compiler's Gen: the code of one block. The state of
    the path being written is `blk` (a BlockState); the function's own,
    about its temps, is here."""

    def __init__(self):
        self.blk = BlockState()
        self.fetched = {}        # temp -> the constant address `@` read it from (fetched_xt)
        self.flags = {}          # temp -> (lines, index, test) of a flag a comparison made
        self.handed = {}         # atom -> times take or flush handed it out

    # The Locals word set's compile hooks (rcl/words/localvars.py) read and
    # set these on the generator.
    vs = property(lambda self: self.blk.vs, lambda self, v: setattr(self.blk, "vs", v))
    rs_known = property(lambda self: self.blk.rs_known,
                        lambda self, v: setattr(self.blk, "rs_known", v))
    rs_pending = property(lambda self: self.blk.rs_pending,
                          lambda self, v: setattr(self.blk, "rs_pending", v))
    index_atom = property(lambda self: self.blk.index_atom,
                          lambda self, v: setattr(self.blk, "index_atom", v))

    # ------------------------------------------------- the data stack as atoms
    def take(self, n, ind):
        """n input atoms, deepest first, loading from the real stack."""
        if n == 0:
            return []
        have = self.blk.vs[-n:] if n <= len(self.blk.vs) else list(self.blk.vs)
        if have and have[0] == "_c":              # a loop's carried top of stack
            self.lp.carried_used = True
        del self.blk.vs[len(self.blk.vs) - len(have):]
        for a in have:
            self.handed[a] = self.handed.get(a, 0) + 1
        loaded = []
        for _ in range(n - len(have)):
            t = self.temp()
            self.emit("%s = s.pop()" % t, ind, "s")
            self.blk.last_pop = (self.lines, len(self.lines) - 1, t, ind)
            self.lp.real_stack = True
            loaded.insert(0, t)
        return loaded + have

    def saw_line(self, ind, uses):
        """(From emit.) A line that looks at the real stack, or one less
        indented than the last pop (another path), ends what flush may
        rewrite (`last_pop`)."""
        if self.blk.last_pop is not None and ("s" in uses or ind < self.blk.last_pop[3]):
            self.blk.last_pop = None

    def flush_dpl(self, ind):
        """An RCL literal's DPL (and WIDE-NUMBER) is stored only when a word
        that may read them comes next."""
        if self.blk.dpl is not None:
            wide = self.blk.dpl == WIDE_DPL
            if self.lp.dpl_guard:                     # compile_loops.py: steady_dpl
                self.emit("if _d:", ind)
                ind += 1
            for a, v, name in ((self.m.a_dpl, MASK if wide else self.blk.dpl & MASK, "DPL"),
                               (self.m.a_wide, MASK if wide else 0, "WIDE-NUMBER")):
                self.emit("mem[%d] = %d; mem[%d] = %d  # %s" % (a, v & 0xFF, a + 1, v >> 8, name),
                          ind, "mem")
            if self.lp.dpl_guard:
                self.emit("_d = 0", ind)
            self.blk.dpl = None

    def flush(self, ind, rewrite=True):
        """Write vs back. When the last line that touched the real stack
        was a pop on this path, that cell is still free: the pop becomes a
        peek (`t = s[-1]`) and the deepest atom goes into the cell
        (`s[-1] = x`, nothing when it is t) instead of a pop and a push.
        rewrite=False: a flush on a side path only (call_check)."""
        self.flush_dpl(ind)
        last, self.blk.last_pop = self.blk.last_pop, None
        for a in self.blk.vs:
            self.handed[a] = self.handed.get(a, 0) + 1
        if self.lp.carrying:                          # inside a loop of several blocks
            return self.carry_out(ind)             # (compile_loops.py)
        if self.blk.vs:
            self.lp.real_stack = True
        if rewrite and last is not None and last[3] == ind and self.blk.vs:
            lines, i, t, at = last
            note = lines[i].partition("  # ")[1:]       # (an inlined call's note stays)
            lines[i] = "    " * at + "%s = s[-1]" % t + "".join(note)
            if self.blk.vs[0] != t:
                self.emit("s[-1] = %s" % self.blk.vs[0], ind, "s")
            del self.blk.vs[0]
        if len(self.blk.vs) == 1:
            self.emit("s.append(%s)" % self.blk.vs[0], ind, "s")
        elif self.blk.vs:
            self.emit("s.extend((%s))" % ", ".join(self.blk.vs), ind, "s")
        self.blk.vs = []

    # --------------------------------------------------------- simple ops
    def op_inline(self, p, ind, tpl=None):
        """Paste p's parsed template (or tpl, one made from a literal's
        inline cells): inputs taken as atoms, outputs kept as atoms; an
        output over numbers only is computed now (folded)."""
        tpl = tpl or p.template
        if p.name == "I" and self.blk.index_atom is not None:   # I again: the same value
            self.blk.vs.append(self.blk.index_atom)
            return
        if self.lp.in_loop and p.name == "I":       # the index is in locals (compile_loops.py)
            t = self.temp()
            self.emit("%s = %s" % (t, I_LOCAL), ind)
            self.blk.vs.append(t)
            self.blk.index_atom = t
            return
        if "rs" in tpl.uses and p.name not in ("I", "J"):
            self.blk.index_atom = None               # the loop frame may have moved
        if p.touches_memory:
            self.flush_dpl(ind)
        atoms = self.take(len(tpl.inputs), ind)
        if tpl.stmt:
            self.statement(tpl.stmt, atoms, ind)
            if self.lp.dpl_guard and "W" in tpl.stmt.uses:     # a store: see compile_loops.py
                self.dpl_overwritten(atoms[-1], ind)
        numbers = tpl.stmt is None and all(a.isdigit() for a in atoms)
        for o in tpl.outputs:
            if o.input is not None:
                self.blk.vs.append(atoms[o.input])
            elif numbers and o.fold is not None:
                self.blk.vs.append(str(o.fold(*map(int, atoms))))
            else:
                t = self.temp()
                self.emit("%s = %s" % (t, o.fill(atoms)), ind, *o.uses)
                self.blk.vs.append(t)
                if p.name == "@" and atoms[0].isdigit():
                    self.fetched[t] = int(atoms[0])
                if o.test is not None:
                    self.flags[t] = (self.lines, len(self.lines) - 1, o.test.fill(atoms))
        if p.name == "I":
            self.blk.index_atom = self.blk.vs[-1]

    def statement(self, stmt, atoms, ind):
        """A template's statement. A store that hits watched memory calls
        m.watched, which may drop this very function's code: then the
        reference loop goes on after the store (stale_check). A statement
        whose one such call ends it has the check inside that `if`, where
        nothing is spent unless the store hit; any other, after it."""
        lines = stmt.fill(atoms).split("\n")
        watch = [watch_test(line) for line in lines]
        found = [w for w in watch if w is not None]
        for n, (line, w) in enumerate(zip(lines, watch)):
            if w is not None and len(found) == 1 and n == len(lines) - 1 \
                    and self.blk.at_next is not None:
                self.emit("if %s:" % w[0], ind, *stmt.uses)
                self.emit(w[1], ind + 1)
                self.stale_check_mid(ind + 1)
            else:
                self.emit(line, ind, *stmt.uses)
        if found and (len(found) > 1 or watch[-1] is None) and self.blk.at_next is not None:
            self.stale_check_mid(ind)

    def stale_check_mid(self, ind):
        """stale_check in the middle of a block's fast path, clk holding
        the whole block's cost: m.clock gets what the reference loop would
        show after this primitive."""
        clock = "m.clock = clk - %d; clk = -1; " % self.blk.rest if self.blk.rest else "m.clock = clk; clk = -1; "
        self.stale_check(self.blk.at_next, ind, clock)

    def op_simple(self, ins, ind):
        """One instruction of a block's fast path: what its kind writes
        (compile_kinds.py), after what it needs of the return stack."""
        self.blk.at_next = ins.next
        p, kind = ins.prim, ins.kind
        # A word set may compile its own primitive (the Locals word set keeps
        # a frame's cells in Python locals: rcl/words/localvars.py); -> True if done.
        hook = p.extra.get("compile") if p is not None else None
        if hook is not None and hook(self, ins.args, ind):
            return
        tpl = kind.template(ins)
        if not kind.keeps_rs(ins, tpl):
            self.forget_rs(ind)
        if kind.rs_growth(ins) is None:
            self.blk.rs_unknown = True
        kind.fast(self, ins, tpl, ind)

    def python_call(self, call, ins, ind):
        """A primitive run as Python (the statement `call`) in the middle of
        a block: the stack written back, the clock handed over, and a check
        that it did not change the code being run."""
        self.flush(ind)
        self.blk.index_atom = None               # Python code may move the loop frame
        self.clock_out(ind)
        self.emit(call, ind)
        self.stale_check(ins.next, ind)
        need = stack_need(self.blk.later)
        if need:                # the rest of the block too short now: the reference loop
            self.stale_check(ins.next, ind, cond="len(s) < %d" % need)   # fails where it does
        self.clock_in(ind)

    def truth(self, f):
        """A Python expression true when flag atom f is not 0. When f is a
        comparison's flag that nothing else uses, its line goes and the
        expression is the comparison itself (`t3 = 0xFFFF if X else 0` is
        never made; the atoms X names are values, so X may move down)."""
        made = self.flags.get(f)
        if made is None or self.handed.get(f) != 1:
            return f
        lines, i, test = made
        lines[i] = None                          # (build drops it)
        return "(%s)" % test

    def branch_test(self, f):
        """The condition under which ?BRANCH on flag atom f jumps (f is 0):
        `if t3 == 0:`, or for a comparison's flag `if not (X):`."""
        t = self.truth(f)
        return "%s == 0" % f if t == f else "not " + t

    def fetched_xt(self, x):
        """What the cell atom x was fetched from holds now (`VEC @ EXECUTE`:
        the xt it will most likely hold when the code runs), or None."""
        a = self.fetched.get(x)
        return None if a is None else self.m.memory.fetch(a)

    def slow_entry(self, ins):
        """(cost, fn, args, at, after) for the slow path (compiler.slow):
        after, where to go on if the primitive may change code, else None."""
        kind = ins.kind
        after = ins.next if kind.may_store(ins) else None
        fn, args = kind.slow(ins)
        return (ins.cost, fn, args, ins.addr, after)

    # ------------------------------------------------------ the clock mid-block
    def clock_out(self, ind):
        """Before Python that may read or move the clock: m.clock is the
        truth until clock_in (clk = -1 tells the function's finally so).
        In the middle of a block, clk already holds the whole block's cost:
        m.clock gets what the reference loop would show (`rest` is the cost
        of the primitives after this one)."""
        self.emit("m.clock = clk - %d; clk = -1" % self.blk.rest if self.blk.rest
                  else "m.clock = clk; clk = -1", ind)

    def clock_in(self, ind):
        self.emit("clk = m.clock + %d" % self.blk.rest if self.blk.rest else "clk = m.clock", ind)

    # -------------------------------------------------------- the return stack
    def call_check(self, ind):
        """An inlined call after Python code that may have moved the return
        stack: overflow here if the real call would, counting what the fast
        path never pushes (the open calls' return addresses, a frame kept
        in Python names), with the data stack and clock the reference has."""
        unseen = self.blk.open_calls + (len(self.blk.rs_known) if self.blk.rs_pending else 0)
        self.emit("if len(rs) > %d:" % (RSTACK_CELLS - unseen), ind, "rs")
        vs, dpl = list(self.blk.vs), self.blk.dpl
        self.flush(ind + 1, rewrite=False)
        self.blk.vs, self.blk.dpl = vs, dpl
        self.clock_out(ind + 1)
        self.emit("m.rs_overflow()", ind + 1)

    def forget_rs(self, ind):
        """Something may look at the return stack: lay down any cells kept
        back (a locals frame whose reads all came from Python names so far)."""
        if self.blk.rs_pending:
            self.emit(self.blk.rs_pending, ind, "rs")
            self.blk.index_atom = None               # the frame is above the loop's now
        self.blk.rs_known = self.blk.rs_pending = None

