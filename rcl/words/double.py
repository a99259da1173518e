"""Double-number primitives: two cells, the high cell on top.

A double is handled in Python as one 32-bit unsigned int (pop2/push2).
"""
from rcl.forth.memory import MASK, signed
from rcl.forth.primitives import HELPERS, prim
from rcl.words.core import m_divmod, pop2, push2

D_MASK = 0xFFFFFFFF


def ds(d):
    """An unsigned 32-bit value as signed."""
    return d - (1 << 32) if d & 0x80000000 else d


HELPERS.update(DS=ds)        # a 32-bit value as signed, for templates


def _d2(op):
    """( d1 d2 -- d3 )"""
    def f(m):
        b, a = pop2(m.s), pop2(m.s)
        push2(m.s, op(a, b) & D_MASK)
    return f


def _d1(op):
    """( d -- d' )"""
    def f(m):
        push2(m.s, op(pop2(m.s)) & D_MASK)
    return f


def _dflag2(test):
    def f(m):
        b, a = pop2(m.s), pop2(m.s)
        m.s.append(MASK if test(a, b) else 0)
    return f


def _dflag1(test):
    def f(m):
        m.s.append(MASK if test(pop2(m.s)) else 0)
    return f


# Inline templates of the doubles the control word uses every tick: cells
# a b (d1, high cell b) and c d (d2); a 32-bit result's cells are its
# low 16 bits and, shifted, its high 16 (two's complement either way).
D1, D2 = "((b << 16) | a)", "((d << 16) | c)"
prim("D+", "( d1 d2 -- d3 )", inline=("a b c d", (
    "(a + c) & 0xFFFF", "((%s + %s) >> 16) & 0xFFFF" % (D1, D2))))(None)
prim("D-", "( d1 d2 -- d3 )", inline=("a b c d", (
    "(a - c) & 0xFFFF", "((%s - %s) >> 16) & 0xFFFF" % (D1, D2))))(None)
prim("DMIN", "( d1 d2 -- d3 )")(_d2(lambda a, b: a if ds(a) < ds(b) else b))
prim("DMAX", "( d1 d2 -- d3 )")(_d2(lambda a, b: a if ds(a) > ds(b) else b))
prim("DNEGATE", "( d -- -d )", inline=("a b", (
    "-a & 0xFFFF", "(-%s >> 16) & 0xFFFF" % D1)))(None)
prim("DABS", "( d -- ud )")(_d1(lambda a: abs(ds(a))))
prim("D2*", "( d -- 2d )")(_d1(lambda a: a << 1))
prim("D2/", "( d -- d/2 ) arithmetic")(_d1(lambda a: ds(a) >> 1))
prim("D=", "( d1 d2 -- f )", inline=("a b c d", (
    "0xFFFF if a == c and b == d else 0",)))(None)
prim("D<>", "( d1 d2 -- f )")(_dflag2(lambda a, b: a != b))
prim("D<", "( d1 d2 -- f ) signed", inline=("a b c d", (
    "0xFFFF if DS(%s) < DS(%s) else 0" % (D1, D2),)))(None)
prim("D>", "( d1 d2 -- f ) signed")(_dflag2(lambda a, b: ds(a) > ds(b)))
prim("DU<", "( ud1 ud2 -- f )")(_dflag2(lambda a, b: a < b))
prim("DU>", "( ud1 ud2 -- f )")(_dflag2(lambda a, b: a > b))
prim("D0=", "( d -- f )")(_dflag1(lambda a: a == 0))
prim("D0<", "( d -- f )")(_dflag1(lambda a: a & 0x80000000))


@prim("S>D", "( n -- d ) sign-extend")
def s_to_d(m):
    m.s.append(MASK if m.s[-1] & 0x8000 else 0)


@prim("D>S", "( d -- n ) the low cell")
def d_to_s(m):
    m.s.pop()


prim("?DNEGATE", "( d n -- d' ) negate d if n < 0", inline=("a b c", (
    "-a & 0xFFFF if c & 0x8000 else a", "(-%s >> 16) & 0xFFFF if c & 0x8000 else b" % D1)))(None)


@prim("?NEGATE", "( n1 n2 -- n3 ) negate n1 if n2 < 0")
def q_negate(m):
    if m.s.pop() & 0x8000:
        m.s[-1] = -m.s[-1] & MASK


prim("M+", "( d n -- d' )", inline=("a b c", (
    "(a + c) & 0xFFFF", "((%s + (c - 0x10000 if c & 0x8000 else c)) >> 16) & 0xFFFF" % D1)))(None)


@prim("M/", "( d n -- quot ) floored (RCL support)")
def m_slash(m):
    s = m.s
    n, hi, lo = s.pop(), s.pop(), s.pop()
    s.append(m_divmod(lo, hi, n)[1])


@prim("M*/", "( d n1 +n2 -- d' ) d*n1/n2 with a 48-bit intermediate, floored")
def m_star_slash(m):
    s = m.s
    n2, n1 = signed(s.pop()), signed(s.pop())
    d = ds(pop2(s))
    push2(s, (d * n1 // n2 if n2 else -1) & D_MASK)


@prim("UD/MOD", "( ud u -- urem udquot )")
def ud_slash_mod(m):
    u = m.s.pop()
    ud = pop2(m.s)
    if u == 0:
        m.s.extend((MASK, MASK, MASK))
        return
    q, r = divmod(ud, u)
    m.s.append(r)
    push2(m.s, q & D_MASK)
