"""The standard tester: T{ ... -> ... }T, as John Hayes's tester and the
Forth 2012 test suite use it (rcl/kernel/03-tester.fs adds #ERRORS,
VERBOSE and TESTING).

    T{ 3.5 FEET EXPECTED -> 1193. }T
    |  `------ code -----'  `want'  |
    |  depth noted          results |  compare the cells above the noted depth
    `- where: file, line, column    `- report; the stack is back at the depth

The words are primitives rather than Forth so that each result can carry
where its T{ stood (file, line, column) and both stacks to a Python
listener: rcl's pytest plugin turns every }T into a test item. At the
prompt a failure prints the standard message, the source line and the
two stacks, counts in #ERRORS, and the session goes on.
"""
from dataclasses import dataclass, field

from rcl.forth.memory import MASK, signed
from rcl.forth import state as forth_state
from rcl.forth.primitives import prim
from rcl.words.io import in_base


@dataclass
class Result:
    """One T{ ... }T: where it stood and what it found (cells, signed)."""
    file: str = None          # the file being loaded, or None at the prompt
    line: int = 0             # the line T{ stood on (1-based)
    column: int = 0           # the offset just past T{ in that line
    end_line: int = 0         # the line }T stood on
    source: list = field(default_factory=list)   # the text of those lines
    expected: list = None
    actual: list = None
    ok: bool = False
    message: str = ""         # "" or the standard tester's complaint
    taken: int = 0            # cells the code took from below T{ (actual None)
    notes: str = ""           # what a listener adds (the pytest plugin: the robot)

    @property
    def text(self):
        return "\n".join(self.source)


class Tester:
    """A machine's tester state; `listener(result)` hears every }T."""

    def __init__(self):
        self.depth = 0
        self.pending = None       # the Result T{ started
        self.listener = None


# T{ ... }T's depth and pending result: the session's.
forth_state.session("tester", lambda m: Tester())


def state_of(m):
    return m.tester


def where(m):
    """(file, line, column, text) of the innermost source being read."""
    src = m.src
    col = m.memory.fetch(m.a_in)
    addr, length = m.source()
    text = m.memory.text(addr, length) if length < 1024 else ""
    return (src.name if src.kind == "file" else None), src.line, col, text


def cells(values):
    return [signed(v) for v in values]


def taken_text(n):
    return "(%d cell%s taken from below T{)" % (n, "" if n == 1 else "s")


def stack_picture(m, values):
    """Cells bottom first in BASE, signed, or `(empty)`."""
    return " ".join(in_base(m, v) for v in values) or "(empty)"


@prim("T{", "( -- ) start a test: note the depth and where it stands")
def t_open(m):
    state = state_of(m)
    state.depth = len(m.s)
    name, line, col, text = where(m)
    state.pending = Result(name, line, col, line, [text])


@prim("->", "( i*x -- ) the test's results: keep them and take them off")
def t_arrow(m):
    state = state_of(m)
    result = state.pending or Result()
    state.pending = result
    short = state.depth - len(m.s)
    if short > 0:                       # the code ate cells below T{
        result.actual, result.taken = None, short
        m.s.extend([0] * short)         # put the depth back, as EMPTY-STACK does
    else:
        result.actual = cells(m.s[state.depth:])
        del m.s[state.depth:]


@prim("}T", "( j*x -- ) compare with the results -> kept, report, count errors")
def t_close(m):
    state = state_of(m)
    result, state.pending = state.pending or Result(), None
    result.expected = cells(m.s[state.depth:])
    del m.s[state.depth:]
    name, line, _, text = where(m)
    if line != result.line and name == result.file:
        result.source.extend(source_lines(m, result.line, line, text))
        result.end_line = line
    judge(result)
    if not result.ok:
        complain(m, result)
    if state.listener is not None:
        state.listener(result)


def source_lines(m, first, last, text):
    """The lines after T{'s own, up to }T's (a test may span lines)."""
    src = m.src
    if src.text is not None and last <= len(src.text):
        return src.text[first:last]
    return [text]


def judge(result):
    if result.actual is None or len(result.actual) != len(result.expected):
        result.message = "WRONG NUMBER OF RESULTS"
    elif result.actual != result.expected:
        result.message = "INCORRECT RESULT"
    result.ok = not result.message


def complain(m, result):
    """The standard tester's message and line, then the two stacks."""
    actual = taken_text(result.taken) if result.actual is None \
        else stack_picture(m, result.actual)
    m.type("%s: %s\n  expected: %s\n  actual:   %s\n" % (
        result.message, " / ".join(s.strip() for s in result.source),
        stack_picture(m, result.expected), actual))
    hit = m.dictionary.find("#ERRORS")
    if hit is not None:
        body = (hit[0] + 2) & MASK
        m.memory.store(body, (m.memory.fetch(body) + 1) & MASK)
