"""The interactive prompt: a thin shell that shows F83's screen over an
injected machine.

It holds no Forth semantics: the machine interprets each line and says
whether it is compiling; an error carries its own F83 screen text. The
shell only draws, the way F83's QUIT loop does (docs/guide.md section 1):

    CR, read a line       2 3 + .          the user's line, echoed
    Enter echoes a blank         ^         (one blank, not a new line)
    the line's output              5       streamed as the words run
    ` ok` if interpreting             ok   (none while `:` is open)
    or the error's text    foo FOO  ?      (then no ok)

A real terminal has already moved to a new line when Enter is read, so
the prompt (prompt_toolkit, `erase_when_done`) erases its own drawing and
the shell re-types the line and a blank itself, then lets the output
follow: the screen line comes out exactly as F83's, wrapped by the
terminal like any text. The text already on the current screen line
(`Output.tail`, e.g. `PAD 80 ACCEPT ` when ACCEPT asks for a line) is the
prompt string, so what the user types lands after it.

Lines starting with a command of the META table (`#help`, `#clock`, ...)
are the shell's own; everything else goes to the machine.

While a `:` definition is open the prompt names it (`SQ] `). An error
inside an open definition abandons it, as F83's ABORT does; the lines up
to its `;` (the rest of a paste, or what the user types next) are then
skipped, not run one by one as interpreted words, and the screen says so.
An error from a file shows its file and line, as gforth does.

On a capable terminal with a simulated board, rcl.status keeps a status
line at the bottom; while a word runs, keys typed ahead are neither echoed
nor lost (the terminal's echo is off): the next prompt takes them.
"""
import contextlib
import shutil
import threading

import rcl
from rcl import status
from rcl.forth import wordloc
from rcl.forth.dictionary import HIDDEN
from rcl.forth.primitives import CLOCK_HZ
from rcl.terminal import PlainTerminal, hold_keys, make_terminal, shows_status


# ------------------------------------------------------------ meta-commands
META = {}     # name -> (function(repl, argument) -> keep going?, help text)


def meta(name, help_text):
    def register(fn):
        META[name] = (fn, help_text)
        return fn
    return register


@meta("#help", "list the prompt's own commands")
def meta_help(shell, arg):
    width = max(len(name) for name in META)
    for name, (_, text) in META.items():
        shell.out.write("\n  %-*s  %s" % (width, name, text))
    shell.out.write("\n  Everything else is Forth: WORDS lists the words, BYE leaves.")
    return True


@meta("#clock", "the virtual clock, in seconds")
def meta_clock(shell, arg):
    shell.out.write("clock %.6f s" % shell.m.seconds)
    return True


@meta("#stack", "the data stack, bottom first, without touching it")
def meta_stack(shell, arg):
    shell.out.write("stack [%s]" % " ".join(str(n) for n in shell.m.stack))
    return True


@meta("#bell", "#bell off: beeps show on the status line without the terminal bell")
def meta_bell(shell, arg):
    shell.bell = arg.lower() != "off"
    if shell.status:
        shell.status.bell = shell.bell
    shell.out.write("bell %s" % ("on" if shell.bell else "off"))
    return True


@meta("#bye", "leave rcl (as BYE or Ctrl-D)")
def meta_bye(shell, arg):
    return False


# ------------------------------------------------------------------- shell
class Repl:
    """The ok prompt over machine `m`, drawing on `out` (cli.Output)."""

    def __init__(self, m, out, term=None, bell=True):
        self.m, self.out = m, out
        self.bell = bell
        self.status = None
        if term is None and (hasattr(m, "sim") or m.board.status()) and shows_status(out):
            lock = threading.RLock()
            out.stream = status.LockedStream(out.stream, lock)
            self.status = status.StatusLine(m, out.stream, lock, bell, self.catch_up)
        self.term = term or make_terminal(out, m, self.status)
        self.pending = []             # further lines of a multi-line paste
        self.guard = OpenDefinition(m)
        self.busy = False             # a word is running
        m.read_line = self.accept_line
        m.read_key = self.read_key
        m.columns = shutil.get_terminal_size().columns
        self.give_back_keys = hold_keys(self.term)

    def run(self):
        """Read, interpret, show; until Ctrl-D, BYE or #bye."""
        if self.status:
            self.status.start()
        try:
            self.loop()
        finally:
            if self.status:
                self.status.stop()
            self.give_back_keys()
        self.out.end_line()

    def loop(self):
        while True:
            try:
                if not self.onecmd(self.next_line(self.begin_line())):
                    break
            except KeyboardInterrupt:            # Ctrl-C at the prompt: clear the line
                self.pending.clear()
                self.guard.skipping = None
            except EOFError:
                break

    def onecmd(self, line):
        """Run one line and show how it ended. -> False to leave. Nothing
        raised here may leave the loop."""
        name, arg = (line.split(None, 1) + ["", ""])[:2]
        command = META.get(name.lower())
        if command:
            return command[0](self, arg.strip())
        if self.guard.skipping:
            return self.skip(line)
        self.guard.before()
        try:
            self.catch_up()
            with self.running():
                self.m.evaluate(line)
            if not self.m.compiling:
                self.out.write(" ok")
        except rcl.ForthError as e:
            self.out.write(error_text(e))
            self.abandoned(line, e)
        except rcl.Bye:
            return False
        except KeyboardInterrupt:
            self.abort()
            self.out.write(" Interrupted ")
        except Exception as e:
            self.abort()
            self.out.write(" Internal error: %s: %s " % (type(e).__name__, e))
        return True

    @contextlib.contextmanager
    def running(self):
        """While a word runs: the status line kept fresh."""
        self.busy = True
        if self.status:
            self.status.resume()
        try:
            yield
        finally:
            self.busy = False
            if self.status:
                self.status.pause()

    def catch_up(self):
        """In real time the board's clock runs while the prompt waits: let
        the idle machine's clock (interrupts and all) reach the wall clock.
        Not while a word runs (it may be waiting in ACCEPT or KEY)."""
        pacer = getattr(self.m.board, "pacer", None)
        if pacer is not None and hasattr(self.m, "sim") and not self.busy:
            behind = pacer.wall() - pacer.start_wall - \
                (self.m.clock - pacer.start_clock) / CLOCK_HZ
            if behind > 0:
                self.m.sim.run(behind)

    # ------------------------------------------------- open definitions
    def abandoned(self, line, error):
        """After an error: was a definition open? Then skip its other lines."""
        name = self.guard.failed(line, error)
        if name:
            self.out.write("\n%s is abandoned: the lines up to its ; are skipped, "
                           "not run (Ctrl-C stops skipping)" % name)

    def skip(self, line):
        self.out.write(self.guard.skip(line))
        return True

    def abort(self):
        try:
            self.m.abort()
        except Exception:
            pass

    # --------------------------------------------------------- screen lines
    def begin_line(self):
        """F83's CR before each read; -> what the new line shows first: ''
        or, while a definition is open or skipped, a continuation prompt."""
        self.out.end_line()
        if self.guard.skipping:
            return "(skipping %s) " % self.guard.skipping
        if self.m.compiling:
            return "%s] " % self.guard.name()
        return ""

    def visible_tail(self):
        """The part of the current line on the cursor's screen row."""
        tail = self.out.tail
        if not tail.isprintable():
            self.out.write("\n")
            return ""
        width = max(shutil.get_terminal_size().columns, 1)
        n = len(tail) % width or (width if tail else 0)
        return tail[len(tail) - n:]

    def next_line(self, shown):
        """The next typed line, drawn after `shown` (what the row already
        holds) with its blank, as F83's screen shows it."""
        if self.pending:
            line = self.pending.pop(0)
            self.out.write(line + " ")
            return line
        first, *rest = self.read(shown).split("\n")
        self.pending.extend(rest)
        if self.term.rewinds:
            self.out.redraw(shown)
            self.out.write(first + " ")
        else:                                    # the terminal echoed it, on its own row
            self.out.tail = ""
        return first

    def read(self, shown):
        """A line from the terminal; if it breaks, from plain input(); if
        that breaks too (the terminal hung up), the input has ended."""
        try:
            return self.term.read(shown)
        except (KeyboardInterrupt, EOFError):
            raise
        except Exception:
            if isinstance(self.term, PlainTerminal):
                raise EOFError from None
            self.term = PlainTerminal(self.out)
            return self.read(shown)

    # ------------------------------------------------- the machine's keyboard
    def accept_line(self):
        """ACCEPT/QUERY at the prompt: a line typed after what is shown;
        None at Ctrl-D. Ctrl-C propagates: the machine aborts."""
        try:
            with self.status_held():
                return self.next_line(self.visible_tail())
        except EOFError:
            return None

    def read_key(self):
        self.out.flush()
        with self.status_held():
            return self.term.read_key(lambda: self.m.break_pending)

    @contextlib.contextmanager
    def status_held(self):
        """A word reads the keyboard: the prompt draws the status line
        meanwhile, not the thread (they must not write at once)."""
        held = self.status is not None and self.status.running is not None
        if held:
            self.status.pause()
        try:
            yield
        finally:
            if held:
                self.status.resume()


def error_text(e):
    """F83's text for an error; from a file, `file:line:` first (gforth);
    then, if it came from a word, the word and its callers (wordloc.py)."""
    text = " %s:%s: %s " % (e.file, e.line, e.display()) if e.file else e.screen()
    return "\n".join([text] + wordloc.describe(e.words()))


def ends_definition(line):
    return ";" in line.split()


class OpenDefinition:
    """Keeps an error inside an open `:` definition from turning the rest
    of it into commands. F83's ABORT abandons the definition; its further
    lines (a paste, a pipe, what the user types next) would then run one by
    one, interpreted: `FORWARD` would start the motors. So after such an
    error the lines up to one holding `;` are skipped.

        before()        before each line runs
        failed(line, e) after it failed with e: the abandoned definition's name, or ''
        skipping        that name while lines are being skipped
        skip(line)      what to show for a skipped line
    """

    def __init__(self, m):
        self.m = m
        self.skipping = None
        self.last, self.was_open = None, False

    def name(self):
        """The name of the definition being compiled, '' if it has none."""
        d = self.m.dictionary
        if d.last and d.flags(d.last) & HIDDEN:
            return d.name_of((d.last + 2) & 0xFFFF) or ""
        return ""

    def before(self):
        self.last, self.was_open = self.m.dictionary.last, self.m.compiling

    def failed(self, line, error):
        d = self.m.dictionary
        opened = d.last != self.last and d.last and d.flags(d.last) & HIDDEN
        if not (self.was_open or opened) or ends_definition(line):
            return ""
        if error.file and not self.was_open:
            return ""        # opened in a file the error ended: its ; went with the file

        self.skipping = self.name() or "the definition"
        return self.skipping

    def skip(self, line):
        if ends_definition(line):
            self.skipping = None
            return " skipped, the definition is over"
        return " skipped"
