"""What a DO loop of several blocks is, for the compiler to write it as one
Python `while` (compile_loops.py explains that form).

`find_regions` picks the loops: a body of blocks that jump only among
themselves (BRANCH, ?BRANCH), hold only `loop_op`s (no call left in, no
Python primitive, the return stack touched only as I and J), are entered
only at their start, and leave the data stack as deep at each block
whichever way it was reached. Its `Region` says how many cells each block
finds in locals (`carry`: every cell above the body's lowest point) and,
for each head (the loop's start, each BEGIN), the most clock the body can
spend before the next head (`heads`: the compiler's `_w` check).

`shape` finds IF ... ELSE ... THEN and BEGIN loops again in the jumps
between the blocks, so that they become Python `if` and `while` instead of
going from block to block through guards.

`shape(jumps, first, last)` gets, for each block k of the body first..last-1
(the loop's own (LOOP) block, `last`, is not part of it), `jumps[k] =
(op, j)`: op None (the block runs into k+1), "BRANCH" or "?BRANCH" (a jump
to block j; ?BRANCH goes on at k+1 when its flag is non-zero). It returns a
list of nodes, or None when the jumps make no shape Python can say:

    ("block", k)            block k's code (a ?BRANCH block leaves its flag in _f)
    ("if", then, else)      if _f: then  else: else (None: no else)
    ("unless", "break")     if not _f: break  (WHILE; "continue": UNTIL)
    ("stmt", "continue")    the end of a REPEAT or AGAIN ("break": a jump out)
    ("loop", nodes)         while True: nodes, then break (a BEGIN loop)

For example `DO  IF A ELSE B THEN  BEGIN C WHILE D REPEAT  LOOP`:

    [("block", 0), ("if", [("block", 1)], [("block", 2)]),
     ("loop", [("block", 3), ("unless", "break"), ("block", 4), ("stmt", "continue")])]
"""

CARRY_LIMIT = 8                  # stack cells a loop of several blocks keeps in locals
INSIDE = ("?BRANCH", "BRANCH")   # the control operations allowed inside such a loop


def stack_effect(ins):
    """(cells taken, cells left) on the data stack by an instruction a loop
    body may hold (loop_op), or by a terminator (None: none)."""
    return (0, 0) if ins is None else ins.kind.stack_effect(ins)


def loop_op(i):
    """May instruction i be in a loop body run as a Python while? Only what
    is known not to look at the loop frame, the clock or the real stack
    (its kind says: compile_kinds.py)."""
    return i.kind.loop_op(i)


class Region:
    """A DO loop whose body is blocks first..last, as one Python while:
    `carry[k]` stack cells are in locals _k0.. when block k starts, `after[k]`
    when its primitives are done; at a head (the loop's start, a BEGIN's)
    `heads[k]` is the clock the body may spend before the next head."""

    def __init__(self, first, last, carry, after, heads, uses_i):
        self.first, self.last, self.carry, self.after = first, last, carry, after
        self.heads, self.uses_i = heads, uses_i


def find_regions(blocks, index):
    """{first block: Region} for the DO loops of several blocks that can
    run as a Python while (blocks: (addr, ops, terminator, next) each;
    index: block number by address)."""
    regions = {}
    for last, (_, _, term, _) in enumerate(blocks):
        if term is None or term.op not in ("(LOOP)", "(+LOOP)"):
            continue
        first = index.get(term.target)
        if first is None or first >= last:
            continue
        r = region(blocks, index, first, last)
        if r is not None:
            regions[first] = r
    return regions

def successors(blocks, index, k):
    """The blocks block k may go on at, or None if it may leave some other way."""
    _, _, term, _ = blocks[k]
    if term is None:
        return [k + 1]
    if term.op not in INSIDE:
        return None
    j = index.get(term.target)
    return [j] if term.op == "BRANCH" else [j, index.get(term.next)]

def region(blocks, index, first, last):
    """The Region of the loop first..last, or None if it cannot be one:
    a primitive that is not a loop_op, a way in but its start or out
    but its end, a stack depth that depends on the path taken."""
    succ = {last: []}
    for k in range(first, last + 1):
        if not all(loop_op(i) for i in blocks[k][1]):
            return None
        if k < last:
            succ[k] = successors(blocks, index, k)
            if succ[k] is None or not all(j is not None and first <= j <= last for j in succ[k]):
                return None
    for k, (_, _, term, _) in enumerate(blocks):
        if not first <= k <= last and term is not None and term.target is not None \
                and first < index.get(term.target, -1) <= last:
            return None
    depth, after, low, todo = {first: 0}, {}, 0, [first]
    while todo:
        k = todo.pop()
        d = depth[k]
        for i in blocks[k][1]:
            n_in, n_out = stack_effect(i)
            low = min(low, d - n_in)
            d += n_out - n_in
        after[k] = d
        n_in, _ = stack_effect(blocks[k][2])
        low = min(low, d - n_in)
        d -= n_in
        for j in succ[k] if k < last else [first]:
            if depth.setdefault(j, d) != d:
                return None
            if j not in after:
                todo.append(j)
    if len(after) != last - first + 1 or -low > CARRY_LIMIT:
        return None
    heads = {first} | {j for k in succ for j in succ[k] if j <= k}
    uses_i = any(i.prim is not None and i.prim.name == "I"
                 for k in range(first, last + 1) for i in blocks[k][1])
    return Region(first, last, {k: d - low for k, d in depth.items()},
                  {k: d - low for k, d in after.items()},
                  {h: head_span(blocks, succ, heads, h) for h in heads}, uses_i)

def head_span(blocks, succ, heads, h):
    """The most clock the body may spend from head h's start up to the
    last check of a block it reaches before the next head."""
    start, span = {h: 0}, 0
    for k in range(h, max(succ) + 1):
        if k not in start:
            continue
        ops, term = blocks[k][1], blocks[k][2]
        pre = sum(i.cost for i in ops)
        span = max(span, start[k] + pre)
        for j in succ[k]:
            if j > k and j not in heads:
                start[j] = max(start.get(j, 0), start[k] + pre + (term.cost if term else 0))
    return span


class NoShape(Exception):
    """Jumps that cross each other: the compiler keeps its guards."""


def shape(jumps, first, last):
    """The nodes of the body first..last-1, or None (see the docstring)."""
    ends = {}                       # a BEGIN's block -> the last block jumping back to it
    for k in range(first, last):
        op, j = jumps[k]
        if op is not None and j <= k:
            ends[j] = max(ends.get(j, k), k)
    try:
        return Shaper(jumps, ends).range(first, last, None, None, last)
    except NoShape:
        return None


class Shaper:
    def __init__(self, jumps, ends):
        self.jumps, self.ends = jumps, ends

    def goto(self, j, head, out, join):
        """The statement that goes to block j: continue at the head of the
        innermost BEGIN loop, break at its exit, nothing at the join."""
        if j == head:
            return "continue"
        if j == out:
            return "break"
        if j == join:
            return None
        raise NoShape

    def range(self, lo, hi, head, out, join, begin=None):
        """Nodes for blocks lo..hi-1, run in order; a jump to `head` or `out`
        continues or leaves the innermost BEGIN loop, one to `join` ends the
        range (the code after it goes on there). `begin`: lo is that loop's head."""
        nodes, k = [], lo
        while k < hi:
            if k in self.ends and k != begin:          # a BEGIN loop: k .. its last jump back
                e = self.ends[k]
                if e >= hi:
                    raise NoShape
                nodes.append(("loop", self.range(k, e + 1, k, e + 1, None, begin=k)))
                k = e + 1
                continue
            begin = None
            op, j = self.jumps[k]
            nodes.append(("block", k))
            if op is None:
                k += 1
            elif op == "BRANCH":                        # only as the range's last block
                if k != hi - 1:
                    raise NoShape
                stmt = self.goto(j, head, out, join)
                if stmt:
                    nodes.append(("stmt", stmt))
                k += 1
            elif j in (head, out):                      # UNTIL, WHILE
                nodes.append(("unless", self.goto(j, head, out, join)))
                k += 1
            elif k < j <= hi:                           # IF
                k = self.if_(k, j, hi, head, out, nodes)
            else:
                raise NoShape
        return nodes

    def if_(self, k, j, hi, head, out, nodes):
        """IF at block k, its ?BRANCH going to j: with an ELSE when the
        block before j jumps forward past it. -> where the code goes on."""
        op, u = self.jumps[j - 1] if j - 1 > k else (None, None)
        if op == "BRANCH" and j < u <= hi and u not in (head, out):
            then = self.range(k + 1, j, head, out, u)
            nodes.append(("if", then, self.range(j, u, head, out, u)))
            return u
        nodes.append(("if", self.range(k + 1, j, head, out, j), None))
        return j
