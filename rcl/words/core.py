"""Core primitives: literals, stack, arithmetic, comparison (memory and
dictionary space are in memory_access.py).

Each is a CODE word: a few lines of Python on the data stack `m.s` (cells
kept unsigned, 0..65535), or an inline template the compiler pastes into
compiled code and the interpreter's function is made from
(`prim(..., inline=...)(None)`: no Python body; see rcl/forth/primitives.py
for the template form).
"""
from rcl.forth.memory import MASK, signed
from rcl.forth.compiler import HELPERS, WIDE_DPL
from rcl.forth.control import DROP_FRAME, FRAME_CELLS, INDEX, LIMIT, frame_cell, index_of
from rcl.forth.primitives import BY_NAME, LITERAL, prim

T = "0xFFFF"                   # a true flag


def push2(s, d):
    """Push a 32-bit value as a double (low cell, then high cell)."""
    s.append(d & MASK)
    s.append((d >> 16) & MASK)


def pop2(s):
    """Pop a double -> unsigned 32-bit int."""
    hi = s.pop()
    return (hi << 16) | s.pop()


# ------------------------------------------------------------------ literals
def _lit_decode_rd(m, ip):
    f = m.memory.fetch
    return (f(ip), f(ip + 2), f(ip + 4)), (ip + 6) & MASK


@prim("LIT", "( -- n ) push the inline cell", kind=LITERAL, args=1)
def lit(m, n):
    m.s.append(n)


@prim("(RLIT)", "( -- n ) push the inline cell, DPL := -1 (RCL literal)",
      kind=LITERAL, args=1)
def rlit(m, n):
    m.s.append(n)
    m.memory.store(m.a_dpl, MASK)
    m.memory.store(m.a_wide, 0)


@prim("(RWLIT)", "( -- n ) push the inline cell, DPL := -1, WIDE-NUMBER on: "
      "a literal typed beyond a signed cell (RCL literal)", kind=LITERAL, args=1)
def rwlit(m, n):
    m.s.append(n)
    m.memory.store(m.a_dpl, MASK)
    m.memory.store(m.a_wide, MASK)


@prim("(RDLIT)", "( -- d ) push the inline double, DPL := its compile-time DPL",
      kind=LITERAL, args=3)
def rdlit(m, lo, hi, dpl):
    m.s.extend((lo, hi))
    m.memory.store(m.a_dpl, dpl)
    m.memory.store(m.a_wide, 0)


# What the compiler pushes and the DPL it restores (WIDE_DPL: -1 with
# WIDE-NUMBER on).
BY_NAME["LIT"].extra["lit"] = lambda a: ((a[0],), None)
BY_NAME["(RLIT)"].extra["lit"] = lambda a: ((a[0],), -1)
BY_NAME["(RWLIT)"].extra["lit"] = lambda a: ((a[0],), WIDE_DPL)
BY_NAME["(RDLIT)"].extra["lit"] = lambda a: ((a[0], a[1]), signed(a[2]))


# --------------------------------------------------------------------- stack
prim("DUP", "( x -- x x )", inline=("a", ("a", "a")))(None)
prim("DROP", "( x -- )", inline=("a", ()))(None)
prim("SWAP", "( a b -- b a )", inline=("a b", ("b", "a")))(None)
prim("OVER", "( a b -- a b a )", inline=("a b", ("a", "b", "a")))(None)
prim("ROT", "( a b c -- b c a )", inline=("a b c", ("b", "c", "a")))(None)
prim("-ROT", "( a b c -- c a b )", inline=("a b c", ("c", "a", "b")))(None)
prim("NIP", "( a b -- b )", inline=("a b", ("b",)))(None)
prim("TUCK", "( a b -- b a b )", inline=("a b", ("b", "a", "b")))(None)


@prim("?DUP", "( x -- 0 | x x )")
def qdup(m):
    if m.s[-1]:
        m.s.append(m.s[-1])


@prim("PICK", "( xu ... x0 u -- xu ... x0 xu ) 0 PICK is DUP")
def pick(m):
    s = m.s
    u = s.pop()
    if u >= len(s):
        raise IndexError
    s.append(s[-1 - u])


@prim("ROLL", "( xu ... x0 u -- xu-1 ... x0 xu )")
def roll(m):
    s = m.s
    u = signed(s.pop())
    if u >= len(s):
        raise IndexError
    if u > 0:
        s.append(s.pop(-1 - u))


@prim("DEPTH", "( -- n ) cells on the data stack")
def depth(m):
    m.s.append(len(m.s) & MASK)


prim("2DUP", "( a b -- a b a b )", inline=("a b", ("a", "b", "a", "b")))(None)
prim("2DROP", "( a b -- )", inline=("a b", ()))(None)
prim("2SWAP", "( a b c d -- c d a b )", inline=("a b c d", ("c", "d", "a", "b")))(None)
prim("2OVER", "( a b c d -- a b c d a b )",
     inline=("a b c d", ("a", "b", "c", "d", "a", "b")))(None)


@prim("2ROT", "( a b c d e f -- c d e f a b )")
def two_rot(m):
    s = m.s
    if len(s) < 6:
        raise IndexError
    s[-6:] = s[-4:] + s[-6:-4]


@prim("3DUP", "( a b c -- a b c a b c )")
def three_dup(m):
    if len(m.s) < 3:
        raise IndexError
    m.s.extend(m.s[-3:])


@prim("4DUP", "( a b c d -- a b c d a b c d )")
def four_dup(m):
    if len(m.s) < 4:
        raise IndexError
    m.s.extend(m.s[-4:])


# -------------------------------------------------------------- return stack
prim(">R", "( x -- ) R: ( -- x )", inline=("a", (), "rs.append(a)"))(None)
prim("R>", "( -- x ) R: ( x -- )", inline=("", ("rs.pop()",)))(None)
prim("R@", "( -- x ) R: ( x -- x )", inline=("", ("rs[-1]",)))(None)
prim("2>R", "( a b -- ) R: ( -- a b )", inline=("a b", (), "rs.append(a); rs.append(b)"))(None)


@prim("2R>", "( -- a b ) R: ( a b -- )")
def two_r_from(m):
    b, a = m.rs.pop(), m.rs.pop()
    m.s.extend((a, b))


@prim("2R@", "( -- a b ) R: ( a b -- a b )")
def two_r_fetch(m):
    if len(m.rs) < 2:
        raise IndexError
    m.s.extend(m.rs[-2:])


prim("I", "( -- n ) the innermost loop index",
     inline=("", (index_of(frame_cell(INDEX), frame_cell(LIMIT)),)))(None)
prim("J", "( -- n ) the next outer loop index",
     inline=("", (index_of(frame_cell(INDEX, 1), frame_cell(LIMIT, 1)),)))(None)
prim("UNLOOP", "( -- ) R: ( loop-sys -- ) drop a DO frame before EXIT",
     inline=("", (), DROP_FRAME))(None)


# ----------------------------------------------------------------- arithmetic
def binary(name, effect, expr):
    """Declare a ( n1 n2 -- n3 ) word from one expression over a and b."""
    prim(name, effect, inline=("a b", (expr,)))(None)


def unary(name, effect, expr):
    prim(name, effect, inline=("a", (expr,)))(None)


binary("+", "( n1 n2 -- n3 )", "(a + b) & 0xFFFF")
binary("-", "( n1 n2 -- n3 )", "(a - b) & 0xFFFF")
binary("*", "( n1 n2 -- n3 ) low 16 bits of the product", "(a * b) & 0xFFFF")
binary("AND", "( x1 x2 -- x3 )", "a & b")
binary("OR", "( x1 x2 -- x3 )", "a | b")
binary("XOR", "( x1 x2 -- x3 )", "a ^ b")
binary("LSHIFT", "( x u -- x' )", "(a << b) & 0xFFFF if b < 16 else 0")
binary("RSHIFT", "( x u -- x' ) logical", "a >> b")
binary("MIN", "( n1 n2 -- n3 ) signed", "a if (a ^ 0x8000) < (b ^ 0x8000) else b")
binary("MAX", "( n1 n2 -- n3 ) signed", "a if (a ^ 0x8000) > (b ^ 0x8000) else b")
unary("NEGATE", "( n -- -n )", "-a & 0xFFFF")
unary("NOT", "( x -- x' ) bitwise (Forth-83): 5 NOT is -6", "a ^ 0xFFFF")
unary("INVERT", "( x -- x' ) bitwise", "a ^ 0xFFFF")
unary("ABS", "( n -- u )", "(-a & 0xFFFF) if a & 0x8000 else a")
unary("1+", "( n -- n+1 )", "(a + 1) & 0xFFFF")
unary("1-", "( n -- n-1 )", "(a - 1) & 0xFFFF")
unary("2+", "( n -- n+2 )", "(a + 2) & 0xFFFF")
unary("2-", "( n -- n-2 )", "(a - 2) & 0xFFFF")
unary("2*", "( n -- 2n )", "(a << 1) & 0xFFFF")
unary("2/", "( n -- n/2 ) arithmetic shift: floors", "(a >> 1) | (a & 0x8000)")
unary("U2/", "( u -- u/2 ) logical shift", "a >> 1")
unary("CELLS", "( n -- 2n )", "(a << 1) & 0xFFFF")
unary("CELL+", "( a -- a+2 )", "(a + 2) & 0xFFFF")
unary("CHAR+", "( a -- a+1 )", "(a + 1) & 0xFFFF")
unary("CHARS", "( n -- n )", "a")
unary("ALIGNED", "( a -- a ) no alignment on the 80188", "a")

# ----------------------------------------------------------------- comparison
binary("=", "( x1 x2 -- f )", T + " if a == b else 0")
binary("<>", "( x1 x2 -- f )", T + " if a != b else 0")
binary("<", "( n1 n2 -- f ) signed", T + " if (a ^ 0x8000) < (b ^ 0x8000) else 0")
binary(">", "( n1 n2 -- f ) signed", T + " if (a ^ 0x8000) > (b ^ 0x8000) else 0")
binary("U<", "( u1 u2 -- f )", T + " if a < b else 0")
binary("U>", "( u1 u2 -- f )", T + " if a > b else 0")
unary("0=", "( x -- f )", T + " if a == 0 else 0")
unary("0<>", "( x -- f )", T + " if a != 0 else 0")
unary("0<", "( n -- f )", T + " if a & 0x8000 else 0")
unary("0>", "( n -- f )", T + " if 0 < a < 0x8000 else 0")


prim("TRUE", "( -- -1 )", inline=("", ("65535",)))(None)
prim("FALSE", "( -- 0 )", inline=("", ("0",)))(None)


@prim("BETWEEN", "( n lo hi -- f ) lo <= n <= hi, signed")
def between(m):
    s = m.s
    hi, lo, n = signed(s.pop()), signed(s.pop()), signed(s.pop())
    s.append(MASK if lo <= n <= hi else 0)


@prim("WITHIN", "( n lo hi -- f ) lo <= n < hi, on the circle (standard)")
def within(m):
    s = m.s
    hi, lo, n = s.pop(), s.pop(), s.pop()
    s.append(MASK if (n - lo) & MASK < (hi - lo) & MASK else 0)


# ------------------------------------------------------------------- division
def um_divmod(ud, u):
    """F83's UM/MOD: no trap; divide by 0 or overflow gives 0xFFFF 0xFFFF."""
    if u == 0 or (ud >> 16) >= u:
        return MASK, MASK
    q, r = divmod(ud, u)
    return r, q


HELPERS.update(UMDIV=um_divmod)


def m_divmod(lo, hi, n):
    """F83's M/MOD ( d n -- rem quot ), floored, built on UM/MOD exactly as
    kernel86.blk builds it (so overflow gives what F83 gives)."""
    if n == 0:
        return lo, hi
    d = (hi << 16) | lo
    ud = (-d & 0xFFFFFFFF) if hi & 0x8000 else d
    r, q = um_divmod(ud, -n & MASK if n & 0x8000 else n)
    if n & 0x8000:
        r = -r & MASK
    if (hi ^ n) & 0x8000:
        q = -q & MASK
        if r:
            q = (q - 1) & MASK
            r = (n - r) & MASK
    return r, q


prim("UM*", "( u1 u2 -- ud )", inline=("a b", ("(a * b) & 0xFFFF", "(a * b) >> 16")))(None)


@prim("*D", "( n1 n2 -- d ) signed 16x16 -> 32 (F83's name for M*)")
def star_d(m):
    s = m.s
    push2(s, signed(s.pop()) * signed(s.pop()))


prim("M*", "( n1 n2 -- d ) signed 16x16 -> 32")(star_d)


prim("UM/MOD", "( ud u -- urem uquot ) no trap: 0 or overflow gives -1 -1",
     inline=("a b c", ("UMDIV((b << 16) | a, c)[0]", "UMDIV((b << 16) | a, c)[1]")))(None)


@prim("M/MOD", "( d n -- rem quot ) floored; n = 0 leaves d as it was")
def m_slash_mod(m):
    s = m.s
    n, hi, lo = s.pop(), s.pop(), s.pop()
    s.extend(m_divmod(lo, hi, n))


@prim("MU/MOD", "( ud u -- urem udquot )")
def mu_slash_mod(m):
    s = m.s
    u, hi, lo = s.pop(), s.pop(), s.pop()
    r1, q1 = um_divmod(hi, u)
    r2, q2 = um_divmod((r1 << 16) | lo, u)
    s.extend((r2, q2, q1))


def fdiv(a, b):
    """Floored quotient of two cells, F83's way (inline helper)."""
    if b and not (a | b) & 0x8000:
        return a // b
    return m_divmod(a, MASK if a & 0x8000 else 0, b)[1]


def fmod(a, b):
    """Floored remainder of two cells, F83's way (inline helper)."""
    if b and not (a | b) & 0x8000:
        return a % b
    return m_divmod(a, MASK if a & 0x8000 else 0, b)[0]


HELPERS.update(FDIV=fdiv, FMOD=fmod)


prim("/MOD", "( n1 n2 -- rem quot ) floored", inline=("a b", ("FMOD(a, b)", "FDIV(a, b)")))(None)
prim("/", "( n1 n2 -- quot ) floored; 7 0 / is 0", inline=("a b", ("FDIV(a, b)",)))(None)
prim("MOD", "( n1 n2 -- rem ) floored; 7 0 MOD is 7", inline=("a b", ("FMOD(a, b)",)))(None)


@prim("*/MOD", "( n1 n2 n3 -- rem quot ) 32-bit intermediate, floored")
def star_slash_mod(m):
    s = m.s
    n3 = s.pop()
    d = (signed(s.pop()) * signed(s.pop())) & 0xFFFFFFFF
    s.extend(m_divmod(d & MASK, d >> 16, n3))


@prim("*/", "( n1 n2 n3 -- quot )")
def star_slash(m):
    star_slash_mod(m)
    del m.s[-2]


@prim("FM/MOD", "( d n -- rem quot ) floored (standard)")
def fm_slash_mod(m):
    s = m.s
    n, d = s.pop(), pop2(s)
    s.extend(m_divmod(d & MASK, d >> 16, n))


@prim("SM/REM", "( d n -- rem quot ) symmetric (standard)")
def sm_slash_rem(m):
    s = m.s
    n, d = signed(s.pop()), pop2(s)
    d = d - (1 << 32) if d & 0x80000000 else d
    if n == 0:
        s.extend((MASK, MASK))
        return
    q = abs(d) // abs(n) * (1 if (d < 0) == (n < 0) else -1)
    s.extend(((d - q * n) & MASK, q & MASK))
