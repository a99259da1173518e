"""Programming-Tools extensions (Forth 2012 chapter 15) that F83 lacks:
conditional compilation ([IF] [ELSE] [THEN] [DEFINED] [UNDEFINED]),
N>R NR>, SYNONYM, and name tokens (TRAVERSE-WORDLIST NAME>STRING
NAME>INTERPRET NAME>COMPILE).

A name token (nt) here is the word's xt: a header is found from its code
field (dictionary.py), so the xt names the word as well as any token could.

F83's own tools (.S ? DUMP SEE WORDS FORGET CODE AHEAD CS-PICK CS-ROLL)
are in tools.py, compiling.py and io.py; ASSEMBLER and EDITOR are
vocabularies of the kernel (rcl/kernel/03-tools.fs).
"""
from rcl.errors import ForthError
from rcl.forth import inner
from rcl.forth.dictionary import HIDDEN, IMMEDIATE
from rcl.forth.memory import MASK
from rcl.forth.primitives import CALL, REGISTRY, RUNTIME, prim
from rcl.words.compiling import parse_word, tick


# --------------------------------------------------- conditional compilation
def skip_to(m, stop_at_else):
    """Skip words, across lines, to the [ELSE] or [THEN] that matches
    (nested [IF]s skipped whole); the input ends the skip too."""
    depth = 0
    while True:
        name, _ = m.parse_name()
        if not name:
            if not m.refill():
                return
            continue
        word = name.upper()
        if word == "[IF]":
            depth += 1
        elif word == "[THEN]":
            if depth == 0:
                return
            depth -= 1
        elif word == "[ELSE]" and depth == 0 and stop_at_else:
            return


@prim("[IF]", "( f -- ) go on if f is true, else skip to the matching [ELSE] or [THEN]",
      immediate=True, kind=CALL)
def bracket_if(m):
    if not m.s.pop():
        skip_to(m, stop_at_else=True)


@prim("[ELSE]", "( -- ) skip to the matching [THEN]", immediate=True, kind=CALL)
def bracket_else(m):
    skip_to(m, stop_at_else=False)


@prim("[THEN]", "( -- ) the end of [IF] ... [ELSE] ...", immediate=True)
def bracket_then(m):
    pass


@prim("[DEFINED]", "( -- f ) is the next name in the search order?", immediate=True)
def bracket_defined(m):
    m.s.append(MASK if m.dictionary.find(parse_word(m)) else 0)


@prim("[UNDEFINED]", "( -- f ) is the next name not in the search order?", immediate=True)
def bracket_undefined(m):
    m.s.append(0 if m.dictionary.find(parse_word(m)) else MASK)


# ------------------------------------------------------------- return stack
def move_group(src, dst, underflow):
    """Move the n cells under n (on top of src) to dst, n on top of them."""
    n = src.pop()
    if n > len(src):
        raise ForthError(underflow)
    dst.extend(src[len(src) - n:])
    del src[len(src) - n:]
    dst.append(n)


@prim("N>R", "( x1 ... xn n -- ) R: ( -- x1 ... xn n ) move n cells and their count")
def n_to_r(m):
    move_group(m.s, m.rs, -4)


@prim("NR>", "( -- x1 ... xn n ) R: ( x1 ... xn n -- ) take back what N>R moved")
def n_r_from(m):
    move_group(m.rs, m.s, -6)


# ------------------------------------------------------------------ SYNONYM
@prim("SYNONYM", "( -- ) SYNONYM new old: new does what old does, immediate if old is")
def synonym(m):
    new, old = parse_word(m), parse_word(m)
    xt = tick(m, old)
    d = m.dictionary
    cf = m.memory.fetch(xt)
    p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
    if p is not None and p.kind is not RUNTIME:
        d.create(new, cf)                    # a primitive: the same code field
    else:                                    # anything else: run it through a vector
        d.create(new, inner.N["(DODEFER)"])  # (no call frame of its own: R> works)
        d.comma(xt)
    if d.flags((xt - 2) & MASK) & IMMEDIATE:
        d.set_flag(d.last, IMMEDIATE)


# -------------------------------------------------------------- name tokens
@prim("TRAVERSE-WORDLIST", "( i*x xt wid -- j*x ) run xt ( k*x nt -- l*x f ) on each "
      "word of wid, newest first, until it gives false", kind=CALL)
def traverse_wordlist(m):
    wid, xt = m.s.pop(), m.s.pop()
    d = m.dictionary
    for lfa in list(d.lfas(d.check_wid(wid))):
        if d.flags(lfa) & HIDDEN or d.name_of((lfa + 2) & MASK) is None:
            continue
        m.s.append((lfa + 2) & MASK)
        m.execute(xt)
        if not m.s.pop():
            break


@prim("NAME>STRING", "( nt -- addr u ) the word's name")
def name_to_string(m):
    nt = m.s.pop()
    lfa = (nt - 2) & MASK
    n = m.dictionary.flags(lfa) & 0x1F
    m.s.extend(((lfa - 1 - n) & MASK, n))


@prim("NAME>INTERPRET", "( nt -- xt ) what the word does when interpreted")
def name_to_interpret(m):
    pass                                     # an nt is the xt


@prim("NAME>COMPILE", "( nt -- x xt ) x xt EXECUTE does what compiling the word does")
def name_to_compile(m):
    nt = m.s[-1]
    imm = m.dictionary.flags((nt - 2) & MASK) & IMMEDIATE
    m.s.append(m.xt_of["EXECUTE"] if imm else m.xt_of["COMPILE,"])
