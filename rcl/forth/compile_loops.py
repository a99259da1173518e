"""DO loops compiled as Python `while` loops: the compiler's loop half.

A loop of one block
-------------------
A loop whose whole body is one block, ending in the (LOOP) or (+LOOP) that
jumps back to the block's own start, such as

    : SUM  0 100 0 DO  I +  LOOP ;

runs as one Python `while`, with the loop index and the limit in Python
locals beside the clock (`clk`, a local of every compiled function), and,
when the body leaves the stack as deep as it found it, the top of the data
stack too:

    _lim = rs[-2]; _i = rs[-1]
    if not s: ...                             # the reference loop runs it (as below)
    _c = s.pop()                              # the top of stack, carried
    while True:
        if clk + 2000000 >= m.deadline:       # the usual check, each iteration
            m.clock = clk; clk = -1; rs[-1] = _i; s.append(_c)
            _r = slow(m, G, SEQ1)             # exact: one primitive at a time
            if _r is not None: return _r      # (the code changed: compiler.py)
            clk = m.clock; _i = rs[-1]; _c = s.pop()
        else:
            clk += 3000000
            t3 = (_i + _lim) & 0xFFFF         # I
            t4 = (_c + t3) & 0xFFFF           # +
            _c = t4
        if _i != 32767: _i = (_i + 1) & 0xFFFF; continue
        break
    s.append(_c)
    del rs[-3:]

Each iteration checks the deadline exactly as the block would, so
interrupts (and a Ctrl-C, which sets the deadline to -1) are taken between
the same primitives as in the reference loop; before the slow path runs,
everything in locals is written back, so the primitives and any interrupt
handler see the real stacks and clock.

An RCL literal stores DPL (and WIDE-NUMBER) each time it runs. When the
body's literals store the same value each iteration (`steady_dpl`), an
iteration finds those cells already holding it unless the slow path ran
since (an interrupt handler may have changed them) or a store of the body
may have hit them (its address is checked against theirs,
`dpl_overwritten`): the fast path stores only while `_d` says so, the slow
path and such a store set `_d` again, and memory at every point is the
reference loop's:

    _d = 1                                    # before the loop
        ...                                   # (the slow path ends: _d = 1)
            if _d:
                mem[1030] = 255; mem[1031] = 255
                mem[1064] = 0; mem[1065] = 0
                _d = 0

Only bodies whose every primitive is known not to look at the loop frame
or the clock qualify: literals, variables, constants and inline templates
that touch the return stack only as I or J (`loop_op`).

A loop of several blocks
------------------------
A body with IF ... ELSE ... THEN or BEGIN ... UNTIL / WHILE ... REPEAT /
AGAIN inside, whose jumps stay inside it and whose stack is as deep at
each block whichever way it got there (loop_shape.py: `find_regions`),
is one `while` too, its blocks in the shape of the source:

    : ODDS  0 10 0 DO  I 1 AND IF  I +  THEN  LOOP ;

    _lim = rs[-2]; _i = rs[-1]
    if len(s) < 1:                            # too short: the reference loop runs it,
        ...                                   # m.run_from(the loop's first cell, d0)
    _k0 = s.pop()                             # the cells the body works on
    _I = (_i + _lim) & 0xFFFF                 # I, once an iteration
    _d = 1
    while True:
        _w = clk + 6000000 >= m.deadline      # may a check fall due before the next head?
        if _w and clk + 3000000 >= m.deadline:
            m.clock = clk; clk = -1; rs[-1] = _i; s.append(_k0)
            _r = slow(m, G, SEQ1)             # exact, as in any block
            if _r is not None: return _r
            ...                               # then _f and _k0 from the real stack
        else:
            clk += 4000000
            _f = _I & 1                       # I 1 AND: the flag ?BRANCH tests
            if _d:
                ...                           # the literal's DPL, as above
        if _f:                                # IF ... THEN
            if _w and clk + 2000000 >= m.deadline:
                ...
            else:
                clk += 2000000
                t7 = (_k0 + _I) & 0xFFFF      # I +
                _k0 = t7                      # handed on in a local, not on s
        if _w and clk + 0 >= m.deadline:
            ...
        else:
            clk += 1000000
            if _i != 32767: _i = (_i + 1) & 0xFFFF; _I = (_i + _lim) & 0xFFFF; continue
        break
    del rs[-3:]; s.append(_k0)

The stack: every cell above the lowest point the body reaches lives in
_k0, _k1, ... (deepest first) for the whole loop; a block hands its cells
to the next by assigning them (`carry_out`), the real stack gets them
before each slow path and when the loop ends. A ?BRANCH's flag is `_f`,
named before the cells move (it may be one of them).

The checks: each block still has its own, but it is made only while `_w`
is true. `_w` is computed at each head (the loop's start, each BEGIN):
false when no check up to the next head can fall due (`heads`, the most
clock the body spends from there). Nothing between two heads is Python
that could move the deadline (a store's m.watched only drops compiled code
or a name cache: it must stay so), so a block whose check is skipped would
have found it false: interrupts fall between the reference loop's primitives,
as everywhere. A Ctrl-C from a signal handler is seen at the next head,
within one pass of the body or of a BEGIN loop inside it; one asked for by
an interrupt handler (in a slow path) at the next primitive, as before.

A +LOOP whose step is known when compiling tests the index with
control.goes_on instead of calling LOOP_STEP. Where loop_shape cannot find
a shape (jumps that cross), the blocks are gone through with guards
`if b <= k` inside the while, as in the rest of a definition.
"""
from rcl.forth.compile_block import BlockState, I_LOCAL, LOAD_FRAME, LOAD_INDEX, STORE_INDEX
from rcl.forth.control import DROP_FRAME, goes_on
from rcl.forth.decode import NO_TERMINATOR
from rcl.forth.loop_shape import find_regions, loop_op, shape


def push(cells):
    """The statement (after "; ") that pushes cells on the real stack."""
    if len(cells) > 1:
        return "; s.extend((%s))" % ", ".join(cells)
    return "; s.append(%s)" % cells[0] if cells else ""


class LoopState:
    """What the code generator knows about the Python while it is in (one
    made fresh for each loop; one with nothing set outside them): its
    index' and limit' are in the locals _i and _lim."""
    __slots__ = ("in_loop", "real_stack", "carried_used", "carrying", "shaped", "dpl_guard")

    def __init__(self, in_loop=False, dpl_guard=False, shaped=False):
        self.in_loop = in_loop       # a loop of one block: I is computed from _i
        self.real_stack = False      # the body loaded from or wrote to the real stack
        self.carried_used = False    # the body took the carried top of stack
        self.carrying = False        # in a Region's block: flush hands vs on in locals (carry_out)
        self.shaped = shaped         # the Region's blocks are laid out as loop_shape found them
        self.dpl_guard = dpl_guard   # the loop's stores of DPL repeat: `_d` says if memory needs them

    @property
    def index_in_locals(self):
        """Is the loop frame's index' in _i now (not in rs, until stored)?"""
        return self.in_loop or self.carrying


class LoopGen:
    """Mixed into the compiler's Gen: `lp` is the loop being written."""

    def loopable(self, ops, term, start):
        """Can this block run as a Python while loop?"""
        if term is None or term.op not in ("(LOOP)", "(+LOOP)") or term.target != start:
            return False
        return all(loop_op(i) for i in ops)

    def steady_dpl(self, ops, stores=False):
        """Do the body's literals all leave the same DPL and WIDE-NUMBER,
        with nothing else in it that may store to memory (so that after
        one iteration's store the next finds them in place)? With `stores`,
        a store template may be there: dpl_overwritten watches its address."""
        values = set()
        for i in ops:
            p, num = i.prim, i.kind.number(i)
            if num is not None:
                if num[1] is not None:
                    values.add(num[1])
                continue
            tpl = i.kind.template(i)
            if tpl is None:
                continue                 # var, con, const, 2con, enter, exit
            writes = tpl.stmt is not None and tpl.stmt.uses & {"mem", "m", "W"}
            if "compile" in p.extra or (writes and not (stores and "W" in tpl.stmt.uses)):
                return False
            if any("m" in o.uses for o in tpl.outputs if o.input is None):
                return False
        return len(values) == 1

    def loop_body(self, ops, cost, plus, ind, carry, steady):
        """One iteration's primitives in Python -> (lines, step, carried
        out), or None when the body does not keep the top of stack (cost:
        the iteration's, counted at its start)."""
        saved, self.lines = self.lines, []
        self.blk = BlockState(["_c"] if carry else [], rest=cost)
        # (steady_dpl: the fast path stores DPL while _d says so)
        self.lp = LoopState(in_loop=True, dpl_guard=steady)
        for i in ops:
            self.blk.rest -= i.cost  # (for a store that changes the code: stale_check)
            self.op_simple(i, ind)
        self.blk.rest = 0
        step = self.take(1, ind)[0] if plus else None
        self.flush_dpl(ind)
        self.lp.dpl_guard = False
        out = None
        if carry:
            ok = self.lp.carried_used and not self.lp.real_stack and len(self.blk.vs) == 1
            out = self.blk.vs[0] if ok else None
        else:
            self.flush(ind)
            ok = True
        lines, self.lines = self.lines, saved
        self.lp, self.blk = LoopState(), BlockState()
        return (lines, step, out) if ok else None

    def loop_block(self, k, ops, term, ind):
        pre = sum(i.cost for i in ops)
        plus = term.op == "(+LOOP)"
        steady = self.steady_dpl(ops, stores=True)
        body = self.loop_body(ops, pre + term.cost, plus, ind + 2, True, steady)
        carry = body is not None
        if not carry:
            body = self.loop_body(ops, pre + term.cost, plus, ind + 2, False, steady)
        lines, step, out = body
        self.emit(LOAD_FRAME, ind, "rs")
        if carry:               # an empty stack: the reference loop runs it, to its underflow
            first = ops[0].addr if ops else term.addr
            self.emit("if not s: m.clock = clk; clk = -1; return m.run_from(%d, d0)" % first,
                      ind, "s", "d0")
            self.emit("_c = s.pop()", ind, "s")
        if steady:
            self.emit("_d = 1", ind)
        self.emit("while True:", ind)
        self.emit("if clk + %d >= m.deadline%s%s:" % (pre, self.depth_check(ops),
                                                      self.need_check(ops, 1 if carry else 0)),
                  ind + 1)
        self.emit("m.clock = clk; clk = -1; " + STORE_INDEX + ("; s.append(_c)" if carry else ""),
                  ind + 2, "s")
        self.slow_path(ops, term, term.cost, ind + 2)
        self.emit("clk = m.clock; " + LOAD_INDEX + ("; _n = s.pop()" if plus else "")
                  + ("; _c = s.pop()" if carry else "") + ("; _d = 1" if steady else ""), ind + 2)
        self.emit("else:", ind + 1)
        self.emit("clk += %d" % (pre + term.cost), ind + 2)
        self.lines.extend(lines)
        if carry and out != "_c":
            self.emit("_c = %s" % out, ind + 2)
        if plus:                  # named even when known: the slow path pops its own
            self.emit("_n = %s" % step, ind + 2)
        self.step_index("_n" if plus else "1", "; continue", ind + 1)
        self.emit("break", ind + 1)
        if carry:
            self.emit("s.append(_c)", ind)
        self.emit(DROP_FRAME, ind)
        self.goto_next(k, term.next, ind)

    def find_regions(self, blocks):
        """{first block: Region} for the loops of several blocks (loop_shape.py)."""
        return find_regions(blocks, self.index)

    def region_loop(self, r, blocks, ind):
        """The Python while of Region r (see the module's docstring)."""
        self.inner.update(blocks[k][0] for k in range(r.first + 1, r.last + 1))
        cells = ["_k%d" % i for i in range(r.carry[r.first])]
        self.emit(LOAD_FRAME, ind, "rs")
        if cells:               # a short stack: the reference loop runs it, to its underflow
            self.emit("if len(s) < %d:" % len(cells), ind, "s")
            self.emit("m.clock = clk; clk = -1; return m.run_from(%d, d0)" % blocks[r.first][0],
                      ind + 1, "d0")
            self.emit("; ".join("%s = s.pop()" % c for c in reversed(cells)), ind)
        if r.uses_i:
            self.emit("_I = " + I_LOCAL, ind)
        self.lp = LoopState(dpl_guard=self.steady_dpl(
            [i for k in range(r.first, r.last + 1) for i in blocks[k][1]], stores=True))
        if self.lp.dpl_guard:
            self.emit("_d = 1", ind)
        self.emit("while True:", ind)
        jumps = {k: self.jump_of(blocks[k][2]) for k in range(r.first, r.last)}
        nodes = shape(jumps, r.first, r.last)
        if nodes is not None:
            self.lp.shaped = True
            self.emit_shape(r, blocks, nodes + [("block", r.last)], ind + 1)
        else:                   # jumps that cross: from block to block through guards
            self.lp.shaped = False
            for k in range(r.first, r.last + 1):
                a = blocks[k][0]
                self.emit("if b <= %d:   # %04X  %s" % (k, a, self.forth[a]), ind + 1)
                self.region_block(r, k, blocks[k], ind + 2)
        self.emit("break", ind + 1)
        self.lp = LoopState()
        self.emit(DROP_FRAME + push(cells), ind)
        self.goto_next(r.last, blocks[r.last][2].next, ind)

    def jump_of(self, term):
        """(op, block index) of a loop body's terminator, for loop_shape."""
        if term is None:
            return None, None
        return term.op, self.index[term.target]

    def emit_shape(self, r, blocks, nodes, ind):
        """Python for loop_shape's nodes."""
        for node in nodes:
            kind = node[0]
            if kind == "block":
                a = blocks[node[1]][0]
                self.emit("# %04X  %s" % (a, self.forth[a]), ind)
                self.region_block(r, node[1], blocks[node[1]], ind)
            elif kind == "if":
                self.emit("if _f:", ind)
                self.emit_shape(r, blocks, node[1], ind + 1)
                if not node[1]:
                    self.emit("pass", ind + 1)
                if node[2]:
                    self.emit("else:", ind)
                    self.emit_shape(r, blocks, node[2], ind + 1)
            elif kind == "unless":
                self.emit("if not _f: %s" % node[1], ind)
            elif kind == "stmt":
                self.emit(node[1], ind)
            else:
                self.emit("while True:", ind)
                self.emit_shape(r, blocks, node[1], ind + 1)
                if node[1][-1] != ("stmt", "continue"):
                    self.emit("break", ind + 1)

    def region_block(self, r, k, block, ind):
        """Block k of Region r: its check (made only while _w says the
        deadline is near), its slow path and its fast one."""
        _, ops, term, self.next_addr = block
        pre = sum(i.cost for i in ops)
        tcost = term.cost if term is not None else 0
        if k in r.heads:
            self.emit("_w = clk + %d >= m.deadline" % r.heads[k], ind)
        self.emit("if _w and clk + %d >= m.deadline%s:" % (pre, self.depth_check(ops)), ind)
        cells = ["_k%d" % i for i in range(r.carry[k])]
        self.emit("m.clock = clk; clk = -1; " + STORE_INDEX + push(cells), ind + 1, "s")
        self.slow_path(ops, term, tcost, ind + 1)
        self.clock_in(ind + 1)
        if self.lp.dpl_guard:                # (a handler may have changed DPL)
            self.emit("_d = 1", ind + 1)
        index = "_I" if r.uses_i else None
        self.lp.carrying = True
        self.blk = BlockState(index_atom=index)
        self.blk.vs = self.take(r.after[k], ind + 1)
        self.region_end(r, k, term, ind + 1)
        self.emit("else:", ind)
        self.blk = BlockState(cells, index_atom=index)
        self.fast_ops(ops, pre + tcost, ind + 1)
        self.region_end(r, k, term, ind + 1)
        self.lp.carrying = False
        self.blk = BlockState()

    def region_end(self, r, k, term, ind):
        """Block k's terminator; the loop's step at its last block. A flag
        or step is named before the cells are handed on (carry_out may
        assign the _k it is)."""
        op = term.op if term is not None else None
        if k == r.last:
            self.loop_step(r, term, ind)
        elif op == "?BRANCH":
            self.name_flag(self.take(1, ind)[0], ind)
            self.flush(ind)
            if not self.lp.shaped:           # jump if zero: ?BRANCH's rule (control.py)
                self.branch("not _f", term.target, k, term.next, ind)
        elif self.lp.shaped:
            self.flush(ind)               # (a jump's place in the shape says where it goes)
        else:
            self.terminator(term or NO_TERMINATOR, k, ind)

    def name_flag(self, f, ind):
        """_f = the flag, or the comparison that made it (`truth`), whose
        Python truth is the flag's. A temp just made for the flag alone is
        made as _f."""
        t = self.truth(f)
        head = "    " * ind + f + " = "
        last = self.lines[-1] if self.lines else None
        if t == f and self.handed.get(f) == 1 and last is not None and last.startswith(head):
            self.lines[-1] = "    " * ind + "_f = " + last[len(head):]
        else:
            self.emit("_f = %s" % t, ind)

    def loop_step(self, r, term, ind):
        """The (LOOP) or (+LOOP) at the body's end: go round again or fall
        out to the while's break."""
        n = self.take(1, ind)[0] if term.op == "(+LOOP)" else "1"
        if not n.isdigit():
            self.emit("_n = %s" % n, ind)
            n = "_n"
        self.flush(ind)
        on = ("; _I = " + I_LOCAL if r.uses_i else "") + "; " + (
            "continue" if self.lp.shaped else "b = %d; continue" % r.first)
        self.step_index(n, on, ind)

    def step_index(self, n, on, ind):
        """Step the index _i by n (a number known when compiling, or the
        name holding it) and go round again (`on`), unless the step ends
        the loop (control.loop_step's rule; goes_on spells it out for a
        known step)."""
        if n.isdigit():
            self.emit("if %s: _i = (_i + %s) & 0xFFFF%s" % (goes_on("_i", int(n)), n, on), ind)
        else:
            self.emit("_y = LOOP_STEP(_i, %s)" % n, ind)
            self.emit("if _y is not None: _i = _y" + on, ind)

    def dpl_overwritten(self, addr, ind):
        """After a store template at addr (its last input; at most 4 bytes)
        in a loop whose literals' DPL is steady: if it may have hit DPL or
        WIDE-NUMBER, the next literal stores them again (_d)."""
        cells = (self.m.a_dpl, self.m.a_wide)
        lo, hi = min(cells) - 3, max(cells) + 1
        if not addr.isdigit():
            self.emit("if %d <= %s <= %d: _d = 1" % (lo, addr, hi), ind)
        elif lo <= int(addr) <= hi:
            self.emit("_d = 1", ind)

    def carry_out(self, ind):
        """Hand the cells in vs to the next block in locals _k0.. (the
        stack from the loop's lowest point up), not to the real stack."""
        pairs = [("_k%d" % i, v) for i, v in enumerate(self.blk.vs) if v != "_k%d" % i]
        if pairs:
            self.emit("%s = %s" % (", ".join(n for n, _ in pairs), ", ".join(v for _, v in pairs)),
                      ind)
        self.blk.vs = []
