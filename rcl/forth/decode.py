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

What the compiler does with each kind of instruction is its kind's
(compile_kinds.py). Also here: how deep the inlined calls of a block take
the return stack (`call_depth`, for their overflow check).
"""
from rcl.forth import compile_kinds as kinds
from rcl.forth.inner import CONTROL_BY_CF, N, decode_args
from rcl.forth.memory import DICT_LIMIT, DICT_START, MASK, PRIM_LIMIT
from rcl.forth.primitives import CALL, DEFAULT_COST, LITERAL, REGISTRY, RUNTIME, SIMPLE

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
    """One decoded cell of threaded code; `kind` says what the compiler
    does with it (compile_kinds.py), `op` is the kind's name."""
    __slots__ = ("addr", "xt", "kind", "args", "next", "target", "cost", "prim")

    def __init__(self, addr, xt, kind, args, nxt, cost, prim=None, target=None):
        self.addr, self.xt, self.kind, self.args = addr, xt, kind, args
        self.next, self.cost, self.prim, self.target = nxt, cost, prim, target

    @property
    def op(self):
        return self.kind.name


NO_TERMINATOR = Instr(0, 0, kinds.FALL, (), 0, 0)   # a block that just runs into the next

# A CONSTANT's value is compiled in (its cell watched); a VALUE's is read.
RUNTIME_KINDS = {N["(DOCOL)"]: kinds.COLON, N["(DOVAR)"]: kinds.VAR, N["(DOCON)"]: kinds.CONST,
                 N["(DOVALUE)"]: kinds.CON, N["(DO2CON)"]: kinds.TWO_CON,
                 N["(DO2VALUE)"]: kinds.TWO_CON, N["(DODEFER)"]: kinds.DEFER}
# A primitive's declared kind (primitives.py) -> its cell's, but for runtimes
PRIM_KINDS = {SIMPLE: kinds.SIMPLE, CALL: kinds.CALL}


def decode(m, ip):
    """Decode the instruction at ip into an Instr."""
    fetch = m.memory.fetch
    xt = fetch(ip)
    nxt = (ip + 2) & MASK
    cf = fetch(xt)
    if cf >= PRIM_LIMIT:
        return Instr(ip, xt, kinds.DOES, (cf,), nxt, m.cost[N["(DOCOL)"]])
    p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
    if p is None:
        return Instr(ip, xt, kinds.BAD, (), nxt, DEFAULT_COST)
    cost = m.cost[cf]
    op = CONTROL_BY_CF.get(cf)
    if op is not None:
        target = None
        if op.target:
            target = fetch(nxt)
            nxt = (nxt + 2) & MASK
        return Instr(ip, xt, kinds.CONTROL[op.name], (), nxt, cost, p, target)
    if p.kind is LITERAL:
        args, nxt = decode_args(m, p, nxt)
        return Instr(ip, xt, kinds.LITERAL, args, nxt, cost, p)
    if p.kind is RUNTIME:
        body = (xt + 2) & MASK
        return Instr(ip, xt, RUNTIME_KINDS.get(cf, kinds.RUNTIME_CALL), (body,), nxt, cost, p)
    return Instr(ip, xt, PRIM_KINDS[p.kind], (), nxt, cost, p)


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
            if ins.kind is kinds.COLON:
                inline(m, ins)
            code[ip] = ins
            if ins.target is not None:
                targets.add(ins.target)
                todo.append(ins.target)
            if ins.kind.ends_block:
                targets.add(ins.next)
            if not ins.kind.falls_through:
                break
            ip = ins.next
    return code, targets


def inline(m, ins, depth=1):
    """Make the colon call ins an "inline" instruction if its callee is
    small and straight; -> whether it did."""
    body = callee(m, ins.args[0], depth)
    if body is None:
        return False
    enter = Instr(ins.addr, ins.xt, kinds.INLINE_ENTER, (ins.next,), ins.next, ins.cost)
    ins.kind, ins.args = kinds.INLINE, (ins.args[0], (enter,) + tuple(body))
    return True


def callee(m, addr, depth):
    """The instructions of the colon body at addr, ending with its "exit",
    or None if it is not worth inlining or might look at the return stack."""
    out, ip = [], addr
    while len(out) < INLINE_LIMIT:
        ins = decode(m, ip)
        if ins.op == "EXIT":
            out.append(Instr(ins.addr, ins.xt, kinds.INLINE_EXIT, (), ins.next, ins.cost))
            return out
        if ins.kind is kinds.COLON and depth < INLINE_DEPTH and inline(m, ins, depth + 1):
            out.extend(ins.args[1])
        elif not ins.kind.plain(ins):
            return None
        else:
            out.append(ins)
        ip = ins.next
    return None


def stack_need(ops):
    """How many cells the ops of one block take from below the data
    stack's depth at the block's start, as far as that is known before the
    block runs (up to the first Python code the compiler cannot see into:
    a block checks again after it, Gen.python_call)."""
    depth = low = 0
    for i in ops:
        effect = i.kind.stack_effect(i)
        if effect is None:
            break
        taken, left = effect
        low = min(low, depth - taken)
        depth += left - taken
    return -low


def call_depth(ops):
    """How deep the inlined calls among ops (one block) take the return
    stack beyond its depth at the block's start, as far as that is known
    before the block runs (up to the first Python code: calls after it are
    checked where they are, Gen.call_check); None if none is."""
    depth, deepest = 0, None
    for i in ops:
        grow = i.kind.rs_growth(i)
        if grow is None:
            break
        depth += grow
        if i.kind is kinds.INLINE_ENTER:
            deepest = depth if deepest is None else max(deepest, depth)
    return deepest
