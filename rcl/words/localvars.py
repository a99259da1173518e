"""Locals word set (Forth 2012 chapter 13): {: ... :}, (LOCAL), LOCALS|.

A definition's locals live in one frame on the return stack, laid down
when the declaration runs and dropped by ; or EXIT:

    : F  {: a b | c -- x :}  a b + c ... ;      1 2 F

    compiles   (LOCALS) 2 1   (LOCAL@) 3  (LOCAL@) 2  +  (LOCAL@) 1 ...
               (UNLOCALS) 3  EXIT
    R: ... ret | a=1 | b=2 | c=0 |      (LOCAL@) k reads rs[-k]

k counts from the top of the return stack at the point of use: a DO
loop's three cells are above the frame, so inside one k grows by 3 per
loop (found from the DO markers on the compile-time stack).

Speed: each of these runtimes carries an inline template built from its
inline cells (extra["inline_args"]), so the compiler pastes `rs[-3]`
where (LOCAL@) 3 stands, as it pastes R@ for R@: a local costs what
the stack shuffle it replaces costs.

While a definition with locals is compiled, the outer interpreter asks
`LocalScope.compile` first with each name (outer.py), so locals shadow
every word; ; and TO know them too (compiling.py).
"""
from functools import lru_cache

from rcl.errors import ForthError
from rcl.forth.primitives import BY_NAME, LITERAL, Template, prim
from rcl.words.compiling import DO_SYS, compile_name, compile_only, parse_word

MAX_LOCALS = 32
LETTERS = "abcdefghijkl"          # input names for the frame's inline template


# ---------------------------------------------------------------- runtimes
@prim("(LOCALS)", "( x1 .. xn -- ) R: ( -- x1 .. xn 0 .. 0 ) a locals frame: "
      "n from the stack, u zeros", kind=LITERAL, args=2)
def paren_locals(m, n, u):
    s = m.s
    if n > len(s):
        raise ForthError(-4)
    m.rs.extend(s[len(s) - n:])
    del s[len(s) - n:]
    m.rs.extend([0] * u)


@prim("(LOCAL@)", "( -- x ) the local k cells down the return stack",
      kind=LITERAL, args=1)
def paren_local_fetch(m, k):
    m.s.append(m.rs[-k])


@prim("(LOCAL!)", "( x -- ) store into the local k cells down the return stack",
      kind=LITERAL, args=1)
def paren_local_store(m, k):
    m.rs[-k] = m.s.pop()


@prim("(UNLOCALS)", "( -- ) R: ( frame -- ) drop a locals frame of n cells",
      kind=LITERAL, args=1)
def paren_unlocals(m, n):
    del m.rs[len(m.rs) - n:]


# Each template is parsed once per distinct inline cells (primitives.Template).
@lru_cache(maxsize=None)
def frame_template(args):
    n, u = args
    if n > len(LETTERS):
        return None                        # a big frame runs through its function
    names = " ".join(LETTERS[:n])
    cells = ", ".join(list(LETTERS[:n]) + ["0"] * u)
    return Template("(LOCALS)", (names, (), "rs.extend((%s,))" % cells if cells else "pass"))


@lru_cache(maxsize=None)
def fetch_template(args):
    return Template("(LOCAL@)", ("", ("rs[-%d]" % args[0],)))


@lru_cache(maxsize=None)
def store_template(args):
    return Template("(LOCAL!)", ("a", (), "rs[-%d] = a" % args[0]))


@lru_cache(maxsize=None)
def unframe_template(args):
    return Template("(UNLOCALS)", ("", (), "del rs[-%d:]" % args[0]))


BY_NAME["(LOCALS)"].extra["inline_args"] = frame_template
BY_NAME["(LOCAL@)"].extra["inline_args"] = fetch_template
BY_NAME["(LOCAL!)"].extra["inline_args"] = store_template
BY_NAME["(UNLOCALS)"].extra["inline_args"] = unframe_template
# What each does to the return stack's depth: an inlined call after it must
# overflow where the real one would (compiler.Gen.depth_check).
BY_NAME["(LOCALS)"].extra["rs_cells"] = lambda args: args[0] + args[1]
BY_NAME["(UNLOCALS)"].extra["rs_cells"] = lambda args: -args[0]


# Within one block of compiled code (compiler.py) the locals' values are
# Python names already: a read is then no code at all, as a DUP is.
# `gen.rs_known` lists them; the frame itself is only pushed
# (`gen.rs_pending`) when something may look at the return stack or the
# block ends, so a definition that fits one block never builds it.
def compile_frame(gen, args, ind):
    n, u = args
    if n > len(LETTERS):
        return False
    gen.forget_rs(ind)
    gen.index_atom = None                  # I's cells are no longer on top
    cells = gen.take(n, ind) + ["0"] * u
    gen.rs_known = cells
    gen.rs_pending = "rs.extend((%s,))" % ", ".join(cells) if cells else None
    return True


def compile_fetch(gen, args, ind):
    known, k = gen.rs_known, args[0]
    if known is None or k > len(known):
        return False                       # the template's rs[-k] then
    gen.vs.append(known[-k])
    return True


def compile_store(gen, args, ind):
    known, k = gen.rs_known, args[0]
    gen.index_atom = None                  # (a store could hit a loop's cells)
    (atom,) = gen.take(1, ind)
    if known is not None and k <= len(known):
        known[-k] = atom
        if gen.rs_pending:                  # the frame, when pushed, holds it
            gen.rs_pending = "rs.extend((%s,))" % ", ".join(known)
            return True
    gen.emit("rs[-%d] = %s" % (k, atom), ind, "rs")
    return True


def compile_unframe(gen, args, ind):
    if gen.rs_pending is None:
        gen.emit("del rs[-%d:]" % args[0], ind, "rs")
    gen.index_atom = None
    gen.rs_known = gen.rs_pending = None    # a frame never pushed is not popped
    return True


for _name, _hook in (("(LOCALS)", compile_frame), ("(LOCAL@)", compile_fetch),
                     ("(LOCAL!)", compile_store), ("(UNLOCALS)", compile_unframe)):
    BY_NAME[_name].extra["compile"] = _hook


# ----------------------------------------------------------- compile time
class LocalScope:
    """The locals of the definition being compiled (names in frame order)."""

    def __init__(self):
        self.names = []
        self.pending = []              # (LOCAL) names not yet in a frame
        self.closed = False

    def offset(self, m, name):
        """k for (LOCAL@) k, or None if name is no local."""
        upper = name.upper()
        if upper not in self.names:
            return None
        i = len(self.names) - 1 - self.names[::-1].index(upper)   # the newest
        loops = sum(1 for v in m.s[m.memory.fetch(m.a_csp):] if v == DO_SYS)
        return len(self.names) - i + 3 * loops

    def compile(self, m, name):
        """Compile name if it is a local or ends the frame; True if done."""
        upper = name.upper()
        k = self.offset(m, name)
        if k is not None:
            compile_name(m, "(LOCAL@)")
            m.dictionary.comma(k)
            return True
        if upper == "EXIT":
            self.unwind(m)
            compile_name(m, "EXIT")
            return True
        if upper == "DOES>":           # the DOES> part runs without the frame
            self.unwind(m)
            m.locals = None
        return False

    def store(self, m, name):
        """From TO: compile a store into local name; False if it is none."""
        k = self.offset(m, name)
        if k is None:
            return False
        compile_name(m, "(LOCAL!)")
        m.dictionary.comma(k)
        return True

    def unwind(self, m):
        if self.names:
            compile_name(m, "(UNLOCALS)")
            m.dictionary.comma(len(self.names))

    def declare(self, m, args, zeros):
        if self.closed:
            raise ForthError(-264, "Locals declared twice")
        if len(self.names) + len(args) + len(zeros) > MAX_LOCALS:
            raise ForthError(-265, "Too many locals")
        self.names += [a.upper() for a in args] + [z.upper() for z in zeros]
        self.closed = True
        compile_name(m, "(LOCALS)")
        m.dictionary.comma(len(args))
        m.dictionary.comma(len(zeros))


def scope(m):
    """The current definition's scope, made on first use."""
    if m.locals is None:
        m.locals = LocalScope()
    return m.locals


# -------------------------------------------------------------- the words
def next_token(m):
    """The next name, across line ends; '' when the input is dry."""
    while True:
        name, _ = m.parse_name()
        if name or not m.refill():
            return name


def brace_colon(m):
    args, zeros, part = [], [], "args"
    while True:
        tok = next_token(m)
        if not tok:
            raise ForthError(-16, "Name expected", "{:")
        word = tok.upper()
        if word == ":}":
            break
        if word == "|" and part == "args":
            part = "zeros"
        elif word == "--":
            part = "outputs"
        elif part == "args":
            args.append(tok)
        elif part == "zeros":
            zeros.append(tok)
    scope(m).declare(m, args, zeros)


prim("{:", "( x1 .. xn -- ) {: args | vals -- outs :} declares locals: args from "
     "the stack (the last one from the top), vals zero", immediate=True)(
    compile_only("{:", brace_colon))


def paren_local(m):
    u, a = m.s.pop(), m.s.pop()
    sc = scope(m)
    if u:
        sc.pending.append(m.memory.text(a, u))
    else:                               # the end: the first named takes the top
        names, sc.pending = sc.pending[::-1], []
        sc.declare(m, names, [])


# Not compile-only: the immediate words that use it run it between [ and ].
prim("(LOCAL)", "( addr u -- ) declare a local; 0 0 ends the declarations. "
     "Run: the first declared takes the top of the stack")(paren_local)


def locals_bar(m):
    names = []
    while True:
        tok = next_token(m)
        if not tok:
            raise ForthError(-16, "Name expected", "LOCALS|")
        if tok == "|":
            break
        names.append(tok)
    scope(m).declare(m, names[::-1], [])


prim("LOCALS|", "( xn .. x1 -- ) LOCALS| a b | : a takes the top of the stack "
     "(Forth 94's order)", immediate=True)(compile_only("LOCALS|", locals_bar))
