"""Compiling and defining words: : ; control structures, CREATE DOES>,
CONSTANT VARIABLE VALUE DEFER, CODE ... END-CODE.

What the control structures compile (addresses are absolute):

    IF ... ELSE ... THEN    ?BRANCH a1 ... BRANCH a2 [a1:] ... [a2:]
    BEGIN ... UNTIL         [d:] ... ?BRANCH d
    BEGIN ... WHILE ... REPEAT   [d:] ... ?BRANCH a ... BRANCH d [a:]
    BEGIN ... AGAIN         [d:] ... BRANCH d
    DO ... LOOP             (DO) x [b:] ... (LOOP) b [x:]     LEAVE jumps to x
    CASE .. OF .. ENDOF .. ENDCASE   OVER = ?BRANCH a DROP .. BRANCH e [a:] .. DROP [e:]

At compile time each open structure is two cells on the data stack: an
address and a tag saying what it is; a word that finds the wrong tag
aborts with ` Conditionals Wrong `, as F83 does.
"""
from rcl.errors import ForthError
from rcl.forth import inner, state
from rcl.forth.dictionary import HIDDEN, IMMEDIATE
from rcl.forth.memory import MASK, signed
from rcl.forth.primitives import BY_NAME, LITERAL, RUNTIME, prim

ORIG, DEST, DO_SYS, CASE_SYS, OF_SYS = 0x7F01, 0x7F02, 0x7F03, 0x7F04, 0x7F05


def compile_name(m, name):
    m.dictionary.comma(m.xt_of[name])


def push_cs(m, addr, tag):
    m.s.extend((addr & MASK, tag))


def pop_cs(m, *tags):
    """Pop a control-flow item whose tag is one of tags; -> address."""
    s = m.s
    if len(s) < 2 or s[-1] not in tags:
        raise ForthError(-22, "Conditionals Wrong")
    s.pop()
    return s.pop()


def mark(m):
    """Compile a placeholder cell; -> its address."""
    a = m.dictionary.here
    m.dictionary.comma(0)
    return a


def resolve(m, a):
    """Point the placeholder at a to HERE."""
    m.memory.store(a, m.dictionary.here)


def parse_word(m):
    name, _ = m.parse_name()
    if not name:
        raise ForthError(-16, "Name expected")
    return name


def tick(m, name):
    hit = m.dictionary.find(name)
    if hit is None:
        raise ForthError(-13, "?", name.upper())
    return hit[0]


def compiling(m):
    return m.memory.fetch(m.a_state) != 0


# ----------------------------------------------------------------- colon
def compile_only(name, body):
    """body, refusing to run outside a definition (F83 would compile junk)."""
    def f(m):
        if not compiling(m):
            raise ForthError(-14, "Compile only", name)
        body(m)
    f.__doc__ = body.__doc__
    return f


@prim(":", "( -- ) start a colon definition; the name stays hidden until ;")
def colon(m):
    xt = m.dictionary.create(parse_word(m), inner.DOCOL)
    m.dictionary.set_flag(m.dictionary.last, HIDDEN)
    begin_colon(m, xt, m.dictionary.last)


# The colon definition being compiled (its xt, its header; 0: none): the session's.
state.session("colon_xt", lambda m: 0)
state.session("colon_lfa", lambda m: 0)


def begin_colon(m, xt, lfa):
    m.colon_xt, m.colon_lfa = xt, lfa
    m.locals = None                   # no locals until {: declares them
    m.memory.store(m.a_csp, len(m.s))
    m.memory.store(m.a_state, MASK)


@prim(":NONAME", "( -- xt ) start a nameless colon definition")
def colon_noname(m):
    xt = m.dictionary.here
    m.dictionary.comma(inner.DOCOL)
    m.s.append(xt)
    begin_colon(m, xt, 0)


def semicolon(m):
    if len(m.s) != m.memory.fetch(m.a_csp):
        raise ForthError(-256, "Stack Changed")
    if m.locals is not None:          # drop the locals frame (localvars.py)
        m.locals.unwind(m)
        m.locals = None
    compile_name(m, "EXIT")
    if m.colon_lfa:
        m.dictionary.set_flag(m.colon_lfa, HIDDEN, False)
    m.colon_lfa = 0
    m.memory.store(m.a_state, 0)


prim(";", "( -- ) end the definition; ` Stack Changed ` if the stack moved",
     immediate=True)(compile_only(";", semicolon))


def recursive(m):
    if m.colon_lfa:
        m.dictionary.set_flag(m.colon_lfa, HIDDEN, False)


def recurse(m):
    m.dictionary.comma(m.colon_xt)


prim("RECURSIVE", "( -- ) make the definition being compiled visible now",
     immediate=True)(compile_only("RECURSIVE", recursive))
prim("RECURSE", "( -- ) compile a call of the definition being compiled",
     immediate=True)(compile_only("RECURSE", recurse))


@prim("IMMEDIATE", "( -- ) mark the newest word immediate")
def immediate(m):
    m.dictionary.set_flag(m.dictionary.last, IMMEDIATE)


@prim("[", "( -- ) interpret", immediate=True)
def left_bracket(m):
    m.memory.store(m.a_state, 0)


@prim("]", "( -- ) compile")
def right_bracket(m):
    m.memory.store(m.a_state, MASK)


# -------------------------------------------------------- control structures
def branch_word(name, effect, body):
    prim(name, effect, immediate=True)(compile_only(name, body))


def _if(m):
    compile_name(m, "?BRANCH")
    push_cs(m, mark(m), ORIG)


def _ahead(m):
    compile_name(m, "BRANCH")
    push_cs(m, mark(m), ORIG)


def _then(m):
    resolve(m, pop_cs(m, ORIG))


def _else(m):
    a = pop_cs(m, ORIG)
    _ahead(m)
    resolve(m, a)


def _begin(m):
    push_cs(m, m.dictionary.here, DEST)


def _back(m, branch):
    d = pop_cs(m, DEST)
    compile_name(m, branch)
    m.dictionary.comma(d)


def _while(m):
    d = pop_cs(m, DEST)
    _if(m)
    push_cs(m, d, DEST)


def _repeat(m):
    _back(m, "BRANCH")
    _then(m)


def _do(name):
    def f(m):
        compile_name(m, name)
        push_cs(m, mark(m), DO_SYS)
    return f


def _loop(name):
    def f(m):
        a = pop_cs(m, DO_SYS)
        compile_name(m, name)
        m.dictionary.comma(a + 2)
        resolve(m, a)
    return f


branch_word("IF", "( f -- ) C: ( -- orig )", _if)
branch_word("AHEAD", "( -- ) C: ( -- orig )", _ahead)
branch_word("THEN", "( -- ) C: ( orig -- )", _then)
branch_word("ENDIF", "( -- ) C: ( orig -- )", _then)
branch_word("ELSE", "( -- ) C: ( orig1 -- orig2 )", _else)
branch_word("BEGIN", "( -- ) C: ( -- dest )", _begin)
branch_word("UNTIL", "( f -- ) C: ( dest -- )", lambda m: _back(m, "?BRANCH"))
branch_word("AGAIN", "( -- ) C: ( dest -- )", lambda m: _back(m, "BRANCH"))
branch_word("WHILE", "( f -- ) C: ( dest -- orig dest )", _while)
branch_word("REPEAT", "( -- ) C: ( orig dest -- )", _repeat)
branch_word("DO", "( limit start -- ) C: ( -- do-sys )", _do("(DO)"))
branch_word("?DO", "( limit start -- ) C: ( -- do-sys )", _do("(?DO)"))
branch_word("LOOP", "( -- ) C: ( do-sys -- )", _loop("(LOOP)"))
branch_word("+LOOP", "( n -- ) C: ( do-sys -- )", _loop("(+LOOP)"))
branch_word("LEAVE", "( -- ) leave the innermost loop now",
            lambda m: compile_name(m, "(LEAVE)"))
branch_word("?LEAVE", "( f -- ) leave the innermost loop if f is true",
            lambda m: compile_name(m, "(?LEAVE)"))


def case(m):
    push_cs(m, 0, CASE_SYS)


branch_word("CASE", "( -- ) C: ( -- case-sys )", case)


def of(m):
    compile_name(m, "OVER")
    compile_name(m, "=")
    compile_name(m, "?BRANCH")
    a = mark(m)
    compile_name(m, "DROP")
    push_cs(m, a, OF_SYS)


prim("OF", "( x1 x2 -- | x1 ) C: ( -- of-sys )", immediate=True)(compile_only("OF", of))


def endof(m):
    a = pop_cs(m, OF_SYS)
    _ahead(m)
    resolve(m, a)


prim("ENDOF", "( -- ) C: ( of-sys -- orig )", immediate=True)(compile_only("ENDOF", endof))


def endcase(m):
    compile_name(m, "DROP")
    while len(m.s) >= 2 and m.s[-1] == ORIG:
        _then(m)
    pop_cs(m, CASE_SYS)


prim("ENDCASE", "( x -- ) C: ( case-sys orig* -- )", immediate=True)(compile_only("ENDCASE", endcase))


@prim("CS-PICK", "( -- ) C: ( x_u ... x_0 u -- x_u ... x_0 x_u )")
def cs_pick(m):
    u = m.s.pop()
    m.s.extend(m.s[-2 * u - 2:len(m.s) - 2 * u])


@prim("CS-ROLL", "( -- ) C: ( x_u ... x_0 u -- x_u-1 ... x_0 x_u )")
def cs_roll(m):
    u = m.s.pop()
    s = m.s
    i = len(s) - 2 * u - 2
    item = s[i:i + 2]
    del s[i:i + 2]
    s.extend(item)


# -------------------------------------------------------------- literals
@prim("LITERAL", "( n -- ) compile n (interpreting: nothing, as in F83)",
      immediate=True)
def literal(m):
    if not compiling(m):
        return
    compile_name(m, "LIT")
    m.dictionary.comma(m.s.pop())


def _dliteral(m):
    if not compiling(m):
        return
    hi, lo = m.s.pop(), m.s.pop()
    for v in (lo, hi):
        compile_name(m, "LIT")
        m.dictionary.comma(v)


prim("DLITERAL", "( d -- ) compile d", immediate=True)(_dliteral)
prim("2LITERAL", "( d -- ) compile d", immediate=True)(_dliteral)


@prim("COMPILE", "( -- ) compile the xt that follows in the caller's code",
      kind=LITERAL, args=1)
def compile_next(m, xt):
    m.dictionary.comma(xt)


def bracket_compile(m):
    m.dictionary.comma(tick(m, parse_word(m)))


prim("[COMPILE]", "( -- ) compile the next word even if it is immediate",
      immediate=True)(compile_only("[COMPILE]", bracket_compile))


def postpone(m):
    name = parse_word(m)
    hit = m.dictionary.find(name)
    if hit is None:
        raise ForthError(-13, "?", name.upper())
    xt, imm = hit
    if imm:
        m.dictionary.comma(xt)
    else:
        compile_name(m, "COMPILE")
        m.dictionary.comma(xt)


prim("POSTPONE", "( -- ) compile the compilation of the next word", immediate=True)(compile_only("POSTPONE", postpone))


@prim("COMPILE,", "( xt -- ) compile a call of xt")
def compile_comma(m):
    m.dictionary.comma(m.s.pop())


@prim("'", "( -- xt ) the xt of the next word (abort with ? if none)")
def tick_word(m):
    m.s.append(tick(m, parse_word(m)))


def bracket_tick(m):
    compile_name(m, "LIT")
    m.dictionary.comma(tick(m, parse_word(m)))


prim("[']", "( -- ) compile the xt of the next word as a literal", immediate=True)(compile_only("[']", bracket_tick))


prim(">BODY", "( xt -- addr ) the data field of a CREATEd word",
     inline=("a", ("(a + 2) & 0xFFFF",)))(None)


def char_of(m):
    name = parse_word(m)
    return ord(name[0])


@prim("CHAR", "( -- c ) the first character of the next word")
def char(m):
    m.s.append(char_of(m))


def _char_literal(convert):
    def f(m):
        c = convert(char_of(m))
        if compiling(m):
            compile_name(m, "LIT")
            m.dictionary.comma(c)
        else:
            m.s.append(c)
    return f


prim("[CHAR]", "( -- c ) compile the first character of the next word",
     immediate=True)(_char_literal(lambda c: c))
prim("ASCII", "( -- c ) the character code of the next word (state-smart, F83)",
     immediate=True)(_char_literal(lambda c: c))
prim("CONTROL", "( -- c ) the control code of the next word's first letter",
     immediate=True)(_char_literal(lambda c: c & 0x1F))


# -------------------------------------------------------- defining words
def define(m, runtime):
    return m.dictionary.create(parse_word(m), inner.N[runtime])


@prim("CREATE", "( -- ) a word that pushes its data field address")
def create(m):
    define(m, "(DOVAR)")


@prim("VARIABLE", "( -- ) a cell initialised to 0")
def variable(m):
    define(m, "(DOVAR)")
    m.dictionary.comma(0)


@prim("2VARIABLE", "( -- ) two cells initialised to 0")
def two_variable(m):
    define(m, "(DOVAR)")
    m.dictionary.comma(0)
    m.dictionary.comma(0)


@prim("CONSTANT", "( n -- ) a word that pushes n")
def constant(m):
    define(m, "(DOCON)")
    m.dictionary.comma(m.s.pop())


@prim("VALUE", "( n -- ) a word that pushes n until TO changes it")
def value(m):
    define(m, "(DOVALUE)")
    m.dictionary.comma(m.s.pop())


def _two_cells(m, runtime):
    hi, lo = m.s.pop(), m.s.pop()
    define(m, runtime)
    m.dictionary.comma(hi)
    m.dictionary.comma(lo)


prim("2CONSTANT", "( d -- ) a word that pushes d")(lambda m: _two_cells(m, "(DO2CON)"))
prim("2VALUE", "( d -- ) a word that pushes d until TO changes it")(
    lambda m: _two_cells(m, "(DO2VALUE)"))


@prim("BUFFER:", "( u -- ) a word naming u bytes")
def buffer_colon(m):
    define(m, "(DOVAR)")
    m.dictionary.allot(signed(m.s.pop()))


@prim("(UNINITIALIZED)", "( -- ) what an unset DEFER runs")
def uninitialized(m):
    raise ForthError(-257, "Uninitialized execution vector.")


@prim("DEFER", "( -- ) an execution vector, set with IS")
def defer(m):
    define(m, "(DODEFER)")
    m.dictionary.comma(m.xt_of["(UNINITIALIZED)"])


def _store_into(m, xt, two=False):
    """TO and IS: store into the body of xt, now or when the code runs."""
    body = (xt + 2) & MASK
    if compiling(m):
        compile_name(m, "LIT")
        m.dictionary.comma(body)
        compile_name(m, "2!" if two else "!")
    elif two:
        hi, lo = m.s.pop(), m.s.pop()
        m.memory.dstore(body, lo, hi)
    else:
        m.memory.store(body, m.s.pop())


@prim("TO", "( x -- ) set the VALUE that follows", immediate=True)
def to(m):
    name = parse_word(m)
    if compiling(m) and m.locals is not None and m.locals.store(m, name):
        return
    xt = tick(m, name)
    cf = m.memory.fetch(xt)
    if cf not in (inner.N["(DOVALUE)"], inner.N["(DO2VALUE)"]):
        raise ForthError(-32, "Not a VALUE", m.dictionary.name_of(xt))
    _store_into(m, xt, cf == inner.N["(DO2VALUE)"])


@prim("IS", "( xt -- ) set the DEFER that follows", immediate=True)
def is_(m):
    xt = tick(m, parse_word(m))
    if m.memory.fetch(xt) != inner.N["(DODEFER)"]:
        raise ForthError(-32, "Not a DEFER", m.dictionary.name_of(xt))
    _store_into(m, xt)


@prim("DEFER!", "( xt2 xt1 -- ) set DEFER xt1 to run xt2")
def defer_store(m):
    xt1 = m.s.pop()
    m.memory.store((xt1 + 2) & MASK, m.s.pop())


@prim("DEFER@", "( xt1 -- xt2 ) what DEFER xt1 runs")
def defer_fetch(m):
    m.s[-1] = m.memory.fetch((m.s[-1] + 2) & MASK)


@prim("ACTION-OF", "( -- xt ) what the DEFER that follows runs", immediate=True)
def action_of(m):
    xt = tick(m, parse_word(m))
    if compiling(m):
        compile_name(m, "LIT")
        m.dictionary.comma(xt)
        compile_name(m, "DEFER@")
    else:
        m.s.append(m.memory.fetch((xt + 2) & MASK))


prim("DOES>", "( -- ) the newest word will run the code that follows",
     immediate=True)(compile_only("DOES>", lambda m: compile_name(m, "(DOES>)")))


@prim("MARKER", "( -- ) a word that forgets itself and all after it")
def marker(m):
    start = m.dictionary.here
    define(m, "(DOMARKER)")
    m.dictionary.comma(start)


# --------------------------------------------------------------- CODE words
@prim("CODE", "( -- ) bind the next name to its Python primitive; skip the "
      "assembler text up to END-CODE or C;")
def code(m):
    name = parse_word(m)
    while True:
        tok, _ = m.parse_name()
        if tok.upper() in ("END-CODE", "C;"):
            break
        if not tok and not m.refill():
            break
    p = BY_NAME.get(name.upper())
    if p is None or p.kind is RUNTIME:
        raise ForthError(-263, "No CODE for " + name.upper())
    m.dictionary.create(name, p.number)
    m.xt_of.setdefault(p.name, m.dictionary.last + 2)
    if p.immediate:
        m.dictionary.set_flag(m.dictionary.last, IMMEDIATE)
