"""Threaded code compiled to Python: the fast path of the inner interpreter.

Follow one colon definition from source to what runs (the tour takes a
few minutes with a machine at hand):

    >>> m = rcl.Forth()
    >>> m.evaluate(": COUNTDOWN  BEGIN 1- DUP 0= UNTIL ;")
    >>> print(rcl.forth.compiler.source(m, "COUNTDOWN"))

1. The outer interpreter (outer.py) lays down threaded code, one cell per
   word: | 1- | DUP | 0= | ?BRANCH | target | EXIT |.
2. The first call of COUNTDOWN (Inner.enter) finds no compiled function
   for its body and calls `compile_code`: `walk` decodes every reachable
   cell into an `Instr` and notes where blocks start (entry, branch targets,
   the cell after a call); `Gen.build` writes one Python function.
3. A block is a straight run of simple primitives ended by a terminator:
   a control operation (control.py: each has its reference function, used
   by run_from, next to its code generator) or a call. What it prints:

    def f(m):
        s = m.s; rs = m.rs                  # only the locals the code uses
        b = 0
        while True:
            if b <= 0:   # 145A              # block 0: 1- DUP 0= ?BRANCH
                if m.clock + 3000000 >= m.deadline:
                    slow(m, SEQ0, 1000000)   # exact: one primitive at a time
                    t1 = s.pop()
                    if t1 == 0: b = 0; continue
                else:
                    m.clock += 4000000       # the whole block's cost at once
                    t2 = s.pop()
                    t3 = (t2 - 1) & 0xFFFF
                    t4 = 0xFFFF if t3 == 0 else 0
                    s.append(t3)
                    if t4 == 0: b = 0; continue
            if b <= 1:   # 1464              # block 1: EXIT
                ...
                return rs.pop()

The clever part, explained once: inside a block the data stack is kept in
Python locals (`vs`, a list of names or constants standing for the top
cells); only at a block's end, or before anything that looks at the real
stack, are they written back. Simple primitives are pasted from their
inline templates (primitives.Template, parsed once at registration), and
an output over constants is computed at compile time (`2 3 +` is `5`).

Jumps: the guard `if b <= k` lets a block fall into the next one with one
comparison. A forward jump only sets b and falls down through the guards
(each fails until block b's); a backward jump sets b and goes round the
`while`. In a long definition the guards are grouped by 32, so a jump
passes at most a guard per group and 32 within its group.

Exactness: a block runs fast only if no interrupt or housekeeping falls due
before its last primitive; otherwise `slow` runs it one primitive at a
time, checking before each, so interrupts fire between exactly the same
primitives as in the reference loop (a Ctrl-C sets the deadline to -1, so
the next block takes the slow path and stops at its first primitive).

Calls: a colon word's function is called as Python (return address pushed
on the real return stack, checked against what EXIT returns: see inner.py).
A small straight colon word is not called at all: decode.py pastes its
primitives into the caller's block, between an "enter" and an "exit" that
cost what the call and its EXIT cost. A DO loop whose body is one block
becomes a Python `while` with the index and the clock in locals
(compile_loops.py).

Locals (rcl/words/localvars.py) use the same idea for the return stack: a
frame's cells stay Python names (`rs_known`), the frame pushed only before
something that may look at the return stack (`forget_rs`).

Memory stays the truth: every cell the compiled code depends on is marked
in `watch`; a store there throws all compiled code away (it is rebuilt on
the next call). A definition already running finishes in its old form.
"""
from rcl.forth.memory import MASK, PRIM_LIMIT, WATCH_CODE
from rcl.forth.primitives import HELPERS
from rcl.forth.compile_loops import LoopGen
from rcl.forth.control import BY_NAME as CONTROL_OPS
from rcl.forth.decode import (NO_TERMINATOR, TERMINATORS, call_depth,  # noqa: F401
                              decode, keeps_rs, literal_template, rs_growth, rt_2con,
                              rt_con, rt_enter, rt_exit, walk)   # (decode: for SEE)
from rcl.forth.inner import COMPILED, N, RSTACK_CELLS, rt_push

DOCOL_N = N["(DOCOL)"]

GROUP = 32                   # blocks per group of guards in a long definition


def slow(m, seq, term_cost=None):
    """Run a block's primitives one by one, then account for its terminator
    (None: a block that runs into the next, or a call that checks itself:
    a second check at the same boundary could take a second interrupt
    there, where the reference loop takes one)."""
    for cost, fn, args in seq:
        if m.clock >= m.deadline:
            m.housekeep()
        m.clock += cost
        fn(m, *args)
    if term_cost is not None:
        if m.clock >= m.deadline:
            m.housekeep()
        m.clock += term_cost


# The locals a compiled function may bind, in order, and what they hold.
PROLOGUE = (("s", "m.s"), ("rs", "m.rs"), ("mem", "m.mem"), ("W", "m.watch"), ("d0", "len(rs)"))

# An RCL literal typed beyond a signed cell: DPL -1 and WIDE-NUMBER on.
WIDE_DPL = "wide"

class Gen(LoopGen):
    """Python source for one definition."""

    def __init__(self, m, entry):
        self.m = m
        self.entry = entry
        self.lines = []
        self.consts = {}
        self.ntemp = 0
        self.vs = []
        self.dpl = None
        self.uses = set()
        self.index_atom = None   # the temp holding I, while the loop frame stays put
        self.rest = 0            # clock units clk holds beyond the primitive being emitted
        self.rs_known = None     # atoms known to be the top return-stack cells (locals)
        self.rs_pending = None   # a line pushing them, not yet emitted (see forget_rs)
        self.open_calls = 0      # inlined calls entered and not left, in the fast path
        self.rs_unknown = False  # Python code ran in this block: see call_check

    # ------------------------------------------------------------ helpers
    def const(self, obj, hint="K"):
        name = "%s%d" % (hint, len(self.consts))
        self.consts[name] = obj
        return name

    def temp(self):
        self.ntemp += 1
        return "t%d" % self.ntemp

    def emit(self, line, ind, *uses):
        """Add a line; `uses` are the prologue's locals it names (s, rs,
        mem, W, d0), recorded so the prologue binds just those."""
        self.lines.append("    " * ind + line)
        self.uses.update(uses)

    def take(self, n, ind):
        """n input atoms, deepest first, loading from the real stack."""
        if n == 0:
            return []
        have = self.vs[-n:] if n <= len(self.vs) else list(self.vs)
        if have and have[0] == "_c":              # a loop's carried top of stack
            self.carried_used = True
        del self.vs[len(self.vs) - len(have):]
        loaded = []
        for _ in range(n - len(have)):
            t = self.temp()
            self.emit("%s = s.pop()" % t, ind, "s")
            self.real_stack = True
            loaded.insert(0, t)
        return loaded + have

    def flush_dpl(self, ind):
        """An RCL literal's DPL (and WIDE-NUMBER) is stored only when a word
        that may read them comes next."""
        if self.dpl is not None:
            wide = self.dpl == WIDE_DPL
            for a, v in ((self.m.a_dpl, MASK if wide else self.dpl & MASK),
                         (self.m.a_wide, MASK if wide else 0)):
                self.emit("mem[%d] = %d; mem[%d] = %d" % (a, v & 0xFF, a + 1, v >> 8), ind, "mem")
            self.dpl = None

    def flush(self, ind):
        self.flush_dpl(ind)
        if self.vs:
            self.real_stack = True
        if len(self.vs) == 1:
            self.emit("s.append(%s)" % self.vs[0], ind, "s")
        elif self.vs:
            self.emit("s.extend((%s))" % ", ".join(self.vs), ind, "s")
        self.vs = []

    # --------------------------------------------------------- simple ops
    def op_inline(self, p, ind, tpl=None):
        """Paste p's parsed template (or tpl, one made from a literal's
        inline cells): inputs taken as atoms, outputs kept as atoms; an
        output over numbers only is computed now (folded)."""
        tpl = tpl or p.template
        if p.name == "I" and self.index_atom is not None:   # I again: the same value
            self.vs.append(self.index_atom)
            return
        if self.in_loop and p.name == "I":       # the index is in locals (compile_loops.py)
            t = self.temp()
            self.emit("%s = (_i + _lim) & 0xFFFF" % t, ind)
            self.vs.append(t)
            self.index_atom = t
            return
        if "rs" in tpl.uses and p.name not in ("I", "J"):
            self.index_atom = None               # the loop frame may have moved
        if p.touches_memory:
            self.flush_dpl(ind)
        atoms = self.take(len(tpl.inputs), ind)
        if tpl.stmt:
            for line in tpl.stmt.fill(atoms).split("\n"):
                self.emit(line, ind, *tpl.stmt.uses)
        numbers = tpl.stmt is None and all(a.isdigit() for a in atoms)
        for o in tpl.outputs:
            if o.input is not None:
                self.vs.append(atoms[o.input])
            elif numbers and o.fold is not None:
                self.vs.append(str(o.fold(*map(int, atoms))))
            else:
                t = self.temp()
                self.emit("%s = %s" % (t, o.fill(atoms)), ind, *o.uses)
                self.vs.append(t)
        if p.name == "I":
            self.index_atom = self.vs[-1]

    def op_simple(self, ins, ind):
        p, op = ins.prim, ins.op
        # A word set may compile its own primitive (the Locals word set keeps
        # a frame's cells in Python locals: rcl/words/localvars.py); -> True if done.
        hook = p.extra.get("compile") if p is not None else None
        if hook is not None and hook(self, ins.args, ind):
            return
        tpl = literal_template(ins)
        if not keeps_rs(ins, tpl):
            self.forget_rs(ind)
        if rs_growth(ins) is None:
            self.rs_unknown = True
        if op == "enter":                          # an inlined call (decode.py): the
            self.open_calls += 1                   # block's check saw the depth it needs,
            if self.rs_unknown:                    # unless Python code ran before it
                self.call_check(ind)
        elif op == "exit":
            self.open_calls -= 1
        elif op == "literal":
            lit = p.extra.get("lit")
            if lit is not None:                    # numbers: pushed as constants
                cells, dpl = lit(ins.args)
                self.vs.extend(str(c) for c in cells)
                if dpl is not None:
                    self.dpl = dpl
                return
            if tpl is not None:                    # made from the inline cells
                self.op_inline(p, ind, tpl)
                return
            self.flush(ind)
            self.index_atom = None
            self.clock_out(ind)
            self.emit("%s(m, *%r)" % (self.const(p.fn, "P"), ins.args), ind)
            self.clock_in(ind)
        elif op == "var":
            self.vs.append(str(ins.args[0]))
        elif op == "const":                        # its cell is watched (decode.py)
            self.vs.append(str(self.m.memory.fetch(ins.args[0])))
        elif op in ("con", "2con"):
            self.flush_dpl(ind)
            a = ins.args[0]
            cell = "(mem[%d] | (mem[%d] << 8))"
            if op == "con":
                t = self.temp()
                self.emit("%s = %s" % (t, cell % (a, (a + 1) & MASK)), ind, "mem")
                self.vs.append(t)
            else:
                lo, hi = self.temp(), self.temp()
                self.emit("%s = %s" % (lo, cell % ((a + 2) & MASK, (a + 3) & MASK)), ind, "mem")
                self.emit("%s = %s" % (hi, cell % (a, (a + 1) & MASK)), ind)
                self.vs.extend((lo, hi))
        elif p.template is not None:
            self.op_inline(p, ind)
        else:
            self.flush(ind)
            self.index_atom = None               # Python code may move the loop frame
            self.clock_out(ind)
            self.emit("%s(m)" % self.const(p.fn, "P"), ind)
            self.clock_in(ind)

    def slow_entry(self, ins):
        """(cost, fn, args) for the slow path."""
        p, op = ins.prim, ins.op
        if op == "enter":
            return (ins.cost, rt_enter, ins.args)
        if op == "exit":
            return (ins.cost, rt_exit, ())
        if op == "literal":
            return (ins.cost, p.fn, ins.args)
        if op == "var":
            return (ins.cost, rt_push, ins.args)
        if op in ("con", "const"):
            return (ins.cost, rt_con, ins.args)
        if op == "2con":
            return (ins.cost, rt_2con, ins.args)
        return (ins.cost, p.fn, ())

    # --------------------------------------------------------- terminators
    def jump_text(self, addr, k):
        """The statement that goes on at addr from block k. A forward jump
        only sets b and falls down through the guards (each fails until
        block b's); a backward one must go round the loop."""
        j = self.index[addr]
        return "b = %d" % j if j > k else "b = %d; continue" % j

    def jump(self, addr, k, ind):
        self.emit(self.jump_text(addr, k), ind)

    def goto_next(self, k, addr, ind):
        """Continue at addr: fall into block k+1 or jump."""
        if self.index.get(addr) != k + 1:
            self.jump(addr, k, ind)

    def branch(self, cond, addr, k, nxt, ind, stmt=None, other=None):
        """If cond: stmt, go to addr; else: other, go on at nxt. A forward
        jump falls through the guards, so the other way must be an else."""
        taken = (stmt + "; " if stmt else "") + self.jump_text(addr, k)
        self.emit("if %s: %s" % (cond, taken), ind)
        rest = [other] if other else []
        if self.index.get(nxt) != k + 1:
            rest.append(self.jump_text(nxt, k))
        if rest and self.index[addr] > k:
            self.emit("else:", ind)
            ind += 1
        for line in rest:
            self.emit(line, ind)

    def clock_out(self, ind):
        """Before Python that may read or move the clock: m.clock is the
        truth until clock_in (clk = -1 tells the function's finally so).
        In the middle of a block, clk already holds the whole block's cost:
        m.clock gets what the reference loop would show (`rest` is the cost
        of the primitives after this one)."""
        self.emit("m.clock = clk - %d; clk = -1" % self.rest if self.rest
                  else "m.clock = clk; clk = -1", ind)

    def clock_in(self, ind):
        self.emit("clk = m.clock + %d" % self.rest if self.rest else "clk = m.clock", ind)

    def call_tail(self, ins, k, ind):
        ret = ins.next
        self.emit("if r != %d: return r" % ret, ind)
        self.goto_next(k, ret, ind)

    def call_check(self, ind):
        """An inlined call after Python code that may have moved the return
        stack: overflow here if the real call would, counting what the fast
        path never pushes (the open calls' return addresses, a frame kept
        in Python names), with the data stack and clock the reference has."""
        unseen = self.open_calls + (len(self.rs_known) if self.rs_pending else 0)
        self.emit("if len(rs) > %d:" % (RSTACK_CELLS - unseen), ind, "rs")
        vs, dpl = list(self.vs), self.dpl
        self.flush(ind + 1)
        self.vs, self.dpl = vs, dpl
        self.clock_out(ind + 1)
        self.emit("m.rs_overflow()", ind + 1)

    def forget_rs(self, ind):
        """Something may look at the return stack: lay down any cells kept
        back (a locals frame whose reads all came from Python names so far)."""
        if self.rs_pending:
            self.emit(self.rs_pending, ind, "rs")
            self.index_atom = None               # the frame is above the loop's now
        self.rs_known = self.rs_pending = None

    def terminator(self, ins, k, ind):
        """The code that ends block k: a control operation (control.py) or
        a call."""
        self.forget_rs(ind)
        op = CONTROL_OPS.get(ins.op)
        if op is not None:
            op.gen(self, ins, k, ind)
            return
        self.flush(ind)
        kind = ins.op
        if kind is None:                  # block ends where another begins
            self.goto_next(k, self.next_addr, ind)
        elif kind in ("colon", "does"):
            code = ins.args[0]                 # the body, or the code after DOES>
            if kind == "does":
                self.emit("s.append(%d)" % ((ins.xt + 2) & MASK), ind, "s")
            self.emit("rs.append(%d)" % ins.next, ind, "rs")
            self.clock_out(ind)
            self.emit("if len(rs) > %d: m.rs_overflow()" % RSTACK_CELLS, ind)
            self.emit("r = (FN(%d) or CP(%d))(m)" % (code, code), ind)
            self.clock_in(ind)
            self.call_tail(ins, k, ind)
        elif kind == "defer":
            body = ins.args[0]
            self.emit("_x = mem[%d] | (mem[%d] << 8)" % (body, (body + 1) & MASK), ind, "mem")
            self.dynamic_call("_x", ins.next, ind)
            self.call_tail(ins, k, ind)
        elif kind == "bad" or ins.prim.kind == "runtime":
            self.clock_out(ind)
            self.emit("r = m.call(%d, %d)" % (ins.xt, ins.next), ind)
            self.clock_in(ind)
            self.call_tail(ins, k, ind)
        else:                             # a primitive that may run Forth or move the clock
            self.clock_out(ind)
            self.emit("%s(m)" % self.const(ins.prim.fn, "P"), ind)
            self.clock_in(ind)
            self.goto_next(k, ins.next, ind)

    def dynamic_call(self, x, ret, ind):
        """Call the xt in x: straight into a colon word's compiled code when
        no interrupt is due, else through m.call (which does it all)."""
        self.emit("_a = (%s + 2) & 0xFFFF" % x, ind)
        self.clock_out(ind)
        self.emit("if mem[%s] == %d and mem[(%s + 1) & 0xFFFF] == 0 and m.clock < m.deadline:"
                  % (x, DOCOL_N, x), ind, "mem")
        self.emit("m.clock += %d; rs.append(%d)" % (self.m.cost[DOCOL_N], ret), ind + 1, "rs")
        self.emit("if len(rs) > %d: m.rs_overflow()" % RSTACK_CELLS, ind + 1)
        self.emit("r = (FN(_a) or CP(_a))(m)", ind + 1)
        self.emit("else: r = m.call(%s, %d)" % (x, ret), ind)
        self.clock_in(ind)

    # ---------------------------------------------------------- assembly
    def block(self, k, ops, term, ind):
        pre = sum(i.cost for i in ops)
        term = term or NO_TERMINATOR
        # What goes through m.call(xt) (a bad xt, a vocabulary) is costed there;
        # everything else, DEFER included, costs its own cell here.
        through_call = term.op == "bad" or (term.op == "call" and term.prim.kind == "runtime")
        tcost = 0 if term.op is None or through_call else term.cost
        seq = self.const(tuple(self.slow_entry(i) for i in ops), "SEQ")
        self.index_atom = None
        self.emit("if clk + %d >= m.deadline%s:" % (pre, self.depth_check(ops)), ind)
        self.clock_out(ind + 1)
        self.emit("slow(m, %s)" % seq if term.op is None or through_call
                  else "slow(m, %s, %d)" % (seq, tcost), ind + 1)
        self.clock_in(ind + 1)
        self.vs, self.dpl, self.rs_known = [], None, None
        self.terminator(term, k, ind + 1)
        self.emit("else:", ind)
        self.emit("clk += %d" % (pre + tcost), ind + 1)
        self.vs, self.dpl, self.index_atom, self.rs_known = [], None, None, None
        self.open_calls, self.rs_unknown = 0, False
        self.rest = pre + tcost
        for i in ops:
            self.rest -= i.cost
            self.op_simple(i, ind + 1)
        self.rest = 0
        self.terminator(term, k, ind + 1)

    def depth_check(self, ops):
        """For a block with inlined calls: the condition under which one of
        them would overflow the return stack (then the slow path runs, and
        overflows exactly where the real call would)."""
        deepest = call_depth(ops)
        if deepest is None:
            return ""
        self.uses.add("rs")
        return " or len(rs) > %d" % (RSTACK_CELLS - deepest)

    def build(self):
        code, targets = walk(self.m, self.entry)
        starts = sorted(a for a in targets if a in code)
        self.index = {a: i for i, a in enumerate(starts)}
        self.emit("def f(m):", 0)
        self.emit("PROLOGUE", 1)
        self.emit("b = 0", 1)
        self.emit("while True:", 1)
        for k, a in enumerate(starts):
            ops, term, ip = [], None, a
            while True:
                ins = code[ip]
                if ins.op in TERMINATORS:
                    term = ins
                    break
                ops.extend(ins.args[1] if ins.op == "inline" else (ins,))
                ip = ins.next
                if ip in self.index or ip not in code:
                    break
            self.next_addr = ip if term is None else None
            ind = 2
            if len(starts) > GROUP:          # a jump passes a guard per group, then per block
                if k % GROUP == 0:
                    self.emit("if b <= %d:" % min(k + GROUP - 1, len(starts) - 1), 2)
                ind = 3
            self.emit("if b <= %d:   # %04X" % (k, a), ind)
            if self.loopable(ops, term, a):
                self.loop_block(k, ops, term, ind + 1)
            else:
                self.block(k, ops, term, ind + 1)
        # Every block ends in a return or a jump, or runs into the next one.
        self.emit("raise RuntimeError('compiled code ran past its last block')", 2)
        if "d0" in self.uses:
            self.uses.add("rs")
        self.lines[1] = "    " + "; ".join(["%s = %s" % (n, v) for n, v in PROLOGUE
                                                if n in self.uses] + ["clk = m.clock"])
        # The clock lives in clk; whatever way the function is left, m.clock
        # gets it back (unless a call or the slow path made m.clock the truth).
        self.lines[2:] = ["    try:"] + ["    " + line for line in self.lines[2:]] + [
            "    finally:", "        if clk >= 0: m.clock = clk"]
        marks = set()
        for ins in code.values():
            for i in (ins.args[1] if ins.op == "inline" else ()) + (ins,):
                span = (i.next - i.addr) & MASK or 2      # (code may wrap round
                marks.update((i.addr + j) & MASK for j in range(span))   # memory's end)
                marks.update((i.xt, (i.xt + 1) & MASK))
                if i.op == "const":
                    marks.update((i.args[0], (i.args[0] + 1) & MASK))
        return "\n".join(self.lines), marks


def compile_code(m, entry):
    """Compile the threaded code at entry; returns the Python function."""
    gen = Gen(m, entry)
    src, marks = gen.build()
    env = dict(gen.consts)
    env.update(HELPERS)
    env.update(slow=slow, FN=m.fn.get, CP=m.compile, BMAP=gen.index)
    exec(compile(src, COMPILED, "exec"), env)
    for a in marks:
        m.watch[a] |= WATCH_CODE
    f = env["f"]
    f.source = src
    return f


def source(m, name):
    """The Python that machine m runs for the colon definition `name` (or
    for the code after DOES> of a word DOES> made): how to follow a word
    from its source to what runs. For example

        >>> m = rcl.Forth(); m.evaluate(": SQ  DUP * ;")
        >>> print(rcl.forth.compiler.source(m, "SQ"))
    """
    found = m.dictionary.find(name)
    if found is None:
        raise LookupError("%s is not defined" % name)
    xt = found[0]
    cf = m.memory.fetch(xt)
    if cf >= PRIM_LIMIT:
        addr = cf
    elif cf == DOCOL_N:
        addr = (xt + 2) & MASK
    else:
        raise ValueError("%s is a primitive, not threaded code" % name)
    f = m.fn.get(addr) or m.compile(addr)
    return getattr(f, "source", None) or compile_code(m, addr).source
