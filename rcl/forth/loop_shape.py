"""The shape of a DO loop's body: IF ... ELSE ... THEN and BEGIN loops
found again in the jumps between its blocks, so that the compiler can
write them as Python `if` and `while` (compile_loops.py) instead of going
from block to block through guards.

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
