"""The registry of primitives: every CODE word is declared once, here-shaped.

    @prim("+", "( n1 n2 -- n3 )", inline=("a b", "(a + b) & 0xFFFF"))
    def plus(m):
        s = m.s; b = s.pop(); s[-1] = (s[-1] + b) & 0xFFFF

One declaration gives the dictionary its header, the inner interpreter its
function and cost, the compiler its inline template, SEE and WORDS the name.

A primitive's number is its index in REGISTRY; that number is what its code
field holds in memory (so numbers stay below memory.PRIM_LIMIT).

Kinds:
  simple   fn(m); static cost; may be inlined by the compiler.
  literal  fn(m, *args) with `args` inline cells decoded by `decode`.
  control  branches, loops, EXIT: the inner interpreter and compiler know
           each by name; fn is None.
  call     fn(m) may run Forth code, change the clock or the interrupt
           deadline: the compiler ends a block after it.
  runtime  what a code field of a defined word does (DOCOL, DOVAR, ...).

Inline templates: (inputs, outputs[, statement]). Inputs name the popped
cells, deepest first; outputs are Python expressions over them, pushed in
order; the statement runs after the inputs are taken. Besides the inputs a
template may name only the compiled function's locals (m, s, rs, mem, W),
the functions in HELPERS and a few builtins: each template is parsed once,
here, and an unknown name is refused at registration. The compiler fills in
a parsed template by formatting (`Template`), never by editing text.
"""
import ast
from dataclasses import dataclass, field

from rcl.board import CLOCK_HZ  # noqa: F401  (the unit lives with the board interface)

HELPERS = {}                 # functions inline templates may call, by name
LOCALS = ("m", "s", "rs", "mem", "W")   # what compiled code binds, templates may use
BUILTINS = ("abs", "min", "max", "len")
DEFAULT_COST = 1_000_000     # clock units (1/36 ns): 1000/36 us per primitive


@dataclass
class Prim:
    name: str
    effect: str
    fn: object
    kind: str = "simple"
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


REGISTRY = [None]            # number 0 is never a valid code field
BY_NAME = {}


def prim(name, effect="", *, kind="simple", cost=DEFAULT_COST, immediate=False,
         inline=None, args=0, decode=None, hidden=False, wordlist="FORTH",
         memory=False, key=None):
    """Register the decorated function as the primitive `name`.

    `key` names the registry entry when the Forth name is shared (a runtime
    such as DOCOL has no Forth name of its own).
    """
    def register(fn):
        p = Prim(name, effect, fn, kind, cost, immediate, inline, args, decode,
                 hidden, wordlist, len(REGISTRY), (fn.__doc__ or "").strip() if fn else "",
                 memory)
        if inline is not None:
            p.template = Template(name, inline)
        REGISTRY.append(p)
        BY_NAME[key or name] = p
        return fn
    return register


def number_of(key):
    return BY_NAME[key].number
