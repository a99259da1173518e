"""Debugging words: DBG, BREAK:, BREAK", BREAKS (kernel), ~~, and the
stepping view's text front end.

The stepping itself is rcl/forth/stepper.py (no terminal in it); here a
key chooses its command and each Step is drawn as one line:

    DBG TRIP   Enter step  I into  O over  F finish  C continue  Q stop
      listing5.fs:19  TRIP > WARNING  ( )  00:00:00  x 0.0 y 0.0 in  heading 0.0
      ...
      listing5.fs:20  TRIP > BACKWARD  ( )  00:00:06  x 0.0 y 0.0 in  heading 0.0
      BACKWARD ended at 00:00:08  x -36.0 y 0.0 in  heading 0.1
      listing5.fs:20  TRIP > TURN-AROUND  ( )  00:00:08  x -36.0 y 0.0 in  heading 0.1

Keys come through KEY's path (io.next_key): at the prompt one key, no
Enter needed; from a pipe the next character (a new line is Enter). So
Ctrl-C while the view waits is Ctrl-C at KEY, and Q aborts as any error
does (the motors off first).

BREAK: compiles (BREAK), whose code field is a runtime: reached with
BREAKS on, it steps the rest of the running definition from the cell
after it, and returns the address that definition's EXIT popped, which
its compiled caller passes on (the call protocol of inner.py).
"""
import os

from rcl.board import NullBoard
from rcl.errors import ForthError
from rcl.forth import stepper, wordloc
from rcl.forth.inner import SENTINEL
from rcl.forth.memory import MASK
from rcl.forth.primitives import RUNTIME, prim
from rcl.words.compiling import compiling, parse_word, tick
from rcl.words.io import lay_string, next_key, quoted
from rcl.words.rclcode import idle_rule

KEYS = {13: stepper.STEP, 10: stepper.STEP, 32: stepper.STEP,
        ord("i"): stepper.INTO, ord("o"): stepper.OVER, ord("f"): stepper.FINISH,
        ord("c"): stepper.CONTINUE, ord("q"): "quit"}
HELP = "Enter step  I into  O over  F finish  C continue  Q stop"


# ---------------------------------------------------------------- the view
def render(step):
    """The lines (each after a new line) the view shows for a Step: its
    BREAK: label, where the last step's move ended, then the word about
    to run (or done) with the stack and, on a board, time and pose."""
    lines = []
    if step.label:
        lines.append(" %s" % step.label)
    if step.moved:
        lines.append("  %s ended at %s" % (step.ran, board_text(step)))
    board = "  " + board_text(step) if step.time else ""
    if step.word is None:
        lines.append("  done  %s%s" % (stack_text(step.stack), board))
    else:
        place = "%s:%s" % (os.path.basename(step.file), step.line) if step.file else "(typed)"
        lines.append("  %s  %s  %s%s" % (
            place, " > ".join(step.chain + [step.word]), stack_text(step.stack), board))
    return "".join("\n" + line for line in lines)


def stack_text(stack):
    """The data stack, bottom first, in decimal: ( 1 2 ), ( ) when empty."""
    return "( %s )" % " ".join(str(n) for n in stack) if stack else "( )"


def board_text(step):
    if step.pose is None:
        return step.time or ""
    x, y, heading = step.pose
    return "%s  x %s y %s in  heading %s" % (step.time, tenths(x), tenths(y),
                                             tenths(round(heading, 1) % 360))


def tenths(value):
    return "%.1f" % (round(value, 1) + 0.0)      # never -0.0


def command(m):
    """The next key's command; other keys show the keys and ask again."""
    while True:
        c = next_key(m)
        cmd = KEYS.get(c) or KEYS.get(c | 0x20)
        if cmd:
            return cmd
        m.type("\n " + HELP)


def drive(m, s, step):
    """Show each step and take the user's command until the stepped
    definition is over. Q stops with ` Stopped `, as any abort. What a
    stepped word prints comes on a line of its own."""
    shown = Column(m)
    try:
        shown.show(render(step))
        while not s.done:
            cmd = stepper.OVER if real_move_running(m) else command(m)
            if cmd == "quit":
                raise ForthError(-28, "Stopped")
            shown.type("\n")
            step = s.advance(cmd)
            shown.show(render(step))
    finally:
        shown.close()


class Column:
    """Whether the machine's output stands at the start of a line, seen
    by wrapping m.type while the view runs (a view opened inside another,
    by a BREAK: in a word stepped over, wraps the outer one's)."""

    def __init__(self, m):
        self.m, self.at_start = m, False
        self.type_through = m.type
        self.outer = m.__dict__.get("type")
        if self.outer is not None:
            self.at_start = self.outer.__self__.at_start
        m.type = self.type

    def type(self, text):
        if text:
            self.at_start = text.endswith("\n")
            self.type_through(text)

    def show(self, lines):
        """Lines that each start with a new line: the first needs none at
        the start of a line."""
        self.type(lines[1:] if self.at_start else lines)

    def close(self):
        if self.outer is None:
            del self.m.type                # the machine's own again
        else:
            self.outer.__self__.at_start = self.at_start
            self.m.type = self.outer


def real_move_running(m):
    """A move or arm move under way on a board that is not simulated: its
    wheels turn in real time, and the control loop runs only while Forth
    does, so the view steps on by itself instead of waiting for a key (a
    simulated robot's time stands still while the view waits)."""
    if hasattr(m, "sim") or isinstance(m.board, NullBoard):
        return False
    # RCL's own rule of "nothing under way" (screens/90-time.fs), asked
    # outside virtual time as (MS) asks it: one rule, not a copy of it.
    if "IDLE-CELLS" not in m.xt_of:        # RCL not loaded: nothing of its moves
        return False
    return m.ask(idle_rule(m)) == 0


def breaks_on(m):
    xt = m.xt_of.get("BREAKS")
    return xt is None or m.memory.fetch((xt + 2) & MASK) != 0


# ------------------------------------------------------------------- words
# DBG and BREAK: cost no virtual time: a stepped run keeps the plain run's
# clock, so its moves end exactly where the plain run's do.
@prim("DBG", "( \"name\" -- ) run name one word at a time: Enter step, I into, "
      "O over, F finish this definition, C continue, Q stop", cost=0)
def dbg(m):
    name = parse_word(m)
    s = stepper.Stepper(m)
    step = s.start(tick(m, name))
    if step is None:
        raise ForthError(-12, "not a colon definition: DBG steps one", name.upper())
    m.type("\nDBG %s   %s" % (name.upper(), HELP))
    drive(m, s, step)
    if s.ip != SENTINEL:                   # its EXIT went elsewhere (R> tricks)
        m.run_from(s.ip)


def stop_here(m, ret, label):
    """A BREAK: reached: step the rest of the running definition; -> the
    address its EXIT popped."""
    if m.masked or not breaks_on(m):       # never inside the tick handler
        return ret
    s = stepper.Stepper(m)
    step = s.resume(ret, label)
    if step is None:
        return ret
    drive(m, s, step)
    return s.ip


@prim("(BREAK)", "( -- ) BREAK: compiled: the stepping view, if BREAKS is on",
      kind=RUNTIME, cost=0)
def paren_break(m, xt, ret):
    return stop_here(m, ret, stepper.break_label())


@prim("(BREAK\")", "( addr u -- ) BREAK\" compiled, after its text: the "
      "stepping view, named, if BREAKS is on", kind=RUNTIME)
def paren_break_quote(m, xt, ret):
    return stop_here(m, ret, stepper.break_label(stepper.break_text(m)))


def compile_only(m, name):
    if not compiling(m):
        raise ForthError(-14, "Compile only", name)


@prim("BREAK:", "( -- ) stop here in the stepping view when reached "
      "(BREAKS OFF runs through)", immediate=True)
def break_colon(m):
    compile_only(m, "BREAK:")
    m.dictionary.comma(m.xt_of["(BREAK)"])


@prim("BREAK\"", "( \"text\" -- ) as BREAK:, the view named by text", immediate=True)
def break_quote(m):
    compile_only(m, 'BREAK"')
    lay_string(m, '(S")', quoted(m))
    m.dictionary.comma(m.xt_of['(BREAK")'])


# ---------------------------------------------------------------------- ~~
def tilde_text(m, file, line, word):
    place = "%s:%s" % (os.path.basename(file), line) if file else "(typed)"
    return "\n~~ %s%s  %s\n" % (place, " " + word if word else "", stack_text(m.stack))


@prim("(~~)", "( -- ) ~~ compiled: show where and the stack", kind=RUNTIME)
def paren_tilde(m, xt, ret):
    cell = (ret - 2) & MASK
    file, line = m.locations.at(cell)
    word = wordloc.containing(m, cell)
    m.type(tilde_text(m, file, line, word and m.dictionary.name_of(word)))
    return ret


@prim("~~", "( -- ) show the file:line and the stack, and go on (gforth's)",
      immediate=True)
def tilde(m):
    if compiling(m):
        m.dictionary.comma(m.xt_of["(~~)"])
        return
    src = m.sources[-1]
    file = src.name if src.kind == "file" else None
    m.type(tilde_text(m, file, src.line, None))
