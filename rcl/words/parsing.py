"""Parsing and the input source: comments, WORD, PARSE, FIND, SOURCE,
REFILL, EVALUATE, SAVE-INPUT, number conversion words, string words."""
from rcl.errors import ForthError
from rcl.forth.dictionary import IMMEDIATE
from rcl.forth.memory import MASK, signed
from rcl.forth.numbers import convert, digit
from rcl.forth.primitives import CALL, prim
from rcl.words.core import pop2, push2


@prim("(", "( -- ) comment up to ); in a file it may span lines", immediate=True)
def paren(m):
    if m.src.kind == "file" and not m.memory.fetch(m.a_blk):
        m.parse_multiline(ord(")"))
    else:
        m.parse(ord(")"))


prim("(S", "( -- ) stack comment, as (", immediate=True)(paren)


@prim("\\", "( -- ) comment to the end of the line (of the 64-column line in a block)",
      immediate=True)
def backslash(m):
    if m.memory.fetch(m.a_blk):
        m.memory.store(m.a_in, (m.memory.fetch(m.a_in) + 63) & ~63)
    else:
        m.memory.store(m.a_in, m.source()[1])


@prim("\\S", "( -- ) stop interpreting the current screen or file", immediate=True)
def backslash_s(m):
    m.memory.store(m.a_in, m.source()[1])
    if m.src.kind == "file" and not m.memory.fetch(m.a_blk):
        m.src.text = []


@prim("WORD", "( c -- addr ) parse a c-delimited word to a counted string at HERE")
def word(m):
    c = m.s.pop() & 0xFF
    addr, length = m.source()
    i = m.memory.fetch(m.a_in)
    mem = m.mem
    blank = c == 32
    while i < length and (mem[(addr + i) & MASK] == c or (blank and mem[(addr + i) & MASK] < 32)):
        i += 1
    m.memory.store(m.a_in, i)
    a, n = m.parse(c) if not blank else _parse_blank(m)
    data = m.memory.read(a, min(n, 255))
    h = m.dictionary.here
    m.memory.write(h, bytes([len(data)]) + data + b" ")
    m.s.append(h)


def _parse_blank(m):
    addr, length = m.source()
    i = start = m.memory.fetch(m.a_in)
    while i < length and m.mem[(addr + i) & MASK] > 32:
        i += 1
    m.memory.store(m.a_in, i + 1 if i < length else i)
    return (addr + start) & MASK, i - start


@prim("PARSE", "( c -- addr u ) text up to c")
def parse(m):
    m.s.extend(m.parse(m.s.pop() & 0xFF))


@prim("PARSE-NAME", "( -- addr u ) the next blank-delimited name")
def parse_name(m):
    name, a = m.parse_name()
    m.s.extend((a, len(name)))


@prim("SOURCE", "( -- addr u ) the current input")
def source(m):
    m.s.extend(m.source())


@prim("SOURCE-ID", "( -- id ) 0 terminal, -1 EVALUATE, else a file")
def source_id(m):
    m.s.append(m.src.source_id & MASK)


@prim("TIB", "( -- addr ) the terminal input buffer")
def tib(m):
    m.s.append(m.sources[0].buf)


@prim("QUERY", "( -- ) read a line from the terminal into TIB", kind=CALL)
def query(m):
    from rcl.words.io import read_line
    m.sources[0].lines = iter([read_line(m)])
    while len(m.sources) > 1:
        m.pop_source()
    m.refill()


@prim("INTERPRET", "( -- ) interpret the rest of the current input", kind=CALL)
def interpret(m):
    m.interpret()


@prim("REFILL", "( -- f ) the next line of the input source; in a block, "
      "the next block", kind=CALL)
def refill(m):
    blk = m.memory.fetch(m.a_blk)
    if blk and m.src.kind == "block":
        from rcl.words.blocks import next_block_source
        ok = blk + 1 < m.blocks.count
        if ok:
            next_block_source(m, blk)
        m.s.append(MASK if ok else 0)
        return
    m.s.append(MASK if m.refill() else 0)


@prim("SAVE-INPUT", "( -- x1 x2 x3 n ) the input position: >IN, line, BLK")
def save_input(m):
    src = m.src
    m.s.extend((m.memory.fetch(m.a_in), src.line & MASK, m.memory.fetch(m.a_blk), 3))


@prim("RESTORE-INPUT", "( x1 x2 x3 n -- f ) go back to a saved position")
def restore_input(m):
    n = m.s.pop()
    vals = [m.s.pop() for _ in range(n)][::-1]
    src = m.src
    if n != 3 or (vals[1] != src.line & MASK and src.text is None) \
            or (vals[2] != 0) != (src.kind == "block"):
        m.s.append(MASK)
        return
    if vals[2]:                              # a block: that block again
        m.blocks.block(vals[2])
        m.memory.store(m.a_blk, vals[2])
    if vals[1] != src.line & MASK:           # a file: go back to that line
        src.line = vals[1] - 1
        m.refill()
    m.memory.store(m.a_in, vals[0])
    m.s.append(0)


@prim("EVALUATE", "( addr u -- ) interpret the string", kind=CALL)
def evaluate(m):
    u, a = m.s.pop(), m.s.pop()
    m.evaluate_string(a, u)


@prim("FIND", "( addr -- addr 0 | xt 1 | xt -1 ) look up a counted string")
def find(m):
    a = m.s[-1]
    name = m.memory.text((a + 1) & MASK, m.mem[a])
    hit = m.dictionary.find(name) if name else None
    if hit is None:
        m.s.append(0)
    else:
        m.s[-1] = hit[0]
        m.s.append(1 if hit[1] else MASK)


@prim("DIGIT", "( c base -- n true | c false )")
def digit_word(m):
    base, c = m.s.pop(), m.s.pop()
    d = digit(chr(c).upper(), base)
    m.s.extend((c, 0) if d is None else (d, MASK))


@prim(">NUMBER", "( ud addr u -- ud' addr' u' ) convert digits while they last")
def to_number(m):
    s = m.s
    u, a = s.pop(), s.pop()
    ud = pop2(s)
    base = m.memory.fetch(m.a_base)
    while u and not u & 0x8000:
        d = digit(chr(m.mem[a]).upper(), base)
        if d is None:
            break
        ud = (ud * base + d) & 0xFFFFFFFF
        a, u = (a + 1) & MASK, u - 1
    push2(s, ud)
    s.extend((a, u))


@prim("CONVERT", "( ud addr -- ud' addr' ) F83: convert digits after addr")
def convert_word(m):
    a = (m.s.pop() + 1) & MASK
    m.s.extend((a, 255))
    to_number(m)
    m.s.pop()


@prim("NUMBER?", "( addr -- d f ) convert a counted string, DPL set (F83)")
def number_q(m):
    a = m.s.pop()
    n = convert(m.memory.text((a + 1) & MASK, m.mem[a]), m.memory.fetch(m.a_base))
    if n is None or not n.ok:
        m.s.extend((0, 0, 0))
        return
    m.memory.store(m.a_dpl, n.dpl & MASK)
    push2(m.s, n.value)
    m.s.append(MASK)


@prim("NUMBER", "( addr -- d ) convert a counted string or abort with ?")
def number(m):
    a = m.s[-1]
    number_q(m)
    if not m.s.pop():
        m.s.pop()
        m.s.pop()
        raise ForthError(-13, "?", m.memory.text((a + 1) & MASK, m.mem[a]).upper())


# ---------------------------------------------------------------- strings
@prim("/STRING", "( addr u n -- addr+n u-n )")
def slash_string(m):
    n, u, a = signed(m.s.pop()), m.s.pop(), m.s.pop()
    m.s.extend(((a + n) & MASK, (u - n) & MASK))


@prim("-TRAILING", "( addr u -- addr u' ) without trailing blanks")
def minus_trailing(m):
    u, a = m.s.pop(), m.s[-1]
    while u and m.mem[(a + u - 1) & MASK] == 32:
        u -= 1
    m.s.append(u)


@prim("COMPARE", "( a1 u1 a2 u2 -- n ) -1, 0 or 1")
def compare(m):
    u2, a2, u1, a1 = m.s.pop(), m.s.pop(), m.s.pop(), m.s.pop()
    x, y = m.memory.read(a1, u1), m.memory.read(a2, u2)
    m.s.append(0 if x == y else (MASK if x < y else 1))


@prim("SEARCH", "( a1 u1 a2 u2 -- a3 u3 f ) find string 2 in string 1")
def search(m):
    u2, a2, u1, a1 = m.s.pop(), m.s.pop(), m.s.pop(), m.s.pop()
    i = m.memory.read(a1, u1).find(m.memory.read(a2, u2))
    if i < 0:
        m.s.extend((a1, u1, 0))
    else:
        m.s.extend(((a1 + i) & MASK, u1 - i, MASK))


@prim("UPPER", "( addr u -- ) upper-case the string in place")
def upper(m):
    u, a = m.s.pop(), m.s.pop()
    m.memory.write(a, m.memory.read(a, u).upper())


@prim("IMMEDIATE?", "( xt -- f ) is the word immediate?")
def immediate_q(m):
    xt = m.s.pop()
    m.s.append(MASK if m.dictionary.flags((xt - 2) & MASK) & IMMEDIATE else 0)
