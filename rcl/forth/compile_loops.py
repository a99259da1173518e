"""DO loops compiled as Python `while` loops: the compiler's loop half.

A loop whose whole body is one block, ending in the (LOOP) or (+LOOP) that
jumps back to the block's own start, such as

    : SUM  0 100 0 DO  I +  LOOP ;

runs as one Python `while`, with the loop index and the limit in Python
locals beside the clock (`clk`, a local of every compiled function), and,
when the body leaves the stack as deep as it found it, the top of the data
stack too:

    _lim = rs[-2]; _i = rs[-1]
    _c = s.pop()                              # the top of stack, carried
    while True:
        if clk + 2000000 >= m.deadline:       # the usual check, each iteration
            m.clock = clk; clk = -1; rs[-1] = _i; s.append(_c)
            slow(m, SEQ1, 1000000)            # exact: one primitive at a time
            clk = m.clock; _i = rs[-1]; _c = s.pop()
        else:
            clk += 3000000
            t3 = (_i + _lim) & 0xFFFF         # I
            t4 = (_c + t3) & 0xFFFF           # +
            _c = t4
        if _i != 32767: _i = _i + 1 & 0xFFFF; continue
        break
    s.append(_c)
    del rs[-3:]

Each iteration checks the deadline exactly as the block would, so
interrupts (and a Ctrl-C, which sets the deadline to -1) are taken between
the same primitives as in the reference loop; before the slow path runs,
everything in locals is written back, so the primitives and any interrupt
handler see the real stacks and clock.

An RCL literal stores DPL (and WIDE-NUMBER) each time it runs. When the
body stores the same value each iteration and writes no other memory
(`steady_dpl`), an iteration finds those cells already holding it unless
the slow path ran since (an interrupt handler may have changed them):
the fast path stores only while `_d` says so, the slow path sets `_d`
again, and memory at every point is the reference loop's:

    _d = 1                                    # before the loop
        ...                                   # (the slow path ends: _d = 1)
            if _d:
                mem[1030] = 255; mem[1031] = 255
                mem[1064] = 0; mem[1065] = 0
                _d = 0

Only bodies whose every primitive is known not to look at the loop frame
or the clock qualify: literals, variables, constants and inline templates
that touch the return stack only as I or J.
"""
from rcl.forth.control import LAST_INDEX
from rcl.forth.decode import literal_template

LOOP_RS_WORDS = ("I", "J")       # the only templates naming rs a loop body may use


class LoopGen:
    """Mixed into the compiler's Gen."""

    in_loop = False
    real_stack = False           # the body loaded from or wrote to the real stack
    carried_used = False         # the body took the carried top of stack

    def loopable(self, ops, term, start):
        """Can this block run as a Python while loop?"""
        if term is None or term.op not in ("(LOOP)", "(+LOOP)") or term.target != start:
            return False
        for i in ops:
            p = i.prim
            if i.op in ("var", "con", "const", "2con", "enter", "exit"):
                continue
            if i.op == "literal" and p.extra.get("lit") is not None:
                continue
            if i.op != "simple" or p.template is None:
                return False
            if "rs" in p.template.uses and p.name not in LOOP_RS_WORDS:
                return False
        return True

    def steady_dpl(self, ops):
        """Do the body's literals all leave the same DPL and WIDE-NUMBER,
        with nothing else in it that may store to memory (so that after
        one iteration's store the next finds them in place)?"""
        values = set()
        for i in ops:
            p = i.prim
            if i.op == "literal" and p.extra.get("lit") is not None:
                dpl = p.extra["lit"](i.args)[1]
                if dpl is not None:
                    values.add(dpl)
                continue
            tpl = literal_template(i) or (p.template if i.op == "simple" else None)
            if tpl is None:
                continue                 # var, con, const, 2con, enter, exit
            if "compile" in p.extra or (tpl.stmt is not None and tpl.stmt.uses & {"mem", "m", "W"}):
                return False
            if any("m" in o.uses for o in tpl.outputs if o.input is None):
                return False
        return len(values) == 1

    def loop_body(self, ops, plus, ind, carry, steady):
        """One iteration's primitives in Python -> (lines, step, carried
        out), or None when the body does not keep the top of stack."""
        saved, self.lines = self.lines, []
        self.vs, self.dpl = (["_c"] if carry else []), None
        self.real_stack, self.in_loop, self.carried_used = False, True, False
        self.index_atom, self.open_calls, self.rs_unknown = None, 0, False
        self.dpl_guard = steady      # (steady_dpl: the fast path stores DPL while _d says so)
        for i in ops:                # (no Python primitive here: `rest` stays 0)
            self.op_simple(i, ind)
        step = self.take(1, ind)[0] if plus else None
        self.flush_dpl(ind)
        self.dpl_guard = False
        out = None
        if carry:
            ok = self.carried_used and not self.real_stack and len(self.vs) == 1
            out = self.vs[0] if ok else None
        else:
            self.flush(ind)
            ok = True
        lines, self.lines = self.lines, saved
        self.in_loop = False
        self.vs = []
        return (lines, step, out) if ok else None

    def loop_block(self, k, ops, term, ind):
        pre = sum(i.cost for i in ops)
        plus = term.op == "(+LOOP)"
        seq = self.const(tuple(self.slow_entry(i) for i in ops), "SEQ")
        steady = self.steady_dpl(ops)
        body = self.loop_body(ops, plus, ind + 2, True, steady)
        carry = body is not None
        if not carry:
            body = self.loop_body(ops, plus, ind + 2, False, steady)
        lines, step, out = body
        self.emit("_lim = rs[-2]; _i = rs[-1]", ind, "rs")
        if carry:
            self.emit("_c = s.pop()", ind, "s")
        if steady:
            self.emit("_d = 1", ind)
        self.emit("while True:", ind)
        self.emit("if clk + %d >= m.deadline%s:" % (pre, self.depth_check(ops)), ind + 1)
        self.emit("m.clock = clk; clk = -1; rs[-1] = _i" + ("; s.append(_c)" if carry else ""),
                  ind + 2, "s")
        self.emit("slow(m, %s, %d)" % (seq, term.cost), ind + 2)
        self.emit("clk = m.clock; _i = rs[-1]" + ("; _n = s.pop()" if plus else "")
                  + ("; _c = s.pop()" if carry else "") + ("; _d = 1" if steady else ""), ind + 2)
        self.emit("else:", ind + 1)
        self.emit("clk += %d" % (pre + term.cost), ind + 2)
        self.lines.extend(lines)
        if carry and out != "_c":
            self.emit("_c = %s" % out, ind + 2)
        if plus:
            self.emit("_n = %s" % step, ind + 2)
            self.emit("_y = LOOP_STEP(_i, _n)", ind + 1)
            self.emit("if _y is not None: _i = _y; continue", ind + 1)
        else:
            self.emit("if _i != %d: _i = _i + 1 & 0xFFFF; continue" % LAST_INDEX, ind + 1)
        self.emit("break", ind + 1)
        if carry:
            self.emit("s.append(_c)", ind)
        self.emit("del rs[-3:]", ind)
        self.goto_next(k, term.next, ind)
