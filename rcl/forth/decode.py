"""Threaded code decoded into instructions: what the compiler sees.

`decode` turns the cell at ip into an `Instr` (its kind, inline arguments,
branch target, cost); `walk` decodes everything reachable from a
definition's entry and finds where blocks start (the entry, every branch
target, the cell after anything that ends a block).

Small colon definitions are inlined here: a call to a word whose body is a
short straight run of simple primitives ending in EXIT (and calling only
such words) does not end the block; it becomes an "inline" instruction
holding the callee's instructions between an "enter" and an "exit", which
cost what the call and the EXIT cost and, run one at a time by the exact
slow path, push and pop the return address as the real call does.

Also here: what an instruction does to the return stack (`keeps_rs`,
`call_depth`: for a locals frame kept in Python names, and for the overflow
check of inlined calls), and the slow path's functions of instructions
that have no primitive function of their own (rt_*).
"""
from rcl.forth.control import BY_NAME as CONTROL_OPS
from rcl.forth.inner import CONTROL, N, RSTACK_CELLS, decode_args
from rcl.forth.memory import DICT_LIMIT, DICT_START, MASK, PRIM_LIMIT
from rcl.forth.primitives import DEFAULT_COST, REGISTRY

# No definition has more cells than the dictionary area holds: code that
# reaches further is a run through data or empty memory (EXECUTE of a wild
# address), which the reference loop runs in the same virtual time; compiling
# its 30,000-odd cells took 7 s on CPython and 80 s on PyPy.
WALK_LIMIT = (DICT_LIMIT - DICT_START) // 2


class TooLarge(Exception):
    """Threaded code larger than any definition: not compiled."""


INLINE_LIMIT = 12            # instructions of a callee worth pasting into its caller
INLINE_DEPTH = 3             # calls nested inside inlined calls


class Instr:
    """One decoded cell of threaded code."""
    __slots__ = ("addr", "xt", "op", "args", "next", "target", "cost", "prim")

    def __init__(self, addr, xt, op, args, nxt, cost, prim=None, target=None):
        self.addr, self.xt, self.op, self.args = addr, xt, op, args
        self.next, self.cost, self.prim, self.target = nxt, cost, prim, target


NO_TERMINATOR = Instr(0, 0, None, (), 0, 0)   # a block that just runs into the next

TERMINATORS = set(CONTROL_OPS) | {"colon", "does", "defer", "call", "bad"}
NO_FALLTHROUGH = {op.name for op in CONTROL_OPS.values() if not op.falls_through}
# A CONSTANT's value is compiled in (its cell watched); a VALUE's is read.
RUNTIME_KINDS = {N["(DOCOL)"]: "colon", N["(DOVAR)"]: "var", N["(DOCON)"]: "const",
                 N["(DOVALUE)"]: "con", N["(DO2CON)"]: "2con",
                 N["(DO2VALUE)"]: "2con", N["(DODEFER)"]: "defer"}


def decode(m, ip):
    """Decode the instruction at ip into an Instr."""
    fetch = m.memory.fetch
    xt = fetch(ip)
    nxt = (ip + 2) & MASK
    cf = fetch(xt)
    if cf >= PRIM_LIMIT:
        return Instr(ip, xt, "does", (cf,), nxt, m.cost[N["(DOCOL)"]])
    p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
    if p is None:
        return Instr(ip, xt, "bad", (), nxt, DEFAULT_COST)
    cost = m.cost[cf]
    op = CONTROL.get(cf)
    if op is not None:
        target = None
        if op.target:
            target = fetch(nxt)
            nxt = (nxt + 2) & MASK
        return Instr(ip, xt, op.name, (), nxt, cost, p, target)
    if p.kind == "literal":
        args, nxt = decode_args(m, p, nxt)
        return Instr(ip, xt, "literal", args, nxt, cost, p)
    if p.kind == "runtime":
        body = (xt + 2) & MASK
        return Instr(ip, xt, RUNTIME_KINDS.get(cf, "call"), (body,), nxt, cost, p)
    return Instr(ip, xt, "call" if p.kind == "call" else "simple", (), nxt, cost, p)


def walk(m, entry):
    """All instructions reachable from entry, by address, and the addresses
    where blocks start. TooLarge if that is more than the dictionary holds."""
    code, todo, targets = {}, [entry], {entry}
    while todo:
        ip = todo.pop()
        while ip not in code:
            if len(code) >= WALK_LIMIT:
                raise TooLarge("code at %d is larger than any definition" % entry)
            ins = decode(m, ip)
            if ins.op == "colon":
                inline(m, ins)
            code[ip] = ins
            if ins.target is not None:
                targets.add(ins.target)
                todo.append(ins.target)
            if ins.op in TERMINATORS:
                targets.add(ins.next)
            if ins.op in NO_FALLTHROUGH:
                break
            ip = ins.next
    return code, targets


def inline(m, ins, depth=1):
    """Make the colon call ins an "inline" instruction if its callee is
    small and straight; -> whether it did."""
    body = callee(m, ins.args[0], depth)
    if body is None:
        return False
    enter = Instr(ins.addr, ins.xt, "enter", (ins.next,), ins.next, ins.cost)
    ins.op, ins.args = "inline", (ins.args[0], (enter,) + tuple(body))
    return True


def callee(m, addr, depth):
    """The instructions of the colon body at addr, ending with its "exit",
    or None if it is not worth inlining or might look at the return stack."""
    out, ip = [], addr
    while len(out) < INLINE_LIMIT:
        ins = decode(m, ip)
        if ins.op == "EXIT":
            out.append(Instr(ins.addr, ins.xt, "exit", (), ins.next, ins.cost))
            return out
        if ins.op == "colon" and depth < INLINE_DEPTH and inline(m, ins, depth + 1):
            out.extend(ins.args[1])
        elif not plain(ins):
            return None
        else:
            out.append(ins)
        ip = ins.next
    return None


def plain(ins):
    """Does ins only compute on the data stack and memory?"""
    if ins.op in ("var", "con", "const", "2con"):
        return True
    if ins.op == "literal":          # (not a locals frame's: never pasted elsewhere)
        return ins.prim.extra.get("lit") is not None
    t = ins.prim.template if ins.op == "simple" else None
    return t is not None and "rs" not in t.uses


def literal_template(ins):
    """The Template a literal-kind primitive makes from its inline cells
    (extra["inline_args"]: the Locals word set's rs[-k]), or None."""
    if ins.op != "literal" or "lit" in ins.prim.extra:
        return None
    make = ins.prim.extra.get("inline_args")
    return make(ins.args) if make is not None else None


def keeps_rs(ins, tpl=None):
    """Does the compiled form of ins surely leave the return stack alone
    (so that a locals frame kept in Python names need not be pushed)?"""
    if ins.op in ("var", "const", "con", "2con", "enter", "exit"):
        return True          # (an inlined call's fast path does not touch rs)
    if ins.op == "literal" and "lit" in ins.prim.extra:
        return True
    tpl = tpl or (ins.prim.template if ins.op == "simple" else None)
    return tpl is not None and "rs" not in tpl.uses


def rs_growth(ins):
    """Cells the compiled ins may push on the return stack, pops not counted
    (an inlined call: its return address; a locals frame: its cells, pushed
    or kept in Python names); None for Python code, which may do anything."""
    if ins.op in ("enter", "exit"):
        return 1 if ins.op == "enter" else -1
    if ins.op in ("var", "const", "con", "2con"):
        return 0
    extra = ins.prim.extra
    if ins.op == "literal" and ("lit" in extra or "rs_cells" in extra):
        return extra["rs_cells"](ins.args) if "rs_cells" in extra else 0
    tpl = literal_template(ins) or (ins.prim.template if ins.op == "simple" else None)
    return tpl.rs_push if tpl is not None else None


def call_depth(ops):
    """How deep the inlined calls among ops (one block) take the return
    stack beyond its depth at the block's start, as far as that is known
    before the block runs (up to the first Python code: calls after it are
    checked where they are, Gen.call_check); None if none is."""
    depth, deepest = 0, None
    for i in ops:
        grow = rs_growth(i)
        if grow is None:
            break
        depth += grow
        if i.op == "enter":
            deepest = depth if deepest is None else max(deepest, depth)
    return deepest


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
