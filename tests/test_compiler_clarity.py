"""The compiler says each thing once: one table of control operations (a
reference function and a code generator side by side), inline templates
parsed at registration, the DO-loop frame in one helper, and a way to read
the Python a word becomes."""
import pytest

import rcl
import rcl.words  # noqa: F401  (every word set registered: the templates tested below)
from rcl.forth import compiler, control
from rcl.forth.compiler import Gen, source, walk
from rcl.forth.primitives import HELPERS, REGISTRY, Template
from compiler_support import PRIM, Ticker, code_lines, in_order


def both_ways(program, word, period=7 * PRIM + 4321):
    """Run program compiled and in the reference loop, with an interrupt
    source; -> what each did (output, stack, clock, interrupt times)."""
    runs = []
    for compiled in (True, False):
        m = rcl.Forth()
        m.compiled = compiled
        m.evaluate("VARIABLE TICKS  : TICK  1 TICKS +! ;")
        m.evaluate(program)
        t = Ticker(m, period)
        m.attach(t)
        out = m.evaluate(word)
        runs.append((out, m.stack, m.clock, t.times, m.evaluate("TICKS @ .")))
    return runs


# One program per control operation, each a definition W that uses it.
PROGRAMS = {
    "EXIT": ": W  1 EXIT 2 ;",
    "BRANCH": ": W  0 BEGIN 1+ DUP 30 > IF EXIT THEN AGAIN ;",
    "?BRANCH": ": W  0 40 0 DO I 3 MOD IF 1+ ELSE 2 + THEN LOOP ;",
    "(DO)": ": W  0 25 0 DO I + LOOP  0 0 DO 1+ DUP 1000 = IF LEAVE THEN LOOP ;",
    "(?DO)": ": W  0 0 ?DO I LOOP  30 10 ?DO I LOOP ;",
    "(LOOP)": ": W  0 32767 32760 DO I + LOOP  3 0 DO -32760 -32767 DO J I + LOOP LOOP ;",
    "(+LOOP)": ": W  0 10 DO I -3 +LOOP  0 30 0 DO I + 7 +LOOP ;",
    "(LEAVE)": ": W  20 0 DO I DUP 13 = IF LEAVE THEN LOOP ;",
    "(?LEAVE)": ": W  20 0 DO I DUP 11 = ?LEAVE LOOP ;",
    "(DOES>)": ": K  CREATE , DOES> @ 2* ;  30 K X  : W  X X + ;",
    "EXECUTE": ": Y  DUP * ;  : W  0 20 0 DO I ['] Y EXECUTE + LOOP ;",
}


def test_there_is_one_program_for_every_control_operation():
    assert set(PROGRAMS) == set(control.BY_NAME)


@pytest.mark.parametrize("name", sorted(PROGRAMS))
def test_every_control_operation_runs_the_same_compiled_and_in_the_reference_loop(name):
    program = PROGRAMS[name]
    compiled, reference = both_ways(program, "W")
    assert compiled == reference
    assert compiled[3], "the interrupt source fired"
    m = rcl.Forth()
    m.evaluate(program)
    body = (m.dictionary.find("W")[0] + 2) & 0xFFFF
    code, _ = walk(m, body)
    ops = {i.op for i in code.values()}
    assert name in ops or name == "(DOES>)"     # DOES> is in K, which W's X uses


def test_the_do_loop_frame_runs_as_f83s():
    def count(limit, start, step):
        _, index = control.do_frame(limit, start)
        n = 0
        while index is not None and n < 70000:
            n += 1
            index = control.loop_step(index, step)
        return n
    assert count(10, 0, 1) == 10
    assert count(0, 10, 0xFFFF) == 11           # 0 10 DO ... -1 +LOOP: 10 down to 0
    assert count(0, 0, 1) == 65536              # DO with limit = start runs 65536 times
    assert count(-32768 & 0xFFFF, 32767, 1) == 1
    assert count(30, 0, 7) == 5


def test_an_inline_template_naming_an_unknown_name_is_refused_at_registration():
    with pytest.raises(ValueError, match="names 'spam'"):
        Template("X", ("a", ("spam(a)",)))
    with pytest.raises(ValueError, match="names 'c'"):
        Template("X", ("a b", ("a + c",)))
    Template("X", ("a b", ("FDIV(a, b)", "rs[-1]"), "mem[a] = b"))


SAMPLES = [0, 1, 2, 7, 15, 16, 0x7FFF, 0x8000, 0x8001, 0xFFFE, 0xFFFF, 1234]


def run_template(m, p):
    """p's inline template, as the compiler fills it in, run on m."""
    g = Gen(m, 0)
    g.op_inline(p, 1)
    g.flush(1)
    src = "def t(m):\n    s = m.s; rs = m.rs; mem = m.mem; W = m.watch\n" + "\n".join(g.lines)
    env = dict(HELPERS)
    exec(src, env)
    env["t"](m)


@pytest.mark.parametrize("p", [p for p in REGISTRY[1:] if p and p.template is not None],
                         ids=lambda p: p.name)
def test_each_inline_template_does_what_its_python_body_does(p):
    n = len(p.template.inputs)
    for i, first in enumerate(SAMPLES):
        cells = [SAMPLES[(i + 3 * j) % len(SAMPLES)] for j in range(n)]
        if n:
            cells[0] = first
        if p.touches_memory:                     # an address in free space, last
            cells[-1] = 0x9000 + 2 * i
        states = []
        for run in (lambda m: p.fn(m), lambda m: run_template(m, p)):
            m = rcl.Forth()
            m.s[:] = [11, 12] + cells
            m.rs[:] = [21, 22, 23, 24, 25, 26]
            m.mem[0x9000:0x9020] = bytes(range(0x20, 0x40))
            run(m)
            states.append((list(m.s), list(m.rs), bytes(m.mem[0x9000:0x9020])))
        assert states[0] == states[1], (p.name, cells)


def compiled_source(program, word="W"):
    m = rcl.Forth()
    m.evaluate(program)
    return source(m, word)


def test_constants_are_folded_as_the_word_computes_them():
    src = compiled_source(": W  2 3 + 7 * 100 MOD ;")
    assert "s.append(35)" in src
    assert "FMOD(" not in src and "& 0xFFFF" not in src


def test_the_prologue_binds_only_the_locals_the_code_uses():
    assert compiled_source(": W  DUP + ;").splitlines()[1] == "    s = m.s; rs = m.rs; clk = m.clock"
    assert "mem = m.mem" in compiled_source(": W  @ ;").splitlines()[1]
    assert "W = m.watch" in compiled_source(": W  ! ;").splitlines()[1]


def test_the_python_of_a_word_can_be_printed_and_is_what_runs():
    m = rcl.Forth()
    m.evaluate(": SQ  DUP * ;  : K  CREATE , DOES> @ SQ ;  3 K NINE  NINE .")
    sq = source(m, "SQ")
    assert sq.startswith("def f(m):") and "t1 * t1" in sq.replace("(", "").replace(")", "")
    body = (m.dictionary.find("SQ")[0] + 2) & 0xFFFF
    assert m.fn[body].source == sq
    assert "def f(m):" in source(m, "NINE")           # the code after DOES>
    with pytest.raises(ValueError):
        source(m, "DUP")
    with pytest.raises(LookupError):
        source(m, "NO-SUCH-WORD")
    assert "source(m" in compiler.__doc__


def test_the_compilers_walk_through_shows_the_python_that_source_prints():
    from rcl.forth import compile_block
    m = rcl.Forth()
    m.evaluate(": COUNTDOWN  BEGIN 1- DUP 0= UNTIL ;  : SQ+1  DUP * 1+ ;")
    doc = compiler.__doc__
    example = doc[doc.index("    def f(m):"):doc.index("m.clock = clk\n") + len("m.clock = clk")]
    shown = [line[4:] for line in code_lines(example)]
    assert len(shown) > 20 and in_order(shown, code_lines(source(m, "COUNTDOWN")))
    sq = code_lines(source(m, "SQ+1"))
    doc = compile_block.__doc__
    first = doc[doc.index(": SQ+1"):].splitlines()[:4]
    col = first[0].index("t1 = ")                  # the Python column, beside the Forth
    body = [line[col:].split(" #")[0].strip() for line in first]
    assert len(body) == 4 and in_order(body, [line.strip() for line in sq])


def test_a_short_stack_is_stack_underflow_both_ways():
    for compiled in (True, False):
        m = rcl.Forth()
        m.compiled = compiled
        m.evaluate(": W  + ;  : V  2DROP DROP ;")
        for line in ("1 W", "DROP", "1 2 V", "5 PICK"):
            with pytest.raises(rcl.ForthError) as e:
                m.evaluate(line)
            assert e.value.code == -4, line


def test_any_other_index_error_in_a_word_is_an_internal_error_tests_can_see(monkeypatch):
    depth = next(p for p in REGISTRY[1:] if p and p.name == "DEPTH")

    def broken(m):
        m.s.append((1, 2, 3)[m.s[-1]])           # a bug: indexes a table
    monkeypatch.setattr(depth, "fn", broken)
    m = rcl.Forth()
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("1 2 3 4 5 6 7 8 9 10 DEPTH")
    assert e.value.code == -4095
    assert "IndexError" in e.value.message
    assert m.evaluate("2 3 + .") == "5 "


def test_the_compiler_asks_an_instructions_kind_and_never_compares_its_name():
    """What the compiler does with each kind of instruction is one class in
    compile_kinds.py (adding a kind is one edit there): no other module of
    the compiler tests an instruction's op against a kind's name."""
    import ast
    import inspect
    from rcl.forth import compile_block, compile_kinds, compile_loops, decode, loop_shape
    names = {k.name for k in vars(compile_kinds).values()
             if isinstance(k, compile_kinds.Kind) and k.name is not None}
    assert {"simple", "literal", "call", "colon", "defer", "inline", "enter"} <= names
    for module in (compiler, compile_block, compile_loops, decode, loop_shape):
        for node in ast.walk(ast.parse(inspect.getsource(module))):
            if isinstance(node, ast.Compare) and any(
                    getattr(n, "attr", getattr(n, "id", None)) == "op" for n in ast.walk(node)):
                said = {c.value for c in ast.walk(node) if isinstance(c, ast.Constant)}
                assert not said & names, (module.__name__, ast.unparse(node))
    m = rcl.Forth()
    m.evaluate(": SQ  DUP * ;  5 CONSTANT C  : W  0 10 0 DO I SQ + LOOP ['] SQ EXECUTE C + . ;")
    code, _ = walk(m, (m.dictionary.find("W")[0] + 2) & 0xFFFF)
    kinds = {i.kind for i in code.values()}
    assert all(isinstance(k, compile_kinds.Kind) for k in kinds)
    assert {compile_kinds.LITERAL, compile_kinds.INLINE, compile_kinds.CONST} <= kinds


def test_an_inlinable_primitive_has_one_body_its_template():
    """The function the interpreter calls is made from the template (so it
    cannot differ from what the compiler pastes); a second body is refused."""
    from rcl.forth import primitives
    plus = primitives.BY_NAME["+"]
    doc = primitives.__doc__
    shown = doc[doc.index("    def f(m):"):].split("\n\n")[0]
    assert [line.split("#")[0].strip() for line in shown.splitlines()] == \
        [line.strip() for line in plus.fn.source.splitlines()]
    assert all(p.fn.source for p in REGISTRY[1:] if p and p.template is not None)
    with pytest.raises(ValueError, match="made from its inline template"):
        primitives.prim("X", "( a -- a )", inline=("a", ("a",)))(lambda m: None)
    assert "X" not in primitives.BY_NAME


def test_a_primitives_kind_is_a_declared_type_and_a_string_is_refused():
    """@prim's kind is one of primitives.PrimKind (the interpreter tests it
    by identity); a kind given as a string, a slip that would make every
    `p.kind is CALL` false, is refused where it is declared."""
    from rcl.forth.primitives import CALL, PrimKind, prim
    assert {p.kind for p in REGISTRY[1:]} == set(PrimKind)
    assert REGISTRY[1].kind in PrimKind
    before = len(REGISTRY)
    with pytest.raises(TypeError, match="PrimKind"):
        prim("NOT-A-WORD", "( -- )", kind="call")
    assert len(REGISTRY) == before
    assert CALL is PrimKind.CALL and CALL.value == "call"      # (the image's fingerprint)
