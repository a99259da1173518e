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
        s = m.s; rs = m.rs; clk = m.clock   # only the locals the code uses
        try:
            b = 0
            while True:
                if b <= 0:   # 198F  1- DUP 0= ?BRANCH      (block 0, the Forth it runs)
                    if clk + 3000000 >= m.deadline or not s:
                        m.clock = clk; clk = -1
                        _r = slow(m, G, SEQ0)    # exact: a primitive at a time
                        if _r is not None: return _r   # (the code changed: see below)
                        clk = m.clock
                        t1 = s.pop()
                        if t1 == 0: b = 0; continue
                    else:
                        clk += 4000000       # the whole block's cost at once
                        t2 = s[-1]
                        t3 = (t2 - 1) & 0xFFFF
                        s[-1] = t3
                        if not (t3 == 0): b = 0; continue   # 0= UNTIL: one test
                if b <= 1:   # 1999  EXIT
                    if clk + 0 >= m.deadline:
                        ...                  # the slow path, as above
                    else:
                        clk += 1000000
                        return rs.pop()
                raise RuntimeError('compiled code ran past its last block')
        finally:
            if clk >= 0: m.clock = clk

   `Gen.build` cuts the code into blocks and writes the guards; `Gen.block`
   writes each block's two ways (the slow path, then the fast one);
   `terminator` its end. The fast path's primitives come from
   compile_block.py (`op_simple`), the straight-line half of the compiler.
   (DUP became a peek, `t2 = s[-1]`, and the flag of 0= is never made:
   the branch tests the comparison; compile_block.py says when.)

The clock lives in `clk`, a local; before any Python that may read or move
the clock, m.clock gets it back and `clk = -1` tells the `finally` that
m.clock is now the truth (`clock_out`, `clock_in`).

A fast path charges its block's whole cost at once, so a primitive that
failed in the middle (a pop from an empty stack) would leave the clock
ahead of the reference loop's. A block that takes cells from below its
start checks the stack's depth with the deadline (`or len(s) < 2`,
`need_check`): too short, the slow path runs it and fails where the
reference loop does. (Python's line numbers cannot say which primitive
failed: PyPy 7.3 reports lines a function does not have.)

The clever part, explained once (compile_block.py has the details): inside
a block the data stack is kept in Python locals (`vs`, a list of names or
constants standing for the top cells); only at a block's end, or before
anything that looks at the real stack, are they written back. Simple
primitives are pasted from their inline templates (primitives.Template,
parsed once at registration), and an output over constants is computed at
compile time (`2 3 +` is `5`).

Jumps: the guard `if b <= k` lets a block fall into the next one with one
comparison. A forward jump only sets b and falls down through the guards
(each fails until block b's); a backward jump sets b and goes round the
`while`. In a long definition the guards are grouped by 32 (more when a
DO loop's `while` would straddle two groups), so a jump passes at most a
guard per group and those within its group.

Exactness: a block runs fast only if no interrupt or housekeeping falls due
before its last primitive; otherwise `slow` runs it one primitive at a
time, checking before each, so interrupts fire between exactly the same
primitives as in the reference loop (a Ctrl-C sets the deadline to -1, so
the next block takes the slow path and stops at its first primitive).

Calls: a colon word's function is called as Python (return address pushed
on the real return stack, checked against what EXIT returns: see inner.py).
EXECUTE of an xt read from a cell (`VEC @ EXECUTE`) or a DEFER first
compares the xt with the colon word the cell held at compile time and
calls that body's function directly while it stands (`dynamic_call`); any
other xt goes through m.call. A small straight colon word is not called
at all: decode.py pastes its primitives into the caller's block, between
an "enter" and an "exit" that cost what the call and its EXIT cost. A DO
loop becomes a Python `while` with the index, the clock and the stack
cells it works on in locals, when its body is one block or several whose
jumps stay inside it, its IF ... THEN and BEGIN loops written as Python
`if` and `while` (compile_loops.py).

Locals (rcl/words/localvars.py) use the same idea for the return stack: a
frame's cells stay Python names (`rs_known`), the frame pushed only before
something that may look at the return stack (`forget_rs`, compile_block.py).

Memory stays the truth: every byte a compiled function rests on is marked
in `watch` (compile_deps.py says which); a store there drops just the
functions resting on it (the next call compiles them again). One of them
still running finds its STALE flag set after the store, call or slow path
that made it, and goes on in the reference loop from the next primitive,
with what it kept in Python names put where the reference keeps it
(`stale_check`, `resume`): run_from reads every cell as it goes, so the
change is seen exactly where the reference loop sees it.
"""
import types

from rcl.errors import ForthError
from rcl.forth.memory import MASK, PRIM_LIMIT
from rcl.forth.primitives import CALL, HELPERS, LITERAL, REGISTRY, RUNTIME, SIMPLE
from rcl.forth.compile_block import (WIDE_DPL, BlockGen, BlockState,  # noqa: F401 (WIDE_DPL:
                                     forth_of)                          # core.py)
from rcl.forth.compile_loops import LoopGen, LoopState
from rcl.forth.control import BY_NAME as CONTROL_OPS, INDEX
from rcl.forth.decode import (NO_TERMINATOR, TooLarge, call_depth, decode, stack_need,  # noqa: F401
                              walk)
from rcl.forth.inner import (COMPILED, CONTROL_BY_CF, N, RSTACK_CELLS,  # (decode: for SEE)
                             decode_args)

DOCOL_N = N["(DOCOL)"]

INLINED = "# inlined: "       # a compiled line's note of the inlined calls it runs in
GROUP = 32                   # blocks per group of guards in a long definition


def slow(m, env, seq):
    """Run a block's primitives one by one (seq: (cost, fn, args, at,
    after) each, the last maybe the terminator's turn: its cost counted,
    its work done by the compiled code after). -> None; or, when the code
    changed under the running function (env's STALE: a store it made, or
    an interrupt handler's), the reference loop runs on (from `after`, a
    primitive that may store; or from `at`, whose boundary's check ran a
    handler) and -> what it returns, for the function to return."""
    for cost, fn, args, at, after in seq:
        if m.clock >= m.deadline:
            m.housekeep()
            if env["STALE"]:
                return m.run_from(checked_step(m, at))
        m.clock += cost
        fn(m, *args)
        if after is not None and env["STALE"]:
            return m.run_from(after)
    return None


def checked_step(m, ip):
    """Run the cell at ip as run_from does, its boundary's check already
    made (a second could take a second interrupt where the reference loop
    takes one, when a handler runs longer than its period); -> next ip."""
    mem = m.mem
    xt = mem[ip] | (mem[(ip + 1) & MASK] << 8)
    ip = (ip + 2) & MASK
    cf = mem[xt] | (mem[(xt + 1) & MASK] << 8)
    op = CONTROL_BY_CF.get(cf)
    if op is not None:
        m.clock += m.cost[cf]
        return op.run(m, ip)
    p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
    if p is not None and p.kind is LITERAL:
        m.clock += m.cost[cf]
        args, ip = decode_args(m, p, ip)
        p.fn(m, *args)
        return ip
    # m.call without its check: what run_from does for any other cell
    if cf >= PRIM_LIMIT:                       # a DOES> child
        m.clock += m.cost[DOCOL_N]
        m.s.append((xt + 2) & MASK)
        return m.enter(cf, ip)
    if p is None:
        raise ForthError(-260)
    m.clock += m.cost[cf]
    if p.kind is RUNTIME:
        return p.fn(m, xt, ip)
    if p.kind is SIMPLE or p.kind is CALL:
        p.fn(m)
        return ip
    if p.name == "EXECUTE":
        return m.call(m.s.pop(), ip)
    raise ForthError(-14, "Compile only", p.name)


def counted(m):
    """A terminator's turn in `slow`: its time counted, its work done by
    the compiled code that follows (a block that runs into the next, or a
    call that checks itself, has no turn: a second check at the same
    boundary could take a second interrupt there, where the reference loop
    takes one)."""


def resume(m, ip, cells=(), index=None, rs_cells=()):
    """Code changed under a running function in the middle of a block: the
    cells it kept in Python names go where the reference loop keeps them
    (cells on the data stack; index, a DO loop's index', into the loop
    frame; rs_cells, a locals frame and the return addresses of the calls
    pasted into the block, on the return stack), and the reference loop
    runs on from ip (-> what its EXIT returns, as a call's function does)."""
    if index is not None:
        m.rs[INDEX] = index
    m.rs.extend(rs_cells)
    m.s.extend(cells)
    return m.run_from(ip)


# The locals a compiled function may bind, in order, and what they hold.
PROLOGUE = (("s", "m.s"), ("rs", "m.rs"), ("mem", "m.mem"), ("W", "m.watch"), ("d0", "len(rs)"))


class Gen(BlockGen, LoopGen):
    """Python source for one definition."""

    def __init__(self, m, entry):
        BlockGen.__init__(self)
        self.m = m
        self.entry = entry
        self.lines = []
        self.consts = {}
        self.ntemp = 0
        self.uses = set()
        self.extra_marks = set()     # watched cells no instruction covers (dynamic_call)
        self.inner = set()           # blocks inside a loop's while: no way in for LEAVE
        self.lp = LoopState()        # (not in a loop)

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
        self.saw_line(ind, uses)
        if self.blk.inlined:             # for a backtrace (wordloc.py): the calls pasted here
            line += "  %s%s" % (INLINED, " ".join(map(str, self.blk.inlined)))
        self.lines.append("    " * ind + line)
        self.uses.update(uses)

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

    def call_tail(self, ins, k, ind):
        """After a call (clk -1, m.clock the truth): a return address the
        callee changed is returned in turn (inner.py); code changed under
        this function runs on in the reference loop; else on at ins.next."""
        ret = ins.next
        self.emit("if r != %d: return r" % ret, ind)
        self.stale_check(ret, ind)
        self.clock_in(ind)
        self.goto_next(k, ret, ind)

    def stale_check(self, ip, ind, clock="", cond="STALE"):
        """After Python code that may have changed the code this function
        was made from (a store, a call, an interrupt handler): if it did,
        the reference loop goes on at ip, the next primitive, as it would
        have run it. Here m.clock is the truth, and whatever the function
        keeps in Python names (a block's stack cells, a loop's index, a
        locals frame, the return addresses of pasted calls) goes where the
        reference loop keeps it first (`resume`). clock: the statement
        that makes m.clock the truth, if clk still is."""
        cells = list(self.blk.vs)
        for a in cells:                        # (a flag handed on is made)
            self.handed[a] = self.handed.get(a, 0) + 1
        rs_cells = list(self.blk.rs_known or ()) if self.blk.rs_pending else []
        rs_cells += self.blk.open_rets
        index = "_i" if self.lp.index_in_locals else None
        if self.blk.dpl is not None:               # (none is pending where checks are made)
            raise AssertionError("a DPL pending at a stale check")
        if not (cells or rs_cells or index):
            self.emit("if %s: %sreturn m.run_from(%d)" % (cond, clock, ip), ind)
            return
        args = [str(ip), "(%s)" % "".join(a + ", " for a in cells).rstrip(" ")]
        if index or rs_cells:
            args.append(index or "None")
        if rs_cells:
            args.append("(%s)" % "".join(a + ", " for a in rs_cells).rstrip(" "))
        self.emit("if %s: %sreturn RESUME(m, %s)" % (cond, clock, ", ".join(args)), ind)

    def terminator(self, ins, k, ind):
        """The code that ends block k: a control operation (control.py) or
        a call, as its kind writes it (compile_kinds.py)."""
        self.forget_rs(ind)
        ins.kind.end(self, ins, k, ind)

    def dynamic_call(self, x, ret, ind, guess=None):
        """Call the xt in x: straight into a colon word's compiled code when
        no interrupt is due at its (DOCOL), else through m.call (which does
        it all). guess: the xt x held when this was compiled (a DEFER's, or
        the cell `@` read); if that is a colon word, x is compared with it
        first and its body called by number (its code field is watched)."""
        docol = self.m.cost[DOCOL_N]
        due = "" if self.blk.docol_checked else " and clk < m.deadline"
        colon = "mem[%s] == %d and mem[(%s + 1) & 0xFFFF] == 0%s" % (x, DOCOL_N, x, due)
        if guess is not None and self.m.memory.fetch(guess) == DOCOL_N:
            # (FN has the body only while compiled code stands: once a store
            # into the guessed word threw it away, the general way runs)
            self.extra_marks.update((guess, (guess + 1) & MASK))
            body = (guess + 2) & MASK
            self.emit("_f = FN(%d) if %s == %d else None" % (body, x, guess), ind)
            self.emit("if _f is not None%s:" % due, ind)
            self.enter_call(None, ret, ind + 1, docol)
            self.emit("elif %s:" % colon, ind, "mem")
        else:
            self.emit("if %s:" % colon, ind, "mem")
        self.emit("_a = (%s + 2) & 0xFFFF" % x, ind + 1)
        self.enter_call("_a", ret, ind + 1, docol)
        self.emit("else:", ind)
        self.clock_out(ind + 1)
        self.emit("r = m.call(%s, %d)" % (x, ret), ind + 1)

    def enter_call(self, a, ret, ind, docol=0):
        """Call the compiled body at a (None: the function in _f) as a colon
        word returning to ret, after docol more clock units (a (DOCOL) not
        counted in the block)."""
        self.emit("rs.append(%d)" % ret, ind, "rs")
        if docol:
            self.emit("m.clock = clk + %d; clk = -1" % docol, ind)
        else:
            self.clock_out(ind)
        self.emit("if len(rs) > %d: m.rs_overflow()" % RSTACK_CELLS, ind)
        self.emit("r = _f(m)" if a is None else "r = (FN(%s) or CP(%s))(m)" % (a, a), ind)

    # ---------------------------------------------------------- assembly
    def block(self, k, ops, term, ind):
        pre = sum(i.cost for i in ops)
        term = term or NO_TERMINATOR
        # What goes through m.call(xt) (a bad xt, a vocabulary) is costed there;
        # everything else, DEFER included, costs its own cell here.
        tcost = term.cost if term.kind.costed else 0
        # EXECUTE and DEFER call at the boundary after their own cell, the
        # callee's (DOCOL): the fast path checks that one too, at the start
        # (the deadline moves only in Python code, which ends a block).
        docol = term.kind.checks_docol
        ahead = tcost if docol else 0
        self.emit("if clk + %d >= m.deadline%s%s:" % (pre + ahead, self.depth_check(ops),
                                                      self.need_check(ops)), ind)
        self.clock_out(ind + 1)
        self.slow_path(ops, term if term.kind.costed else None, tcost, ind + 1)
        self.clock_in(ind + 1)
        self.blk = BlockState()
        self.terminator(term, k, ind + 1)
        self.emit("else:", ind)
        self.blk = BlockState(docol_checked=docol)
        self.fast_ops(ops, pre + tcost, ind + 1)
        self.terminator(term, k, ind + 1)
        self.blk = BlockState()

    def slow_path(self, ops, term, tcost, ind):
        """`slow` runs the block's primitives one at a time, then term's
        turn (its cost tcost; None: no turn); if the code changed under
        the function meanwhile, the reference loop goes on where slow says."""
        entries = [self.slow_entry(i) for i in ops]
        if term is not None:
            entries.append((tcost, counted, (), term.addr, None))
        self.emit("_r = slow(m, G, %s)" % self.const(tuple(entries), "SEQ"), ind)
        self.emit("if _r is not None: return _r", ind)

    def fast_ops(self, ops, cost, ind):
        """The fast path's body: the block's whole cost at once, then its
        primitives pasted (op_simple), `rest` the cost still ahead of each."""
        self.emit("clk += %d" % cost, ind)
        self.blk.rest = cost
        for n, i in enumerate(ops):
            self.blk.rest -= i.cost
            self.blk.later = ops[n + 1:]
            self.op_simple(i, ind)
        self.blk.rest = 0

    def need_check(self, ops, kept=0):
        """For a block that takes cells from below its start: the condition
        under which the data stack is too short for it (then the slow path
        runs, and fails exactly where the reference loop does). kept: cells
        of the stack the code holds in Python names instead."""
        need = stack_need(ops) - kept
        if need <= 0:
            return ""
        self.uses.add("s")
        return " or not s" if need == 1 else " or len(s) < %d" % need   # (not s: no call)

    def depth_check(self, ops):
        """For a block with inlined calls: the condition under which one of
        them would overflow the return stack (then the slow path runs, and
        overflows exactly where the real call would)."""
        deepest = call_depth(ops)
        if deepest is None:
            return ""
        self.uses.add("rs")
        return " or len(rs) > %d" % (RSTACK_CELLS - deepest)

    @staticmethod
    def groups(n, regions):
        """{first block: last block} of each group of guards in a definition
        of n blocks, if it is long; a loop's while stays in one group."""
        if n <= GROUP:
            return {}
        out, k = {}, 0
        while k < n:
            end = min(k + GROUP, n) - 1
            for r in regions.values():
                if r.first <= end < r.last:
                    end = r.last
            out[k], k = end, end + 1
        return out

    def build(self):
        code, targets = walk(self.m, self.entry)
        starts = sorted(a for a in targets if a in code)
        self.index = {a: i for i, a in enumerate(starts)}
        self.emit("def f(m):", 0)
        self.emit("PROLOGUE", 1)
        self.emit("b = 0", 1)
        self.emit("while True:", 1)
        blocks, self.forth = [], {}
        for a in starts:
            ops, term, ip, words = [], None, a, []
            while True:
                ins = code[ip]
                words.append(forth_of(self.m, ins))
                if ins.kind.ends_block:
                    term = ins
                    break
                ops.extend(ins.kind.parts(ins))
                ip = ins.next
                if ip in self.index or ip not in code:
                    break
            self.forth[a] = " ".join(words)
            blocks.append((a, ops, term, ip if term is None else None))
        regions = self.find_regions(blocks)
        groups = self.groups(len(blocks), regions)
        skip = -1                            # blocks up to here went into a region's while
        for k, (a, ops, term, self.next_addr) in enumerate(blocks):
            ind = 2
            if groups:                       # a jump passes a guard per group, then per block
                if k in groups:
                    self.emit("if b <= %d:" % groups[k], 2)
                ind = 3
            if k <= skip:
                continue
            self.emit("if b <= %d:   # %04X  %s" % (k, a, self.forth[a]), ind)
            if k in regions:
                self.region_loop(regions[k], blocks, ind + 1)
                skip = regions[k].last
            elif self.loopable(ops, term, a):
                self.loop_block(k, ops, term, ind + 1)
            else:
                self.block(k, ops, term, ind + 1)
        # Every block ends in a return or a jump, or runs into the next one.
        self.emit("raise RuntimeError('compiled code ran past its last block')", 2)
        self.lines = [line for line in self.lines if line is not None]   # (truth() drops a flag)
        if "d0" in self.uses:
            self.uses.add("rs")
        self.lines[1] = "    " + "; ".join(["%s = %s" % (n, v) for n, v in PROLOGUE
                                                if n in self.uses] + ["clk = m.clock"])
        # The clock lives in clk; whatever way the function is left, m.clock
        # gets it back (unless a call or the slow path made m.clock the truth).
        self.lines[2:] = ["    try:"] + ["    " + line for line in self.lines[2:]] + [
            "    finally:", "        if clk >= 0: m.clock = clk"]
        marks = set(self.extra_marks)
        for ins in code.values():
            for i in {ins, *ins.kind.parts(ins)}:       # (an inlined call: its callee's too)
                span = (i.next - i.addr) & MASK or 2      # (code may wrap round
                marks.update((i.addr + j) & MASK for j in range(span))   # memory's end)
                marks.update((i.xt, (i.xt + 1) & MASK))
                marks.update(i.kind.watched(i))
        return "\n".join(self.lines), marks


# Python's own compiler takes about 90 bytes of memory a character: the
# largest word of the system is some 20 KB of Python; a wild EXECUTE into
# data once made 14 MB of it and took 1.2 GB and 20 s. Past this the
# reference loop runs the code, with the same outcome.
SOURCE_LIMIT = 2_000_000


def compile_code(m, entry):
    """Compile the threaded code at entry; returns the Python function."""
    gen = Gen(m, entry)
    src, marks = gen.build()
    if len(src) > SOURCE_LIMIT:
        raise TooLarge("code at %d would be %d characters of Python" % (entry, len(src)))
    env = types.ModuleType(COMPILED).__dict__   # (PyPy's JIT reads a module's
    env.update(gen.consts)                      # globals as constants, a dict's not)
    env.update(HELPERS)
    env.update(slow=slow, RESUME=resume, STALE=False, G=env,
               FN=m.fn.get, CP=m.compile,
               BMAP={a: k for a, k in gen.index.items() if a not in gen.inner})
    exec(compile(src, COMPILED, "exec"), env)
    f = env["f"]
    f.source = src
    f.marks = marks                  # the bytes it rests on (compile_deps.py)
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
    text = getattr(f, "source", None) or compile_code(m, addr).source
    return "\n".join(line.split("  " + INLINED)[0] for line in text.split("\n"))
