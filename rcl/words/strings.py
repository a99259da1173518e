"""String word set extensions (Forth 2012 chapter 17): SLITERAL, and text
substitution with REPLACES SUBSTITUTE UNESCAPE.

The rest of the set is older than this module: -TRAILING /STRING COMPARE
SEARCH in parsing.py, BLANK CMOVE CMOVE> in memory_access.py.

Substitution: `%name%` in a text becomes what `REPLACES` gave for name
(names compare without case, as dictionary names do); `%%` becomes one
`%`; an unknown `%name%` is passed on as it is (17.6.2.2255). The replacement texts are kept
by the machine, not in the image, so they survive FORGET.
"""
from rcl.forth.memory import MASK, signed
from rcl.forth import state
from rcl.forth.primitives import prim
from rcl.words.compiling import compile_only
from rcl.words.io import lay_string

SUBSTITUTE_OVERFLOW = -78       # result did not fit: Forth 2012 leaves n < 0


def replacements(m):
    return m.replacements


# REPLACES' table is the system's (as its definitions are): names and texts as bytes.
state.system("replacements", lambda m: {},
             lambda m: {k.decode("latin-1"): v.decode("latin-1") for k, v in m.replacements.items()},
             lambda m, d: setattr(m, "replacements", {k.encode("latin-1"): v.encode("latin-1")
                                                      for k, v in d.items()}))


def sliteral(m):
    u, a = m.s.pop(), m.s.pop()
    lay_string(m, '(S")', m.memory.text(a, u))


prim("SLITERAL", "( addr u -- ) compile the string; it gives ( -- addr' u ) when run",
     immediate=True)(compile_only("SLITERAL", sliteral))


@prim("REPLACES", "( addr1 u1 addr2 u2 -- ) %name2% will stand for text 1")
def replaces(m):
    u2, a2, u1, a1 = m.s.pop(), m.s.pop(), m.s.pop(), m.s.pop()
    replacements(m)[m.memory.read(a2, u2).upper()] = m.memory.read(a1, u1)


def substitute_text(table, text):
    """-> (result, substitutions made)."""
    out, n, i = [], 0, 0
    while i < len(text):
        c = text[i:i + 1]
        end = text.find(b"%", i + 1) if c == b"%" else -1
        if c != b"%" or end < 0:
            out.append(c)
            i += 1
        elif end == i + 1:                      # %% is one %
            out.append(b"%")
            i += 2
        elif text[i + 1:end].upper() in table:
            out.append(table[text[i + 1:end].upper()])
            n += 1
            i = end + 1
        else:                                   # not a name: passed on as it is
            out.append(text[i:end + 1])
            i = end + 1
    return b"".join(out), n


@prim("SUBSTITUTE", "( addr1 u1 addr2 u2 -- addr2 u3 n ) text 1 with %name% "
      "replaced, into the buffer at addr2 (u2 bytes); n < 0 if it did not fit")
def substitute(m):
    u2, a2, u1, a1 = m.s.pop(), m.s.pop(), m.s.pop(), m.s.pop()
    result, n = substitute_text(replacements(m), m.memory.read(a1, u1))
    if len(result) > u2 or a1 == a2:
        m.s.extend((a2, 0, SUBSTITUTE_OVERFLOW & MASK))
        return
    m.memory.write(a2, result)
    m.s.extend((a2, len(result), n))


@prim("UNESCAPE", "( addr1 u1 addr2 -- addr2 u2 ) a copy with every % doubled")
def unescape(m):
    a2, u1, a1 = m.s.pop(), m.s.pop(), m.s.pop()
    data = m.memory.read(a1, signed(u1) if signed(u1) > 0 else 0).replace(b"%", b"%%")
    m.memory.write(a2, data)
    m.s.extend((a2, len(data)))
