"""Terminal output and input, number output, pictured numeric output,
and the string literals that print or push text.

Output goes to the machine's `type`, which streams to the prompt or
collects for `evaluate`. Numbers print in BASE with upper-case digits.
"""
from rcl.errors import ForthError
from rcl.forth.memory import MASK, PAD_OFFSET, signed
from rcl.forth import state
from rcl.forth.primitives import LITERAL, prim
from rcl.words.compiling import compile_only
from rcl.words.core import pop2
from rcl.words.double import ds

DIGITS = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZ"


def in_base(m, n):
    """n (a Python int, any sign) as text in BASE."""
    base = m.memory.fetch(m.a_base)
    if not 2 <= base <= 36:
        base = 10
    text, u = "", abs(n)
    while True:
        u, d = divmod(u, base)
        text = DIGITS[d] + text
        if not u:
            break
    return "-" + text if n < 0 else text


def right(text, width):
    return " " * max(0, signed(width) - len(text)) + text


# ------------------------------------------------------------------ output
@prim("EMIT", "( c -- ) type one character")
def emit(m):
    m.type(chr(m.s.pop() & 0xFF))


@prim("TYPE", "( addr u -- ) type u characters")
def type_(m):
    u, a = m.s.pop(), m.s.pop()
    m.type(m.memory.text(a, 0 if u & 0x8000 else u))


@prim("CR", "( -- ) new line")
def cr(m):
    m.type("\n")


@prim("SPACE", "( -- )")
def space(m):
    m.type(" ")


@prim("SPACES", "( n -- ) n blanks; none if n <= 0")
def spaces(m):
    m.type(" " * max(0, signed(m.s.pop())))


@prim("BELL", "( -- ) sound the console bell (F83's BEEP)")
def bell(m):
    m.type("\a")


prim("BEEP", "( -- ) sound the console bell")(bell)


@prim("PAGE", "( -- ) clear the screen (to a file or pipe: a form feed)")
def page(m):
    m.type("\f")       # the terminal's side turns it into ANSI's clear (rcl/cli.py)


@prim(".", "( n -- ) print signed, then a blank")
def dot(m):
    m.type(in_base(m, signed(m.s.pop())) + " ")


@prim("U.", "( u -- ) print unsigned, then a blank")
def u_dot(m):
    m.type(in_base(m, m.s.pop()) + " ")


@prim(".R", "( n width -- ) signed, right-justified, no blank")
def dot_r(m):
    w = m.s.pop()
    m.type(right(in_base(m, signed(m.s.pop())), w))


@prim("U.R", "( u width -- ) unsigned, right-justified")
def u_dot_r(m):
    w = m.s.pop()
    m.type(right(in_base(m, m.s.pop()), w))


@prim("D.", "( d -- ) print a double, then a blank")
def d_dot(m):
    m.type(in_base(m, ds(pop2(m.s))) + " ")


@prim("UD.", "( ud -- ) print an unsigned double, then a blank")
def ud_dot(m):
    m.type(in_base(m, pop2(m.s)) + " ")


@prim("D.R", "( d width -- ) right-justified")
def d_dot_r(m):
    w = m.s.pop()
    m.type(right(in_base(m, ds(pop2(m.s))), w))


@prim("UD.R", "( ud width -- ) right-justified")
def ud_dot_r(m):
    w = m.s.pop()
    m.type(right(in_base(m, pop2(m.s)), w))


@prim("?", "( addr -- ) print the cell at addr")
def question(m):
    m.type(in_base(m, signed(m.memory.fetch(m.s.pop()))) + " ")


@prim("DECIMAL", "( -- ) BASE := 10")
def decimal(m):
    m.memory.store(m.a_base, 10)


@prim("HEX", "( -- ) BASE := 16")
def hex_(m):
    m.memory.store(m.a_base, 16)


@prim("OCTAL", "( -- ) BASE := 8")
def octal(m):
    m.memory.store(m.a_base, 8)


# -------------------------------------------------- pictured numeric output
def pad(m):
    return (m.dictionary.here + PAD_OFFSET) & MASK


@prim("<#", "( -- ) start pictured output (it grows down from PAD)")
def lt_sharp(m):
    m.memory.store(m.a_hld, pad(m))


@prim("HOLD", "( c -- ) put c in front of the pictured output")
def hold(m):
    h = (m.memory.fetch(m.a_hld) - 1) & MASK
    if not pad(m) - 256 <= h < pad(m):        # also: HLD never set by <#
        raise ForthError(-17, "Pictured output overflow")
    m.memory.store(m.a_hld, h)
    m.memory.cstore(h, m.s.pop())


@prim("HOLDS", "( addr u -- ) put a string in front of the pictured output")
def holds(m):
    u, a = m.s.pop(), m.s.pop()
    for c in reversed(m.memory.read(a, u)):
        m.s.append(c)
        hold(m)


@prim("#", "( ud -- ud' ) convert one digit")
def sharp(m):
    base = m.memory.fetch(m.a_base) or 10
    ud = pop2(m.s)
    ud, d = divmod(ud, base)
    m.s.extend((ud & MASK, ud >> 16, ord(DIGITS[d % 36])))
    hold(m)


@prim("#S", "( ud -- 0 0 ) convert all digits (at least one)")
def sharp_s(m):
    sharp(m)
    while m.s[-1] or m.s[-2]:
        sharp(m)


@prim("SIGN", "( n -- ) hold a minus sign if n < 0")
def sign(m):
    if m.s.pop() & 0x8000:
        m.s.append(ord("-"))
        hold(m)


@prim("#>", "( ud -- addr u ) end pictured output")
def sharp_gt(m):
    m.s.pop()
    m.s.pop()
    h = m.memory.fetch(m.a_hld)
    m.s.extend((h, (pad(m) - h) & MASK))


# ------------------------------------------------------------ string literals
def decode_counted(m, ip):
    """Inline counted string: -> ((addr, len), address after it)."""
    n = m.mem[ip]
    return ((ip + 1) & MASK, n), (ip + 1 + n) & MASK


def string_prim(name, effect):
    return prim(name, effect, kind=LITERAL, decode=decode_counted)


@string_prim("(.\")", "( -- ) type the inline string")
def paren_dot_quote(m, a, n):
    m.type(m.memory.text(a, n))


@string_prim("(S\")", "( -- addr u ) the inline string")
def paren_s_quote(m, a, n):
    m.s.extend((a, n))


@string_prim("(C\")", "( -- addr ) the inline counted string")
def paren_c_quote(m, a, n):
    m.s.append((a - 1) & MASK)


@string_prim("(\")", "( -- addr u ) the inline string (F83's \": R> COUNT ...)")
def paren_quote(m, a, n):
    m.s.extend((a, n))


@string_prim("(ABORT\")", "( f -- ) abort with the inline message if f")
def paren_abort_quote(m, a, n):
    if m.s.pop():
        raise ForthError(-2, m.memory.text(a, n))


def lay_string(m, runtime, text):
    """Compile runtime followed by text as a counted string."""
    data = text.encode("latin-1", "replace")[:255]
    m.dictionary.comma(m.xt_of[runtime])
    m.dictionary.ccomma(len(data))
    for c in data:
        m.dictionary.ccomma(c)


def quoted(m):
    a, n = m.parse(ord('"'))
    return m.memory.text(a, n)


# Which of the four rotating S" buffers was used last: the session's.
state.session("sbuf", lambda m: 0)


def transient(m, text):
    """Place text in one of the rotating S" buffers; -> (addr, len)."""
    from rcl.forth.memory import STRING_BUFFERS
    data = text.encode("latin-1", "replace")[:255]
    m.sbuf = (m.sbuf + 1) % 4
    a = STRING_BUFFERS + 256 * m.sbuf
    m.memory.write(a, bytes([len(data)]) + data)
    return a + 1, len(data)


def state(m):
    return m.memory.fetch(m.a_state) != 0


@prim(".\"", "( -- ) compile a string to type when run (F83: compiles even "
      "outside a definition, typing nothing)", immediate=True)
def dot_quote(m):
    lay_string(m, '(.")', quoted(m))


def string_word(m, text, runtime, counted=False):
    """S" C" " S\\" : compile runtime and text, or (interpreting) leave the
    text in a transient buffer as addr u, or as a counted string's addr."""
    if state(m):
        lay_string(m, runtime, text)
    elif counted:
        m.s.append(transient(m, text)[0] - 1)
    else:
        m.s.extend(transient(m, text))


@prim("S\"", "( -- addr u ) a string: compiled, or in a transient buffer",
      immediate=True)
def s_quote(m):
    string_word(m, quoted(m), '(S")')


@prim("C\"", "( -- addr ) a counted string: compiled, or transient", immediate=True)
def c_quote(m):
    string_word(m, quoted(m), '(C")', counted=True)


@prim("\"", "( -- addr u ) F83's string literal", immediate=True)
def quote(m):
    string_word(m, quoted(m), '(")')


ESCAPES = {"a": "\a", "b": "\b", "e": "\x1b", "f": "\f", "l": "\n", "n": "\n",
           "q": '"', "r": "\r", "t": "\t", "v": "\v", "z": "\0", '"': '"',
           "\\": "\\", "m": "\r\n"}


def escaped(m):
    """Parse a S\\" string up to an unescaped quote, translating escapes."""
    addr, length = m.source()
    i = m.memory.fetch(m.a_in)
    out = []
    while i < length:
        c = chr(m.mem[(addr + i) & MASK])
        i += 1
        if c == '"':
            break
        if c == "\\" and i < length:
            e = chr(m.mem[(addr + i) & MASK])
            i += 1
            if e == "x":
                hexes = m.memory.text((addr + i) & MASK, 2)
                out.append(chr(int(hexes, 16)) if all(c in "0123456789abcdefABCDEF"
                                                      for c in hexes) else "?")
                i += 2
            else:
                out.append(ESCAPES.get(e, e))
        else:
            out.append(c)
    m.memory.store(m.a_in, i)
    return "".join(out)


@prim("S\\\"", "( -- addr u ) a string with \\ escapes", immediate=True)
def s_backslash_quote(m):
    string_word(m, escaped(m), '(S")')


def abort_quote(m):
    lay_string(m, '(ABORT")', quoted(m))


prim("ABORT\"", "( f -- ) abort with the message if f is true",
     immediate=True)(compile_only('ABORT"', abort_quote))


@prim(".(", "( -- ) type the text up to ) now", immediate=True)
def dot_paren(m):
    a, n = m.parse(ord(")"))
    m.type(m.memory.text(a, n))


# ------------------------------------------------------------------- input
def next_key(m):
    if m.keys:
        return m.keys.pop(0)
    key = m.wait_input(m.read_key) if m.read_key is not None else None
    if key is None:
        raise ForthError(-39, "No input")
    return key


@prim("KEY", "( -- c ) the next key")
def key(m):
    m.s.append(next_key(m) & 0xFF)


@prim("KEY?", "( -- f ) is a key waiting?")
def key_q(m):
    ready = bool(m.keys) or (m.key_ready is not None and m.key_ready())
    m.s.append(MASK if ready else 0)


def read_line(m):
    """The next line for ACCEPT/EXPECT: typed-ahead keys, else the terminal."""
    if m.keys:
        text = "".join(chr(c) for c in m.keys)
        line, _, rest = text.partition("\r") if "\r" in text else text.partition("\n")
        m.keys = [ord(c) for c in rest]
        return line
    line = next(m.sources[0].lines, None)
    if line is None and m.read_line is not None:
        line = m.wait_input(m.read_line)
    return "" if line is None else line      # at the end of input: an empty line


@prim("ACCEPT", "( addr n -- n2 ) read a line of at most n characters")
def accept(m):
    n, a = signed(m.s.pop()), m.s.pop()
    data = read_line(m).encode("latin-1", "replace")[:max(0, n)]
    m.memory.write(a, data)
    m.s.append(len(data))


@prim("EXPECT", "( addr n -- ) read a line; its length goes to SPAN")
def expect(m):
    accept(m)
    m.memory.store(m.a_span, m.s.pop())
