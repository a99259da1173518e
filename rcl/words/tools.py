"""Programming tools: .S DUMP WORDS SEE FORGET EMPTY and friends.

SEE decompiles threaded code back to Forth: branches become IF ELSE THEN,
BEGIN UNTIL / AGAIN / WHILE REPEAT, DO LOOP, and literals their numbers,
so that a colon word's text, compiled again (under any name), lays down
the same cells (the table above `number_text`; tests/test_see_roundtrip.py
checks it over every colon word of the system).
"""
from rcl.forth import inner
from rcl.forth.compiler import decode
from rcl.forth.dictionary import HIDDEN, IMMEDIATE
from rcl.forth.memory import MASK, PRIM_LIMIT, signed
from rcl.forth.primitives import REGISTRY, prim
from rcl.words.compiling import parse_word, tick
from rcl.words.io import in_base
from rcl.words.help import columns, wrap


@prim(".S", "( -- ) show the stack, deepest first, unsigned, 7 columns each")
def dot_s(m):
    if not m.s:
        m.type("Empty ")
    else:
        m.type("".join("%7s " % in_base(m, v) for v in m.s))


@prim("DUMP", "( addr u -- ) bytes in hex and as text, 16 a line")
def dump(m):
    u, a = m.s.pop(), m.s.pop()
    lines = []
    for row in range(a, a + min(u, 4096), 16):
        data = m.memory.read(row & MASK, min(16, a + u - row))
        hexes = " ".join("%02X" % b for b in data)
        text = "".join(chr(b) if 32 <= b < 127 else "." for b in data)
        lines.append("\n%04X  %-48s %s" % (row & MASK, hexes, text))
    m.type("".join(lines) + "\n")


@prim("WORDS", "( -- ) the words of the first vocabulary searched, newest first")
def words(m):
    d = m.dictionary
    # Not the hidden ones: a definition an error abandoned stays hidden, and
    # typing its name gives ?, so listing it would mislead.
    names = [d.name_of((lfa + 2) & MASK) for lfa in d.lfas(d.order()[0])
             if not d.flags(lfa) & HIDDEN]
    m.type("\n".join(wrap([n for n in names if n], columns(m))) + "\n")


@prim(".NAME", "( xt -- ) print the name of a word")
def dot_name(m):
    m.type((m.dictionary.name_of(m.s.pop()) or "?") + " ")


@prim(">NAME", "( xt -- addr ) the count byte of its name (F83: name field)")
def to_name(m):
    m.s[-1] = (m.s[-1] - 3) & MASK


@prim("NAME>", "( nfa -- xt ) from the count byte to the code field")
def name_from(m):
    m.s[-1] = (m.s[-1] + 3) & MASK


@prim(">LINK", "( xt -- lfa ) the link field")
def to_link(m):
    m.s[-1] = (m.s[-1] - 2) & MASK


@prim("L>NAME", "( lfa -- nfa ) from the link field to the count byte")
def link_to_name(m):
    m.s[-1] = (m.s[-1] - 1) & MASK


@prim("FORGET", "( -- ) forget the next word and everything defined after it")
def forget(m):
    xt = tick(m, parse_word(m))
    m.dictionary.forget_to(m.dictionary.header_start(xt))


@prim("EMPTY", "( -- ) forget everything defined after the base system")
def empty(m):
    m.dictionary.forget_to(m.memory.fetch(m.a_fence))


@prim("SEE", "( -- ) decompile the next word: a colon word as Forth text that "
      "compiles again to the same code")
def see(m):
    m.type(decompile(m, tick(m, parse_word(m))) + "\n")


# ------------------------------------------------------------- decompiler
# SEE's text for a colon definition compiles again to the same cells
# (docs/words.md, SEE): each cell is written as the source that lays it
# down, in the base in use, with RCL literals on (the system's default):
#
#     LIT n            [ n ] LITERAL   (['] NAME when n is NAME's xt,
#                                      [CHAR] c when n is a printable character)
#     (RLIT) n         n               (RWLIT) n  n beyond a signed cell
#     (RDLIT) d dpl    d with dpl digits after the point: 3.50
#     a call           NAME, POSTPONE NAME (immediate), RECURSE (itself),
#                      [ xt COMPILE, ] (a name that finds another word)
#     COMPILE x        COMPILE x   (COMPILE [COMPILE] x for an immediate x)
#     strings          ." text"  S" text"  S\" te\"xt"  C" text"  ABORT" text"
#     debugging        BREAK:  BREAK" text"  ~~  (their runtimes, as typed)
QUOTES = {'(.")': '."', '(S")': 'S"', '(C")': 'C"', '(ABORT")': 'ABORT"', '(")': '"'}


def number_text(m, value, dpl=-1):
    if dpl < 0:
        return in_base(m, signed(value))
    d = value - (1 << 32) if value & 0x80000000 else value
    digits = in_base(m, abs(d)).rjust(dpl + 1, "0")
    text = digits[:len(digits) - dpl] + "." + digits[len(digits) - dpl:]
    return "-" + text if d < 0 else text


def unshadowed(m, text):
    """A number's text that no word of that name takes over (F83 has
    constants named 0 1 2 ...): a leading zero after the sign if needed."""
    if m.dictionary.find(text) is None:
        return text
    return "-0" + text[1:] if text.startswith("-") else "0" + text


def decompile(m, xt):
    d = m.dictionary
    name = d.name_of(xt) or "(noname)"
    cf = m.memory.fetch(xt)
    if cf >= PRIM_LIMIT:
        return "%s is a DOES> word; its DOES> part:\n%s" % (name, body_text(m, cf))
    p = REGISTRY[cf] if 0 < cf < len(REGISTRY) else None
    if p is None:
        return "%s ?" % name
    body = (xt + 2) & MASK
    fetch = m.memory.fetch
    imm = " IMMEDIATE" if d.flags((xt - 2) & MASK) & IMMEDIATE else ""
    if cf == inner.DOCOL:
        return ": %s %s ;%s" % (name, body_text(m, body, xt), imm)
    kind = {"(DOCON)": "%d CONSTANT %s", "(DOVALUE)": "%d VALUE %s",
            "(DOVAR)": "CREATE %s ( data at %04X )"}.get(p.name)
    if p.name in ("(DOCON)", "(DOVALUE)"):
        return kind % (signed(fetch(body)), name)
    if p.name == "(DOVAR)":
        return kind % (name, body)
    if p.name == "(DODEFER)":
        return "DEFER %s  IS %s" % (name, d.name_of(fetch(body)) or "?")
    if p.name == "(DOVOC)":
        return "VOCABULARY %s" % name
    return "CODE %s %s (a Python primitive)%s" % (name, p.effect, imm)


def decoded(m, start):
    """The instructions from start up to the definition's final EXIT (the
    first EXIT no forward branch jumps past)."""
    code, ip, last_fwd = [], start, start
    while len(code) < 2000:
        ins = decode(m, ip)
        code.append(ins)
        if ins.target is not None and ins.target > ins.addr:
            last_fwd = max(last_fwd, ins.target)
        if ins.op == "EXIT" and ins.addr >= last_fwd:
            break
        ip = ins.next
    return code


def body_text(m, start, self_xt=None):
    """Structured Forth for the threaded code at start, up to its final EXIT."""
    out, thens, repeats, begins, whiles = [], {}, {}, set(), set()
    code = decoded(m, start)
    for ins in code:
        if ins.op in ("BRANCH", "?BRANCH") and ins.target <= ins.addr:
            begins.add(ins.target)
    for ins in code:                   # WHILE: ?BRANCH forward past a backward BRANCH
        if ins.op == "?BRANCH" and ins.target > ins.addr:
            prev = [i for i in code if i.next == ins.target]
            if prev and prev[0].op == "BRANCH" and prev[0].target <= ins.addr:
                whiles.add(ins.addr)
    for ins in code:
        if ins.addr in thens:
            out.extend(["THEN"] * thens.pop(ins.addr))
        if ins.addr in begins:
            out.append("BEGIN")
        op = ins.op
        if op == "?BRANCH":
            if ins.target <= ins.addr:
                out.append("UNTIL")
            elif ins.addr in whiles:           # its THEN is REPEAT's, or a THEN after
                out.append("WHILE")
                thens[ins.target] = thens.get(ins.target, 0) + 1
                repeats[ins.target] = repeats.get(ins.target, 0) + 1
            else:
                out.append("IF")
                thens[ins.target] = thens.get(ins.target, 0) + 1
        elif op == "BRANCH":
            if ins.target <= ins.addr:
                if repeats.get(ins.next):       # REPEAT is AGAIN and a WHILE's THEN
                    thens[ins.next] -= 1
                    repeats[ins.next] -= 1
                    out.append("REPEAT")
                else:
                    out.append("AGAIN")
            elif thens.get(ins.next):
                thens[ins.next] -= 1
                out.append("ELSE")
                thens[ins.target] = thens.get(ins.target, 0) + 1
            else:
                out.append("AHEAD")
                thens[ins.target] = thens.get(ins.target, 0) + 1
        elif op in ("(DO)", "(?DO)", "(LOOP)", "(+LOOP)", "(LEAVE)", "(?LEAVE)"):
            out.append(op[1:-1])
        elif op == "(DOES>)":
            out.append("DOES>")
        elif op == "EXIT":
            if ins is not code[-1]:
                out.append("EXIT")
        elif op == "literal":
            out.append(literal_text(m, ins))
        else:
            out.append(debug_text(m, ins.xt, out) or call_text(m, ins.xt, self_xt))
    if code and code[-1].next in thens:
        out.extend(["THEN"] * thens.pop(code[-1].next))
    return " ".join(out)


# The debugging words compile runtimes of their own (rcl/words/debugging.py):
# written back as they were typed. BREAK" text" is S" text" then (BREAK").
DEBUG_RUNTIMES = {"(BREAK)": "BREAK:", "(~~)": "~~"}


def debug_text(m, xt, out):
    """BREAK:, ~~ or BREAK" text" for a debugging runtime (BREAK" takes
    the S" text" just written over), else None."""
    name = m.dictionary.name_of(xt)
    if name in DEBUG_RUNTIMES and m.dictionary.find(name) == (xt, False):
        return DEBUG_RUNTIMES[name]
    if name == '(BREAK")' and out and out[-1].startswith('S" '):
        return 'BREAK"' + out.pop()[2:]
    return None


def call_text(m, xt, self_xt=None):
    """The source that compiles a call of xt."""
    d = m.dictionary
    if xt == self_xt:
        return "RECURSE"
    name = d.name_of(xt)
    hit = d.find(name) if name else None
    if hit is None or hit[0] != xt:
        return "[ %s COMPILE, ]" % number_text(m, xt)
    return "POSTPONE " + name if hit[1] else name


def literal_text(m, ins):
    name, args = ins.prim.name, ins.args
    if name == "LIT":
        named = m.dictionary.name_of(args[0])
        if named and m.dictionary.find(named) == (args[0], False):
            return "['] " + named
        if 33 <= args[0] <= 126:               # RCL's numbers are (RLIT): LIT is [CHAR]'s
            return "[CHAR] " + chr(args[0])
        return "[ %s ] LITERAL" % number_text(m, args[0])
    if name == "(RLIT)":
        return unshadowed(m, number_text(m, args[0]))
    if name == "(RWLIT)":                       # typed beyond a signed cell
        return in_base(m, args[0] if args[0] & 0x8000 else args[0] + 0x10000)
    if name == "(RDLIT)":
        return number_text(m, args[0] | (args[1] << 16), signed(args[2]))
    if name == "COMPILE":
        target = call_text(m, args[0])
        if target.startswith("POSTPONE "):
            return "COMPILE [COMPILE] " + target[9:]
        return "COMPILE " + target
    if len(args) == 2 and name in QUOTES:
        return string_text(name, m.memory.text(args[0], args[1]))
    return "%s %s" % (name, " ".join(str(a) for a in args))


def string_text(name, text):
    plain = '"' not in text and "\\" not in text and all(" " <= c <= "~" for c in text)
    if plain or name != '(S")':
        return '%s %s"' % (QUOTES[name], text)
    escaped = "".join("\\" + c if c in '"\\' else c if " " <= c <= "~"
                      else "\\x%02X" % ord(c) for c in text)
    return 'S\\" %s"' % escaped
