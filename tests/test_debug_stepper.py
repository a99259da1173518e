"""The stepping engine (rcl/forth/stepper.py) and the words DBG, BREAK:,
BREAK", BREAKS and ~~ (rcl/words/debugging.py), in process: the keys go
through KEY's path (typed-ahead keys, `m.keys`), as at the prompt."""
import pathlib

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

import rcl
from rcl.forth import stepper
from rcl.forth.primitives import BY_NAME

EXAMPLES = pathlib.Path(rcl.SCREENS) / "examples"
MOTOR_BITS = 0x35               # M1-ON M2-ON M1-GO M2-GO: MOTOR latch bits 0, 2, 4, 5
# TRIP's first row (listing5.fs line 19) and its BACKWARD, as a word of its
# own, with a BREAK: (which costs no time) to see where BACKWARD ended
TRIP1 = ": TRIP1  WARNING RERB 20 IPS 3 FEET BACKWARD BREAK: TURN-AROUND ;"


def keys(m, text):
    """Type keys ahead, as a user would (Enter is 13)."""
    m.keys.extend(13 if c == "\n" else ord(c) for c in text)


def steps(out):
    """The step lines of the view: [(place, chain > word)]."""
    found = []
    for line in out.split("\n"):
        parts = line.split("  ")
        if line.startswith("  ") and len(parts) > 2 and (":" in parts[1] or parts[1] == "(typed)"):
            found.append((parts[1], parts[2]))
    return found


@pytest.fixture
def rt(tmp_path, forth):
    """A bare machine with a two-word program loaded from rt.fs."""
    path = tmp_path / "rt.fs"
    path.write_text(": SQ  ( n -- n*n )\n  DUP * ;\n"
                    ": SUMSQ  ( a b -- a*a+b*b )\n  SQ SWAP\n  SQ + ;\n")
    forth.include(str(path))
    return forth


# ---------------------------------------------------------------- DBG
def test_dbg_steps_each_word_with_its_file_line_and_the_stack(rt):
    keys(rt, "oooo")
    out = rt.evaluate("3 4 DBG SUMSQ")
    assert steps(out) == [("rt.fs:4", "SUMSQ > SQ"), ("rt.fs:4", "SUMSQ > SWAP"),
                          ("rt.fs:5", "SUMSQ > SQ"), ("rt.fs:5", "SUMSQ > +")]
    assert "( 3 4 )" in out.split("\n")[2] and "( 3 16 )" in out.split("\n")[3]
    assert out.rstrip().endswith("done  ( 25 )")
    assert rt.stack == [25]


def test_into_steps_the_called_words_body_and_finish_leaves_it(rt):
    keys(rt, "iofooo")
    out = rt.evaluate("3 4 DBG SUMSQ")
    assert steps(out) == [("rt.fs:4", "SUMSQ > SQ"), ("rt.fs:2", "SUMSQ > SQ > DUP"),
                          ("rt.fs:2", "SUMSQ > SQ > *"), ("rt.fs:4", "SUMSQ > SWAP"),
                          ("rt.fs:5", "SUMSQ > SQ"), ("rt.fs:5", "SUMSQ > +")]
    assert rt.stack == [25]


def test_enter_steps_into_the_users_words_and_over_the_systems(rt):
    keys(rt, "\n\n\n\n\n\n\n\n\n")
    out = rt.evaluate("3 4 DBG SUMSQ")
    assert [w for _, w in steps(out)] == [
        "SUMSQ > SQ", "SUMSQ > SQ > DUP", "SUMSQ > SQ > *", "SUMSQ > SWAP",
        "SUMSQ > SQ", "SUMSQ > SQ > DUP", "SUMSQ > SQ > *", "SUMSQ > +"]


def test_continue_runs_to_the_end(rt):
    keys(rt, "c")
    rt.evaluate("3 4 DBG SUMSQ")
    assert rt.stack == [25] and rt.keys == []


def test_q_stops_as_an_abort_does(rt):
    keys(rt, "\nq")
    with pytest.raises(rcl.ForthError) as e:
        rt.evaluate("3 4 DBG SUMSQ")
    assert e.value.message == "Stopped" and rt.stack == []


def test_another_key_shows_the_keys(rt):
    keys(rt, "xc")
    out = rt.evaluate("3 4 DBG SUMSQ")
    assert out.split("\n")[3] == " Enter step  I into  O over  F finish  C continue  Q stop"


def test_dbg_of_a_primitive_says_it_steps_colon_definitions(forth):
    with pytest.raises(rcl.ForthError) as e:
        forth.evaluate("DBG DUP")
    assert "not a colon definition" in e.value.display()


def test_dbg_costs_no_virtual_time(rt):
    plain = rcl.Forth()
    plain.evaluate(": SQ DUP * ; : SUMSQ SQ SWAP SQ + ;")
    rt.clock = plain.clock = 0
    plain.evaluate("3 4 SUMSQ")
    keys(rt, "i\n\n\nc")
    rt.evaluate("3 4 DBG SUMSQ")
    assert rt.clock == plain.clock


# ----------------------------------------------------- stepping = running
WORDS = ["DUP", "DROP", "SWAP", "OVER", "+", "-", "*", "1+", "2*", "NEGATE",
         "ABS", "MAX", "V @ +", "DUP V !", "V +!", "H1", "H2"]


def body():
    atom = st.one_of(st.sampled_from(WORDS), st.integers(-99, 99).map(str))
    seq = st.lists(atom, min_size=1, max_size=5).map(" ".join)
    ifs = seq.flatmap(lambda a: seq.map(lambda b: "0< IF %s ELSE %s THEN" % (a, b)))
    loop = seq.map(lambda a: "3 0 DO I + %s LOOP" % a)
    return st.lists(st.one_of(seq, ifs, loop), min_size=1, max_size=4).map(" ".join)


PROGRAM = """VARIABLE V
: H1 ( n -- n' ) DUP 0< IF NEGATE THEN 7 + ;
: H2 ( a b -- c ) H1 SWAP H1 * 1000 MOD ;
"""


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(body(), st.text("\niofc", min_size=0, max_size=40))
def test_stepping_a_word_leaves_what_running_it_leaves(code, typed):
    runs = []
    for how in ("run", "dbg"):
        m = rcl.Forth()
        m.evaluate(PROGRAM + ": W " + code + " ;")
        m.clock = 0
        m.evaluate("5 0 0 0 0 0 0 0 0")
        if how == "dbg":
            keys(m, typed + "c")
            try:
                m.evaluate("DBG W")
            except rcl.ForthError as e:
                runs.append(("error", e.code))
                continue
        else:
            try:
                m.evaluate("W")
            except rcl.ForthError as e:
                runs.append(("error", e.code))
                continue
        v = m.dictionary.find("V")[0] + 2
        runs.append((m.stack, m.memory.fetch(v), m.clock))
    assert runs[0] == runs[1]


# ------------------------------------------------------------- BREAK:
def test_break_stops_in_a_compiled_word_and_continues_after_it(forth):
    forth.evaluate(": FOO  1 BREAK: 2 + ; : BAR  FOO 10 * ;")
    keys(forth, "\n")
    out = forth.evaluate("BAR")
    lines = out.split("\n")
    assert lines[1] == " BREAK:" and "FOO > +  ( 1 2 )" in lines[2]
    assert forth.stack == [30]


def test_break_quote_names_the_stop(forth):
    forth.evaluate(': FOO  1 BREAK" after one" 2 + ;')
    keys(forth, "c")
    out = forth.evaluate("FOO")
    assert out.split("\n")[1] == ' BREAK" after one"'
    assert forth.stack == [3]


def test_a_break_inside_a_do_loop_steps_the_rest_of_the_loop(forth):
    # the view's frame starts under the loop's three return-stack cells:
    # it ends at FOO's EXIT, not when the loop ends
    forth.evaluate(": FOO  0 4 0 DO I + I 2 = IF BREAK: THEN LOOP 100 + ;")
    keys(forth, "\n" * 5)
    out = forth.evaluate("FOO")
    assert [w for _, w in steps(out)] == ["FOO > I", "FOO > +", "FOO > I", "FOO > =",
                                          "FOO > +"]
    assert out.endswith("  done  ( 106 )")
    assert forth.stack == [106] and forth.rs == [] and forth.keys == []


def test_a_break_in_a_word_stepped_over_opens_a_view_of_its_own(forth):
    forth.evaluate(": IN  1 BREAK: 2 ; : OUT  IN + ;")
    keys(forth, "occ")
    out = forth.evaluate("DBG OUT")
    assert out.split("\n")[2:] == ["  (typed)  OUT > IN  ( )", " BREAK:", "  done  ( 1 2 )",
                                    "  (typed)  OUT > +  ( 1 2 )", "  done  ( 3 )"]
    assert forth.stack == [3] and forth.keys == [ord("c")]


def test_continue_stops_at_each_pass_of_a_break_in_a_loop(forth):
    forth.evaluate(': LP  3 0 DO I BREAK" in loop" DROP LOOP ; : CALLS  LP 7 ;')
    keys(forth, "ccc")
    out = forth.evaluate("CALLS")
    assert out.count(' BREAK" in loop"') == 3
    assert [line for line in out.split("\n") if "LP >" in line] == [
        "  (typed)  LP > DROP  ( 0 )", "  (typed)  LP > DROP  ( 1 )",
        "  (typed)  LP > DROP  ( 2 )"]
    assert forth.stack == [7] and forth.rs == []


def test_breaks_off_runs_through_without_recompiling(forth):
    forth.evaluate(": FOO  1 BREAK: 2 + ;")
    forth.evaluate("BREAKS OFF")
    out = forth.evaluate("FOO")
    assert out == "" and forth.stack == [3]
    keys(forth, "c")
    forth.evaluate("BREAKS ON FOO")
    assert forth.stack == [3, 3] and forth.keys == []


def test_a_break_costs_no_virtual_time(forth):
    forth.evaluate(": A 1 2 + DROP ; : B 1 2 BREAK: + DROP ; BREAKS OFF")
    forth.clock = 0
    forth.evaluate("A")
    a = forth.clock
    forth.clock = 0
    forth.evaluate("B")
    assert forth.clock == a


def test_breaks_runtime_run_from_the_prompt_steps_nothing(forth):
    assert forth.evaluate("1 2 (BREAK)") == "" and forth.stack == [1, 2]


def test_break_outside_a_definition_is_compile_only(forth):
    with pytest.raises(rcl.ForthError) as e:
        forth.evaluate("BREAK:")
    assert e.value.code == -14


# ------------------------------------------------------------------- ~~
def test_tilde_shows_file_line_word_and_stack_and_goes_on(tmp_path, forth):
    path = tmp_path / "t.fs"
    path.write_text(": FOO  1 2\n  ~~ + ;\n")
    forth.include(str(path))
    assert forth.evaluate("FOO") == "\n~~ t.fs:2 FOO  ( 1 2 )\n"
    assert forth.stack == [3]


def test_tilde_typed_shows_the_stack(forth):
    assert forth.evaluate("7 ~~") == "\n~~ (typed)  ( 7 )\n"


# ---------------------------------------------------------- on the robot
@pytest.fixture(scope="module")
def trip_start():
    """TRIP's first row run plainly (compiled), seen at a BREAK: right
    after BACKWARD: (pose, clock) there."""
    m = rcl.open()
    for name in ("listing4.fs", "listing5.fs"):
        m.include(EXAMPLES / name)
    m.evaluate(TRIP1)
    seen = []

    def key():
        seen.append((m.sim.pose, m.clock))
        return ord("q")
    m.read_key = key
    with pytest.raises(rcl.ForthError):
        m.evaluate("TRIP1")
    return seen[0]


def test_stepping_trip_names_its_words_and_a_move_ends_where_a_plain_runs_does(trip_start):
    m = rcl.open()
    for name in ("listing4.fs", "listing5.fs"):
        m.include(EXAMPLES / name)
    m.evaluate(TRIP1)                        # the same dictionary and clock as the plain run
    s = stepper.Stepper(m)
    shown = [s.start(m.dictionary.find("TRIP")[0])]
    for _ in range(5):
        shown.append(s.advance(stepper.OVER))
    assert [(st.word, st.line) for st in shown] == [
        ("WARNING", 19), ("RERB", 19), ("IPS", 19), ("FEET", 19), ("BACKWARD", 20),
        ("TURN-AROUND", 20)]
    assert shown[3].stack == [3]
    assert shown[-1].ran == "BACKWARD" and shown[-1].moved
    assert (shown[-1].pose, m.clock) == trip_start
    assert shown[-1].pose[0] == pytest.approx(-36, abs=1)   # 3 feet back


def test_q_inside_a_move_stops_the_motors():
    m = rcl.open()
    for name in ("listing4.fs", "listing5.fs"):
        m.include(EXAMPLES / name)
    shown, motors = [], []
    m.write = shown.append

    def key():
        # over WARNING RERB IPS FEET, into BACKWARD and (MOVE), then over
        # each word up to its wait: the motors run there; then Q
        screen = "".join(shown)
        if "> WAIT-MOVE" not in screen.split("\n")[-1]:
            return ord("o")
        motors.append(m.sim.relays[0] & MOTOR_BITS)
        return ord("q")
    m.read_key = key
    keys(m, "oooo" + "ii")
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("DBG TRIP")
    assert e.value.message == "Stopped"
    assert motors == [MOTOR_BITS]            # both wheels on at the view
    assert m.sim.relays[0] & MOTOR_BITS == 0


def test_on_a_board_over_a_link_the_view_never_waits_while_a_move_runs():
    # a real board's wheels turn in real time: stepped into FORWARD, the
    # view goes on by itself from MOVING ON to the move's end
    from rcl.words.debugging import real_move_running
    m = rcl.open(port="rclsim://?rate=4")
    try:
        m.evaluate(": M  RERB 1 FEET FORWARD ;")
        shown, asked = [], []
        m.write = shown.append

        def key():
            asked.append(real_move_running(m))
            return ord("i") if len(asked) in (3, 4) else ord("o")   # into FORWARD, (MOVE)
        m.read_key = key
        m.evaluate("DBG M")
    finally:
        m.board.close()
    out = "".join(shown)
    assert "M > FORWARD > (MOVE) > WAIT-MOVE" in out and "M > FORWARD > (MOVE) > MOVED" in out
    assert asked and not any(asked)
    assert len(asked) < len(steps(out))        # the steps of the move took no key
