"""Memory and dictionary-space primitives: @ ! C@ C! and friends, FILL and
MOVE, HERE ALLOT , C, PAD.

Stores go through memory.Memory (or, inlined, check `watch`), so a store
into compiled code or a header is seen.
"""
from rcl.forth.memory import MASK, signed
from rcl.forth.primitives import prim

# --------------------------------------------------------------------- memory
FETCH = "mem[a] | (mem[(a + 1) & 0xFFFF] << 8)"


def cell_store(x, a):
    """An inline template's text storing cell x at address a (names, or
    parenthesised expressions), a store into watched memory seen."""
    return ("mem[{a}] = {x} & 0xFF; mem[({a} + 1) & 0xFFFF] = {x} >> 8\n"
            "if W[{a}] or W[({a} + 1) & 0xFFFF]: m.watched({a})").format(x=x, a=a)


STORE = cell_store("a", "b")


prim("@", "( addr -- x )", inline=("a", (FETCH,)), memory=True)(None)
prim("!", "( x addr -- )", inline=("a b", (), STORE), memory=True)(None)
prim("C@", "( addr -- c )", inline=("a", ("mem[a]",)), memory=True)(None)
prim("C!", "( c addr -- )", inline=("a b", (), "mem[b] = a & 0xFF\nif W[b]: m.watched(b)"),
     memory=True)(None)


@prim("+!", "( n addr -- ) add n to the cell at addr", memory=True)
def plus_store(m):
    a = m.s.pop()
    m.memory.store(a, (m.memory.fetch(a) + m.s.pop()) & MASK)


prim("2@", "( addr -- d ) high cell at addr", memory=True,
     inline=("a", ("mem[(a + 2) & 0xFFFF] | (mem[(a + 3) & 0xFFFF] << 8)", FETCH)))(None)
prim("2!", "( d addr -- ) high cell at addr", memory=True,
     inline=("a b c", (), cell_store("b", "c") + "\n" + cell_store("a", "((c + 2) & 0xFFFF)")))(None)
prim("ON", "( addr -- ) store -1", memory=True, inline=("a", (), cell_store("0xFFFF", "a")))(None)
prim("OFF", "( addr -- ) store 0", memory=True, inline=("a", (), cell_store("0", "a")))(None)


def _span(m, n):
    """A byte count from the stack. A count with the top bit set (a negative
    number) moves nothing: on the 80188 it would wipe the whole segment,
    dictionary included, which no program means to do."""
    return 0 if n & 0x8000 else n


@prim("FILL", "( addr u c -- )")
def fill(m):
    s = m.s
    c, u, a = s.pop(), s.pop(), s.pop()
    m.memory.write(a, bytes([c & 0xFF]) * _span(m, u))


@prim("ERASE", "( addr u -- )")
def erase(m):
    s = m.s
    u, a = s.pop(), s.pop()
    m.memory.write(a, bytes(_span(m, u)))


@prim("BLANK", "( addr u -- )")
def blank(m):
    s = m.s
    u, a = s.pop(), s.pop()
    m.memory.write(a, b" " * _span(m, u))


@prim("CMOVE", "( from to u -- ) byte by byte, low addresses first")
def cmove(m):
    s = m.s
    u, to, frm = _span(m, s.pop()), s.pop(), s.pop()
    if frm < to < frm + u:                 # overlapping: propagate like F83
        for i in range(u):
            m.memory.cstore((to + i) & MASK, m.mem[(frm + i) & MASK])
    else:
        m.memory.write(to, m.memory.read(frm, u))


@prim("CMOVE>", "( from to u -- ) byte by byte, high addresses first")
def cmove_up(m):
    s = m.s
    u, to, frm = _span(m, s.pop()), s.pop(), s.pop()
    if to < frm < to + u:
        for i in reversed(range(u)):
            m.memory.cstore((to + i) & MASK, m.mem[(frm + i) & MASK])
    else:
        m.memory.write(to, m.memory.read(frm, u))


@prim("MOVE", "( from to u -- ) as if through a buffer")
def move(m):
    s = m.s
    u, to, frm = _span(m, s.pop()), s.pop(), s.pop()
    m.memory.write(to, m.memory.read(frm, u))


prim("COUNT", "( addr -- addr+1 u )", inline=("a", ("(a + 1) & 0xFFFF", "mem[a]")),
     memory=True)(None)


# ----------------------------------------------------------------- dictionary
@prim("HERE", "( -- addr ) next free byte of the dictionary")
def here(m):
    m.s.append(m.dictionary.here)


@prim("PAD", "( -- addr ) scratch area above HERE")
def pad(m):
    from rcl.forth.memory import PAD_OFFSET
    m.s.append((m.dictionary.here + PAD_OFFSET) & MASK)


@prim("ALLOT", "( n -- ) reserve n bytes")
def allot(m):
    m.dictionary.allot(signed(m.s.pop()))


@prim(",", "( x -- ) compile a cell")
def comma(m):
    m.dictionary.comma(m.s.pop())


@prim("C,", "( c -- ) compile a byte")
def c_comma(m):
    m.dictionary.ccomma(m.s.pop())


@prim("ALIGN", "( -- ) nothing to align on the 80188")
def align(m):
    pass


@prim("UNUSED", "( -- u ) bytes left in the dictionary")
def unused(m):
    from rcl.forth.memory import PAD_OFFSET
    limit = m.heap_floor      # the heap's floor (DICT_LIMIT when empty)
    m.s.append(max(0, limit - PAD_OFFSET - m.dictionary.here))


prim("NOOP", "( -- )", inline=("", ()))(None)
