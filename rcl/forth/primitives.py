"""The registry of primitives: every CODE word is declared once, here-shaped.

    @prim("NIP", "( a b -- b )")
    def nip(m):
        del m.s[-2]

    prim("+", "( n1 n2 -- n3 )", inline=("a b", "(a + b) & 0xFFFF"))(None)

One declaration gives the dictionary its header, the inner interpreter its
function and cost, the compiler its inline template, SEE and WORDS the name.
A primitive the compiler may paste has one body, its inline template: the
function the interpreter calls is made from it at registration (`body_of`),
so what runs one primitive at a time and what runs compiled cannot differ:

    def f(m):                   # +, as made from its template
        s = m.s
        b = s.pop()
        a = s[-1]
        s[-1] = (a + b) & 0xFFFF

A primitive's number is its index in REGISTRY; that number is what its code
field holds in memory (so numbers stay below memory.PRIM_LIMIT).

Kinds (`PrimKind`, below): how the inner interpreter runs a primitive.
The compiler's kinds of instruction (compile_kinds.py) are made from these
once, where decode.py decodes a cell.

Inline templates: (inputs, outputs[, statement]). Inputs name the popped
cells, deepest first; outputs are Python expressions over them, pushed in
order; the statement runs after the inputs are taken. Besides the inputs a
template may name only the compiled function's locals (m, s, rs, mem, W),
the functions in HELPERS and a few builtins: each template is parsed once,
here, and an unknown name is refused at registration. The compiler fills in
a parsed template by formatting (`Template`), never by editing text.
"""
import ast
import enum
import sys
import types
from dataclasses import dataclass, field

from rcl.board import CLOCK_HZ  # noqa: F401  (the unit lives with the board interface)


class PrimKind(enum.Enum):
    """How the inner interpreter runs a primitive, as @prim declares it."""
    SIMPLE = "simple"     # fn(m); static cost; may be inlined by the compiler
    LITERAL = "literal"   # fn(m, *args): `args` inline cells decoded by `decode`
    CONTROL = "control"   # a branch, loop or EXIT: the interpreter and the compiler
                          # know each by name (control.py); fn is None
    CALL = "call"         # fn(m) may run Forth code, change the clock or the interrupt
                          # deadline: the compiler ends a block after it
    RUNTIME = "runtime"   # fn(m, xt, ip): what a defined word's code field does (DOCOL, ...)


# The kinds as plain names: declarations read `kind=CALL`, and the inner
# interpreter tests `p.kind is RUNTIME` on every call (a module global is
# read several times faster than an attribute of an Enum class).
SIMPLE, LITERAL, CONTROL = PrimKind.SIMPLE, PrimKind.LITERAL, PrimKind.CONTROL
CALL, RUNTIME = PrimKind.CALL, PrimKind.RUNTIME

HELPERS = {}                 # functions inline templates may call, by name
LOCALS = ("m", "s", "rs", "mem", "W")   # what compiled code binds, templates may use
BUILTINS = ("abs", "min", "max", "len")
DEFAULT_COST = 1_000_000     # clock units (1/36 ns): 1000/36 us per primitive
# The file name of Python made for Forth (compiled code, bodies made from
# templates): an IndexError raised there is a stack underflow (inner.py).
COMPILED = "<forth>"


@dataclass
class Prim:
    name: str
    effect: str
    fn: object
    kind: PrimKind = PrimKind.SIMPLE
    cost: int = DEFAULT_COST
    immediate: bool = False
    inline: tuple = None
    args: int = 0            # inline cells after the xt (literal kind)
    decode: object = None    # decode(m, ip) -> (args, next_ip) for odd inline data
    hidden: bool = False     # only enters the dictionary through CODE name
    wordlist: str = "FORTH"
    number: int = 0
    doc: str = ""
    touches_memory: bool = False   # inline form reads or writes memory
    extra: dict = field(default_factory=dict)
    template: object = None        # the parsed inline form (Template)


class Part:
    """One expression or statement of a template, parsed: `fmt` has the
    inputs as {0}, {1}, ...; `uses` are the locals it names; `fold`, for an
    expression over inputs and helpers only, computes it from numbers."""

    def __init__(self, word, text, inputs, mode):
        tree = ast.parse(text, mode=mode)
        starts = [0]
        for line in text.split("\n"):
            starts.append(starts[-1] + len(line) + 1)
        spans, self.uses = [], set()
        for node in ast.walk(tree):
            if not isinstance(node, ast.Name):
                continue
            if node.id in inputs:
                at = starts[node.lineno - 1] + node.col_offset
                spans.append((at, at + len(node.id), inputs.index(node.id)))
            elif node.id in LOCALS:
                self.uses.add(node.id)
            elif node.id not in HELPERS and node.id not in BUILTINS:
                raise ValueError("inline template of %s names %r" % (word, node.id))
        out, last = [], 0
        for start, end, i in sorted(spans):
            out.append(text[last:start].replace("{", "{{").replace("}", "}}"))
            out.append("{%d}" % i)
            last = end
        out.append(text[last:].replace("{", "{{").replace("}", "}}"))
        self.fmt = "".join(out)
        self.input = inputs.index(text) if text in inputs else None
        self.fold = None
        if mode == "eval" and not self.uses:
            self.fold = eval("lambda %s: %s" % (", ".join(inputs), text), dict(HELPERS))
        # A flag `0xFFFF if test else 0`: its test alone, for a branch on it
        body = tree.body if mode == "eval" else None
        self.test = None
        if isinstance(body, ast.IfExp) and all(
                isinstance(n, ast.Constant) for n in (body.body, body.orelse)) \
                and (body.body.value, body.orelse.value) == (0xFFFF, 0):
            self.test = Part(word, ast.get_source_segment(text, body.test), inputs, mode)

    def fill(self, atoms):
        return self.fmt.format(*atoms)


class Template:
    """A primitive's inline form: (inputs, outputs[, statement]), parsed."""

    def __init__(self, word, inline):
        self.inputs = inline[0].split()
        outs = inline[1]
        outs = [outs] if isinstance(outs, str) else list(outs)
        self.outputs = [Part(word, o, self.inputs, "eval") for o in outs]
        self.stmt = Part(word, inline[2], self.inputs, "exec") if len(inline) > 2 else None
        self.uses = set().union(*(o.uses for o in self.outputs),
                                self.stmt.uses if self.stmt else ())
        self.rs_push = rs_pushes(word, inline[2]) if len(inline) > 2 else 0


def rs_pushes(word, stmt):
    """How many cells a template's statement pushes on the return stack
    (pops not counted): rs.append(x) one, rs.extend((x, ...)) as many as
    written; any other growth is refused (the compiler must know the
    depth an inlined call after it reaches)."""
    n = 0
    for node in ast.walk(ast.parse(stmt)):
        f = node.func if isinstance(node, ast.Call) else None
        if not (isinstance(f, ast.Attribute) and isinstance(f.value, ast.Name)
                and f.value.id == "rs"):
            continue
        if f.attr == "append":
            n += 1
        elif f.attr == "extend" and isinstance(node.args[0], ast.Tuple):
            n += len(node.args[0].elts)
        elif f.attr not in ("pop", "clear"):
            raise ValueError("inline template of %s grows rs by rs.%s" % (word, f.attr))
    return n


def body_of(name, tpl):
    """The Python function of a primitive, made from its parsed template as
    the compiler pastes it: inputs popped (top first), the statement, the
    outputs pushed. When nothing else looks at the data stack, the deepest
    input is read in place and the first output stored over it (a pop and
    a push cost twice a store)."""
    ins = tpl.inputs
    outs = [o.fill(ins) for o in tpl.outputs]
    peek = bool(ins and outs) and tpl.stmt is None and "s" not in tpl.uses
    lines = ["%s = s.pop()" % x for x in reversed(ins[1 if peek else 0:])]
    if peek:
        lines.append("%s = s[-1]" % ins[0])
    if tpl.stmt is not None:
        lines.extend(tpl.stmt.fill(ins).split("\n"))
    if peek:
        first = outs.pop(0)
        if first != ins[0]:
            lines.append("s[-1] = %s" % first)
    if len(outs) == 1:
        lines.append("s.append(%s)" % outs[0])
    elif outs:
        lines.append("s.extend((%s))" % ", ".join(outs))
    binds = [("s", "m.s"), ("rs", "m.rs"), ("mem", "m.mem"), ("W", "m.watch")]
    uses = tpl.uses | ({"s"} if ins or outs else set())
    text = "\n".join(["def f(m):"] + ["    %s = %s" % b for b in binds if b[0] in uses]
                     + ["    " + line for line in lines or ["pass"]])
    env = types.ModuleType(COMPILED).__dict__      # (for PyPy's JIT, as compiled code's)
    env.update(HELPERS)
    exec(compile(text, COMPILED, "exec"), env)
    f = env["f"]
    f.__name__ = f.__qualname__ = name
    f.source = text
    return f


REGISTRY = [None]            # number 0 is never a valid code field
BY_NAME = {}


def prim(name, effect="", *, kind=SIMPLE, cost=DEFAULT_COST, immediate=False,
         inline=None, args=0, decode=None, hidden=False, wordlist="FORTH",
         memory=False, key=None):
    """Register the decorated function as the primitive `name`.

    `key` names the registry entry when the Forth name is shared (a runtime
    such as DOCOL has no Forth name of its own). With an inline template
    the primitive has no Python body of its own: register None, and the
    body is made from the template.
    """
    if not isinstance(kind, PrimKind):
        raise TypeError("%s: kind must be a primitives.PrimKind, not %r" % (name, kind))

    def register(fn):
        template = Template(name, inline) if inline is not None else None
        if template is not None:
            if fn is not None:
                raise ValueError("%s: its body is made from its inline template" % name)
            fn = body_of(name, template)
            # its word set is the module that declared it (as namedtuple finds its module)
            fn.__module__ = sys._getframe(1).f_globals.get("__name__", fn.__module__)
        p = Prim(name, effect, fn, kind, cost, immediate, inline, args, decode,
                 hidden, wordlist, len(REGISTRY), (fn.__doc__ or "").strip() if fn else "",
                 memory)
        p.template = template
        REGISTRY.append(p)
        BY_NAME[key or name] = p
        return fn
    return register


def number_of(key):
    return BY_NAME[key].number
