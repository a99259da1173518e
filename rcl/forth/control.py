"""Control operations: branches, DO loops, EXIT, EXECUTE, each said twice,
side by side: once as the reference interpreter runs it, once as the
compiler writes it in Python.

    op        cells after the xt   reference `run(m, ip)` -> next ip
    BRANCH    target               ip = target
    ?BRANCH   target               ( f -- ) jump if f is zero
    (DO)      target (after LOOP)  ( limit start -- ) push a loop frame
    (LOOP)    target (loop start)  step the index by 1; leave or jump back

`run(m, ip)` gets ip pointing just past the xt (at the inline target, if
any) and returns where to go on. `gen(g, ins, k, ind)` writes the same
meaning into block k of a compiled definition (g is the compiler's `Gen`;
ins the decoded instruction, with `target` and `next`). A test runs every
operation both ways and compares stacks, output and the virtual clock.

F83's DO-loop frame, drawn once (three cells on the return stack):

    rs[-3]  where LEAVE goes (the cell after the loop)
    rs[-2]  limit' = limit + 0x8000
    rs[-1]  index' = index - limit'      (so I = index' + limit')

The loop ends when adding the step to index' overflows a signed cell: the
index crossed the boundary between limit-1 and limit, from either side.
`do_frame` and `loop_step` are the only places that arithmetic is written
(`goes_on` spells loop_step out for a step known when compiling), and
LEAVE, LIMIT, INDEX and `frame_cell` the only place the layout is: the
reference functions below, the compiler's loops (compile_loops.py) and the
I, J and UNLOOP templates (words/core.py) all name the cells through them.
"""
from dataclasses import dataclass

from rcl.forth.memory import MASK
from rcl.forth.primitives import HELPERS

LAST_INDEX = 0x7FFF          # index' from which a step of +1 ends the loop
FRAME_CELLS = 3              # a DO loop's frame on the return stack, and its cells:
LEAVE, LIMIT, INDEX = -3, -2, -1      # rs[LEAVE], rs[LIMIT], rs[INDEX]
DROP_FRAME = "del rs[-%d:]" % FRAME_CELLS   # (as Python text, for compiled code)


def frame_cell(cell, loop=0):
    """Python text for a cell (LEAVE, LIMIT or INDEX) of the DO-loop frame
    `loop` frames out (0: the innermost), with nothing above it on rs."""
    return "rs[%d]" % (cell - FRAME_CELLS * loop)


def index_of(index, limit):
    """Python text for a loop's index from its index' and limit'."""
    return "(%s + %s) & 0xFFFF" % (index, limit)


def do_frame(limit, start):
    """(limit', index') for a loop from start up to limit."""
    lim = (limit + 0x8000) & MASK
    return lim, (start - lim) & MASK


def loop_step(index, n):
    """The index' after a step of n, or None when the loop ends."""
    y = ((index ^ 0x8000) - 0x8000) + ((n ^ 0x8000) - 0x8000)
    return y & MASK if -0x8000 <= y <= 0x7FFF else None


def goes_on(index, n):
    """Python text true when a step of n, known when compiling, from the
    index' named `index` does not end the loop (loop_step's rule spelt out;
    the new index' is then (index + n) & 0xFFFF)."""
    n = (n ^ 0x8000) - 0x8000
    if n == 1:
        return "%s != %d" % (index, LAST_INDEX)
    if n >= 0:                   # ends when a non-negative index' passes 0x7FFF
        return "%s >= 0x8000 or %s <= %d" % (index, index, 0x7FFF - n)
    return "%s < 0x8000 or %s >= %d" % (index, index, 0x8000 - n)


HELPERS.update(DO_FRAME=do_frame, LOOP_STEP=loop_step)


@dataclass
class ControlOp:
    name: str
    effect: str
    run: object              # run(m, ip) -> next ip
    gen: object              # gen(g, ins, k, ind): Python for block k
    target: bool = False     # an inline target cell follows the xt
    falls_through: bool = True   # may go on at the next cell
    leaves: bool = False     # may leave the definition (pops the return stack)
    takes: int = 0           # cells it pops from the data stack
    calls: bool = False      # calls a word at the boundary after its own cell (its (DOCOL))


# ------------------------------------------------------------------ EXIT
def run_exit(m, ip):
    return m.rs.pop()


def gen_exit(g, ins, k, ind):
    g.flush(ind)
    g.emit("return rs.pop()", ind, "rs")


# -------------------------------------------------------------- branches
def run_branch(m, ip):
    return m.memory.fetch(ip)


def gen_branch(g, ins, k, ind):
    g.flush(ind)
    g.goto_next(k, ins.target, ind)


def run_qbranch(m, ip):
    return m.memory.fetch(ip) if m.s.pop() == 0 else (ip + 2) & MASK


def gen_qbranch(g, ins, k, ind):
    (f,) = g.take(1, ind)
    g.flush(ind)
    g.branch(g.branch_test(f), ins.target, k, ins.next, ind)


# ----------------------------------------------------------------- loops
def run_do(m, ip):
    start, limit = m.s.pop(), m.s.pop()
    m.rs.extend((m.memory.fetch(ip),) + do_frame(limit, start))
    return (ip + 2) & MASK


def gen_do(g, ins, k, ind):
    limit, start = g.take(2, ind)
    g.flush(ind)
    g.emit("rs.extend((%d,) + DO_FRAME(%s, %s))" % (ins.target, limit, start), ind, "rs")
    g.goto_next(k, ins.next, ind)


def run_qdo(m, ip):
    start, limit = m.s.pop(), m.s.pop()
    if start == limit:
        return m.memory.fetch(ip)
    m.rs.extend((m.memory.fetch(ip),) + do_frame(limit, start))
    return (ip + 2) & MASK


def gen_qdo(g, ins, k, ind):
    limit, start = g.take(2, ind)
    g.flush(ind)
    g.emit("if %s == %s: %s" % (start, limit, g.jump_text(ins.target, k)), ind)
    g.emit("else:", ind)
    g.emit("rs.extend((%d,) + DO_FRAME(%s, %s))" % (ins.target, limit, start), ind + 1, "rs")
    g.goto_next(k, ins.next, ind + 1)


def run_loop(m, ip):
    rs = m.rs
    x = loop_step(rs[INDEX], 1)
    if x is None:
        del rs[-FRAME_CELLS:]
        return (ip + 2) & MASK
    rs[INDEX] = x
    return m.memory.fetch(ip)


def gen_loop(g, ins, k, ind):
    g.flush(ind)
    index = frame_cell(INDEX)
    g.emit("_x = %s" % index, ind, "rs")    # loop_step(_x, 1), spelt out: the hot path
    g.branch("_x != %d" % LAST_INDEX, ins.target, k, ins.next, ind,
             "%s = _x + 1 & 0xFFFF" % index, DROP_FRAME)


def run_plus_loop(m, ip):
    rs = m.rs
    x = loop_step(rs[INDEX], m.s.pop())
    if x is None:
        del rs[-FRAME_CELLS:]
        return (ip + 2) & MASK
    rs[INDEX] = x
    return m.memory.fetch(ip)


def gen_plus_loop(g, ins, k, ind):
    (n,) = g.take(1, ind)
    g.flush(ind)
    g.emit("_y = LOOP_STEP(%s, %s)" % (frame_cell(INDEX), n), ind, "rs")
    g.branch("_y is not None", ins.target, k, ins.next, ind,
             "%s = _y" % frame_cell(INDEX), DROP_FRAME)


def run_leave(m, ip):
    rs = m.rs
    ip = rs[LEAVE]
    del rs[-FRAME_CELLS:]
    return ip


def gen_leave(g, ins, k, ind):
    g.flush(ind)
    leave(g, ind)


def run_qleave(m, ip):
    return run_leave(m, ip) if m.s.pop() else ip


def gen_qleave(g, ins, k, ind):
    (f,) = g.take(1, ind)
    g.flush(ind)
    g.emit("if %s:" % f, ind)
    leave(g, ind + 1)
    g.goto_next(k, ins.next, ind)


def leave(g, ind):
    """Go where the loop frame says (a block of this definition, or, for a
    frame some other word made, the reference loop)."""
    g.emit("_t = %s; %s" % (frame_cell(LEAVE), DROP_FRAME), ind, "rs")
    g.emit("b = BMAP.get(_t)", ind)
    g.emit("if b is None: m.clock = clk; clk = -1; return m.run_from(_t, d0)", ind, "d0")
    g.emit("continue", ind)


# ----------------------------------------------------- DOES> and EXECUTE
def run_does(m, ip):
    m.dictionary.set_does(ip)
    return m.rs.pop()


def gen_does(g, ins, k, ind):
    g.flush(ind)
    g.emit("m.dictionary.set_does(%d)" % ins.next, ind)
    g.emit("return rs.pop()", ind, "rs")


def run_execute(m, ip):
    return m.call(m.s.pop(), ip)


def gen_execute(g, ins, k, ind):
    (x,) = g.take(1, ind)
    g.flush(ind)
    g.dynamic_call(x, ins.next, ind, g.fetched_xt(x))
    g.call_tail(ins, k, ind)


OPS = [
    ControlOp("EXIT", "( -- ) return from the current definition", run_exit, gen_exit,
              falls_through=False, leaves=True),
    ControlOp("BRANCH", "( -- ) jump to the inline address", run_branch, gen_branch,
              target=True, falls_through=False),
    ControlOp("?BRANCH", "( f -- ) jump to the inline address if f is zero",
              run_qbranch, gen_qbranch, target=True, takes=1),
    ControlOp("(DO)", "( limit start -- ) R: ( -- leave limit' index' )", run_do, gen_do,
              target=True, takes=2),
    ControlOp("(?DO)", "( limit start -- ) as (DO), but skip the loop if limit = start",
              run_qdo, gen_qdo, target=True, takes=2),
    ControlOp("(LOOP)", "( -- ) add 1 to the index; loop back unless it crossed",
              run_loop, gen_loop, target=True),
    ControlOp("(+LOOP)", "( n -- ) add n to the index; loop back unless it crossed",
              run_plus_loop, gen_plus_loop, target=True, takes=1),
    ControlOp("(LEAVE)", "( -- ) leave the loop now", run_leave, gen_leave,
              falls_through=False),
    ControlOp("(?LEAVE)", "( f -- ) leave the loop if f is non-zero", run_qleave, gen_qleave,
              takes=1),
    ControlOp("(DOES>)", "( -- ) make the last word run the code after DOES>",
              run_does, gen_does, falls_through=False, leaves=True),
    ControlOp("EXECUTE", "( xt -- ) run the word xt", run_execute, gen_execute, leaves=True,
              takes=1, calls=True),
]
BY_NAME = {op.name: op for op in OPS}
