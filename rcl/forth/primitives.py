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
order; the statement runs after the inputs are taken (m, mem, W and the
input names are in scope). The compiler substitutes names textually, so
input names are single letters a..e.
"""
from dataclasses import dataclass, field

from rcl.board import CLOCK_HZ  # noqa: F401  (the unit lives with the board interface)

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
        REGISTRY.append(p)
        BY_NAME[key or name] = p
        return fn
    return register


def number_of(key):
    return BY_NAME[key].number
