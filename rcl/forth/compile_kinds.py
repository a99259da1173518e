"""Instruction kinds: all the compiler does with each kind of decoded cell.

decode.py gives every cell of threaded code an `Instr` whose `kind` is one
of the objects below (`ins.op`, what SEE and the tests read, is its name).
A kind says in one class what the compiler asks of it; the callers ask
`ins.kind`, never the name, so adding a kind is one class here and the
line of decode.py that makes it:

    asked by                   method            answers
    decode.walk                ends_block        a terminator (a block ends after it)?
                               falls_through     may go on at the next cell
    decode.callee              plain(ins)        computes only on the stack and memory
    compile_block.op_simple    template(ins)     the inline template pasted, or None
                               keeps_rs(ins)     leaves the return stack alone
                               fast(g, ins, ..)  its fast-path code in a block
    decode.call_depth          rs_growth(ins)    cells pushed on rs (None: unknown)
    compile_block.slow_entry   slow(ins)         (function, args) for the exact path
                               may_store(ins)    may change code (a stale check after)
    compile_block.forth_of     forth(m, ins)     the Forth a comment shows
    compile_loops.steady_dpl   number(ins)       a number literal's (cells, DPL)
    loop_shape                 loop_op(ins)      fits a Python while
                               stack_effect(ins) (cells taken, cells left)
    compiler.Gen.block         costed            its cost counted by its block
                               checks_docol      calls after its own cell (its (DOCOL))
    compiler.Gen.terminator    end(g, ins, ..)   the code that ends a block
    compiler.Gen.build         parts(ins)        the instructions it stands for
                               watched(ins)      cells its code rests on beyond its own

    kind      from (decode.py)                  args
    simple    a primitive with no Forth inside  ()
    literal   a primitive with inline cells     the decoded cells
    var       (DOVAR)                           (body,)
    const     (DOCON): the value compiled in    (body,)
    con       (DOVALUE): read when run          (body,)
    2con      (DO2CON), (DO2VALUE)              (body,)
    colon     (DOCOL)                           (body,)
    does      a DOES> child                     (code after DOES>,)
    defer     (DODEFER)                         (body,)
    call      a primitive that may run Forth    (); a runtime: (body,), called as a word
    bad       no primitive                      ()
    inline    a small colon call pasted         (body, (enter, ..., exit))
    enter     an inlined call's start           (return address,)
    exit      its EXIT                          ()
    (name)    a control operation (control.py)  (); its target in ins.target
    None      a block that runs into the next
"""
from rcl.forth.control import BY_NAME as CONTROL_OPS
from rcl.forth.inner import RSTACK_CELLS, rt_push
from rcl.forth.memory import MASK, signed

LOOP_RS_WORDS = ("I", "J")       # the only templates naming rs a loop body may use


# ------------------------------------------------- the exact path's functions
# What `slow` runs for instructions with no primitive function of their own.

def rt_enter(m, ret):
    """An inlined call, one primitive at a time: what Inner.enter does."""
    rs = m.rs
    rs.append(ret)
    if len(rs) > RSTACK_CELLS:
        m.rs_overflow()


def rt_exit(m):
    m.rs.pop()


def rt_con(m, a):
    m.s.append(m.memory.fetch(a))


def rt_2con(m, a):
    m.s.extend(m.memory.dfetch(a))


# ---------------------------------------------------------------- the kinds
class Kind:
    """The defaults: a cell that runs Python the compiler cannot see into."""
    name = None
    ends_block = False
    falls_through = True     # may go on at the next cell
    costed = True            # its cost counted in its block (not in m.call's)
    checks_docol = False     # calls a word at the boundary after its own cell

    def template(self, ins):
        return None

    def number(self, ins):
        """(cells, dpl) of a number literal, or None."""
        return None

    def plain(self, ins):
        return False

    def keeps_rs(self, ins, tpl=None):
        tpl = tpl or self.template(ins)
        return tpl is not None and "rs" not in tpl.uses

    def rs_growth(self, ins):
        tpl = self.template(ins)
        return tpl.rs_push if tpl is not None else None

    def may_store(self, ins):
        tpl = self.template(ins)
        return tpl is None or bool(tpl.uses & {"W", "m"})

    def loop_op(self, ins):
        return False

    def stack_effect(self, ins):
        """(cells taken, cells left), or None: Python the compiler cannot see into."""
        tpl = self.template(ins)
        return None if tpl is None else (len(tpl.inputs), len(tpl.outputs))

    def forth(self, m, ins):
        name = m.dictionary.name_of(ins.xt)
        return name if name else "xt %d" % ins.xt

    def slow(self, ins):
        return ins.prim.fn, ()

    def parts(self, ins):
        return (ins,)

    def watched(self, ins):
        return ()

    def __repr__(self):
        return "<kind %s>" % self.name


class Simple(Kind):
    name = "simple"

    def template(self, ins):
        return ins.prim.template

    def plain(self, ins):
        t = ins.prim.template
        return t is not None and "rs" not in t.uses

    def loop_op(self, ins):
        t = ins.prim.template
        return t is not None and ("rs" not in t.uses or ins.prim.name in LOOP_RS_WORDS)

    def forth(self, m, ins):
        return ins.prim.name

    def fast(self, g, ins, tpl, ind):
        if ins.prim.template is not None:
            g.op_inline(ins.prim, ind)
        else:
            g.python_call("%s(m)" % g.const(ins.prim.fn, "P"), ins, ind)


class Literal(Kind):
    """A primitive followed by inline cells: a number (extra["lit"] says
    its cells and DPL), or a word set's (extra["inline_args"] may make a
    template from the cells, as the Locals word set's rs[-k] does)."""
    name = "literal"

    def number(self, ins):
        """(cells, dpl) of a number literal, or None."""
        lit = ins.prim.extra.get("lit")
        return lit(ins.args) if lit is not None else None

    def template(self, ins):
        if "lit" in ins.prim.extra:
            return None
        make = ins.prim.extra.get("inline_args")
        return make(ins.args) if make is not None else None

    def plain(self, ins):            # (not a locals frame's: never pasted elsewhere)
        return ins.prim.extra.get("lit") is not None

    loop_op = plain

    def keeps_rs(self, ins, tpl=None):
        return "lit" in ins.prim.extra or Kind.keeps_rs(self, ins, tpl)

    def rs_growth(self, ins):
        extra = ins.prim.extra
        if "rs_cells" in extra:
            return extra["rs_cells"](ins.args)
        return 0 if "lit" in extra else Kind.rs_growth(self, ins)

    def stack_effect(self, ins):
        number = self.number(ins)
        return (0, len(number[0])) if number is not None else Kind.stack_effect(self, ins)

    def forth(self, m, ins):
        p = ins.prim
        if p.extra.get("lit") is None:
            return " ".join([p.name] + [str(a) for a in ins.args if isinstance(a, int)])
        cells, _ = self.number(ins)
        if len(cells) == 2:
            return str(signed(cells[0]) if cells[1] == 0 else (cells[1] << 16 | cells[0]))
        return str(signed(cells[0]))

    def slow(self, ins):
        return ins.prim.fn, ins.args

    def fast(self, g, ins, tpl, ind):
        num = self.number(ins)
        if num is not None:                        # numbers: pushed as constants
            cells, dpl = num
            g.blk.vs.extend(str(c) for c in cells)
            if dpl is not None:
                g.blk.dpl = dpl
        elif tpl is not None:                      # made from the inline cells
            g.op_inline(ins.prim, ind, tpl)
        else:
            g.python_call("%s(m, *%r)" % (g.const(ins.prim.fn, "P"), ins.args), ins, ind)


class Cell(Kind):
    """A word whose runtime only pushes (a variable, a constant, a value):
    no Python call, no store, the return stack untouched."""
    pushes = 1

    def plain(self, ins):
        return True

    loop_op = plain

    def keeps_rs(self, ins, tpl=None):
        return True

    def rs_growth(self, ins):
        return 0

    def may_store(self, ins):
        return False

    def stack_effect(self, ins):
        return 0, self.pushes


class Var(Cell):
    name = "var"

    def slow(self, ins):
        return rt_push, ins.args

    def fast(self, g, ins, tpl, ind):
        g.blk.vs.append(str(ins.args[0]))


class Const(Cell):
    """A CONSTANT: its value compiled in, its cell watched."""
    name = "const"

    def slow(self, ins):
        return rt_con, ins.args

    def watched(self, ins):
        return ins.args[0], (ins.args[0] + 1) & MASK

    def fast(self, g, ins, tpl, ind):
        g.blk.vs.append(str(g.m.memory.fetch(ins.args[0])))


CELL = "(mem[%d] | (mem[%d] << 8))"


class Con(Cell):
    """A VALUE: read from memory each time."""
    name = "con"

    def slow(self, ins):
        return rt_con, ins.args

    def fast(self, g, ins, tpl, ind):
        g.flush_dpl(ind)
        a = ins.args[0]
        t = g.temp()
        g.emit("%s = %s" % (t, CELL % (a, (a + 1) & MASK)), ind, "mem")
        g.blk.vs.append(t)


class TwoCon(Cell):
    name = "2con"
    pushes = 2

    def slow(self, ins):
        return rt_2con, ins.args

    def fast(self, g, ins, tpl, ind):
        g.flush_dpl(ind)
        a = ins.args[0]
        lo, hi = g.temp(), g.temp()
        g.emit("%s = %s" % (lo, CELL % ((a + 2) & MASK, (a + 3) & MASK)), ind, "mem")
        g.emit("%s = %s" % (hi, CELL % (a, (a + 1) & MASK)), ind)
        g.blk.vs.extend((lo, hi))


class Enter(Kind):
    """An inlined call's start (decode.inline): costs what the call costs;
    the fast path pushes no return address (the block's check saw the
    depth it needs, unless Python code ran before it: call_check)."""
    name = "enter"

    def keeps_rs(self, ins, tpl=None):
        return True          # (an inlined call's fast path does not touch rs)

    def rs_growth(self, ins):
        return 1

    def may_store(self, ins):
        return False

    def loop_op(self, ins):
        return True

    def stack_effect(self, ins):
        return 0, 0

    def slow(self, ins):
        return rt_enter, ins.args

    def fast(self, g, ins, tpl, ind):
        g.blk.open_calls += 1
        if g.blk.rs_unknown:
            g.call_check(ind)
        g.blk.inlined.append(ins.addr)
        g.blk.open_rets.append(str(ins.args[0]))


class Exit(Enter):
    """An inlined call's EXIT."""
    name = "exit"

    def rs_growth(self, ins):
        return -1

    def slow(self, ins):
        return rt_exit, ()

    def fast(self, g, ins, tpl, ind):
        g.blk.open_calls -= 1
        if g.blk.inlined:
            g.blk.inlined.pop()
            g.blk.open_rets.pop()


class Inline(Kind):
    """A small colon call whose body is pasted into the block (decode.py)."""
    name = "inline"

    def parts(self, ins):
        return ins.args[1]


# ------------------------------------------------------------ terminators
class Terminator(Kind):
    """A cell after which the block ends: its code after the data stack's
    atoms are written back (`flush`)."""
    ends_block = True

    def end(self, g, ins, k, ind):
        g.flush(ind)
        self.after_flush(g, ins, k, ind)


class Fall(Terminator):
    """No terminator: the block runs into the next one."""
    costed = False

    def stack_effect(self, ins):
        return 0, 0

    def after_flush(self, g, ins, k, ind):
        g.goto_next(k, g.next_addr, ind)


class Colon(Terminator):
    name = "colon"

    def after_flush(self, g, ins, k, ind):
        g.enter_call(str(ins.args[0]), ins.next, ind)      # the body, or the code after DOES>
        g.call_tail(ins, k, ind)


class Does(Colon):
    """A DOES> child: its body's address pushed, the code after DOES> called."""
    name = "does"

    def after_flush(self, g, ins, k, ind):
        g.emit("s.append(%d)" % ((ins.xt + 2) & MASK), ind, "s")
        Colon.after_flush(self, g, ins, k, ind)


class Defer(Terminator):
    name = "defer"
    checks_docol = True

    def after_flush(self, g, ins, k, ind):
        body = ins.args[0]
        g.emit("_x = mem[%d] | (mem[%d] << 8)" % (body, (body + 1) & MASK), ind, "mem")
        g.dynamic_call("_x", ins.next, ind, g.m.memory.fetch(body))
        g.call_tail(ins, k, ind)


class Call(Terminator):
    """A primitive that may run Forth, move the clock or the deadline."""
    name = "call"

    def forth(self, m, ins):
        return ins.prim.name

    def after_flush(self, g, ins, k, ind):
        g.clock_out(ind)
        g.emit("%s(m)" % g.const(ins.prim.fn, "P"), ind)
        g.stale_check(ins.next, ind)
        g.clock_in(ind)
        g.goto_next(k, ins.next, ind)


class ThroughCall(Terminator):
    """A cell run as m.call(xt) runs it, costed there: a bad xt."""
    name = "bad"
    costed = False

    def after_flush(self, g, ins, k, ind):
        g.clock_out(ind)
        g.emit("r = m.call(%d, %d)" % (ins.xt, ins.next), ind)
        g.call_tail(ins, k, ind)


class RuntimeCall(ThroughCall):
    """A word with a runtime of its own (a vocabulary, a marker, ...),
    run through m.call; shown as its runtime."""
    name = "call"

    def forth(self, m, ins):
        return ins.prim.name


class Control(Terminator):
    """A control operation: its code generator is in control.py."""

    def __init__(self, op):
        self.op = op
        self.name = op.name
        self.checks_docol = op.calls
        self.falls_through = op.falls_through

    def forth(self, m, ins):
        return ins.prim.name

    def stack_effect(self, ins):
        return self.op.takes, 0

    def end(self, g, ins, k, ind):
        self.op.gen(g, ins, k, ind)


SIMPLE, LITERAL, CALL, BAD, RUNTIME_CALL = Simple(), Literal(), Call(), ThroughCall(), RuntimeCall()
VAR, CONST, CON, TWO_CON = Var(), Const(), Con(), TwoCon()
COLON, DOES, DEFER = Colon(), Does(), Defer()
INLINE, INLINE_ENTER, INLINE_EXIT, FALL = Inline(), Enter(), Exit(), Fall()
CONTROL = {name: Control(op) for name, op in CONTROL_OPS.items()}
