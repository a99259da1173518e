"""The interactive prompt: a thin shell that shows F83's screen over an
injected machine.

It holds no Forth semantics: the machine interprets each line and says
whether it is compiling; an error carries its own F83 screen text. The
shell only draws, the way F83's QUIT loop does (f83-semantics.md 9.2):

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
import atexit
import contextlib
import math
import os
import shutil
import sys
import threading

import rcl
from rcl import status
from rcl.forth.dictionary import HIDDEN
from rcl.forth.primitives import CLOCK_HZ


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
        if term is None and hasattr(m, "sim") and shows_status(out):
            lock = threading.RLock()
            out.stream = status.LockedStream(out.stream, lock)
            self.status = status.StatusLine(m, out.stream, lock, bell, self.catch_up)
        self.term = term or make_terminal(out, m, self.status)
        self.pending = []             # further lines of a multi-line paste
        self.skipping = None          # an abandoned definition whose lines are skipped
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
                self.skipping = None
            except EOFError:
                break

    def onecmd(self, line):
        """Run one line and show how it ended. -> False to leave. Nothing
        raised here may leave the loop."""
        name, arg = (line.split(None, 1) + ["", ""])[:2]
        command = META.get(name.lower())
        if command:
            return command[0](self, arg.strip())
        if self.skipping:
            return self.skip(line)
        last, was_open = self.m.dictionary.last, self.m.compiling
        try:
            self.catch_up()
            with self.running():
                self.m.evaluate(line)
            if not self.m.compiling:
                self.out.write(" ok")
        except rcl.ForthError as e:
            self.out.write(error_text(e))
            self.abandoned(line, last, was_open)
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
        if self.status:
            self.status.resume()
        try:
            yield
        finally:
            if self.status:
                self.status.pause()

    def catch_up(self):
        """In real time the board's clock runs while the prompt waits: let
        the idle machine's clock (interrupts and all) reach the wall clock."""
        pacer = getattr(self.m.board, "pacer", None)
        if pacer is not None and hasattr(self.m, "sim"):
            behind = pacer.wall() - pacer.start_wall - \
                (self.m.clock - pacer.start_clock) / CLOCK_HZ
            if behind > 0:
                self.m.sim.run(behind)

    # ------------------------------------------------- open definitions
    def open_definition(self):
        """The name of the `:` definition being compiled, '' if it has none."""
        d = self.m.dictionary
        if d.last and d.flags(d.last) & HIDDEN:
            return d.name_of((d.last + 2) & 0xFFFF) or ""
        return ""

    def abandoned(self, line, last, was_open):
        """After an error: was a definition open? Then skip its other lines."""
        d = self.m.dictionary
        opened = d.last != last and d.last and d.flags(d.last) & HIDDEN
        if not (was_open or opened) or ends_definition(line):
            return
        name = (d.name_of((d.last + 2) & 0xFFFF) if d.last else "") or "the definition"
        self.skipping = name
        self.out.write("\n%s is abandoned: the lines up to its ; are skipped, "
                       "not run (Ctrl-C stops skipping)" % name)

    def skip(self, line):
        if ends_definition(line):
            self.skipping = None
            self.out.write(" skipped, the definition is over")
        else:
            self.out.write(" skipped")
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
        if self.skipping:
            return "(skipping %s) " % self.skipping
        if self.m.compiling:
            return "%s] " % self.open_definition()
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
            return self.next_line(self.visible_tail())
        except EOFError:
            return None

    def read_key(self):
        self.out.flush()
        return self.term.read_key()


def error_text(e):
    """F83's text for an error; from a file, `file:line:` first (gforth)."""
    if e.file:
        return " %s:%s: %s " % (e.file, e.line, e.display())
    return e.screen()


def ends_definition(line):
    return ";" in line.split()


# ---------------------------------------------------------------- terminals
# Terminal handling, in one place. A terminal has read(shown) -> str
# (EOFError at Ctrl-D, KeyboardInterrupt at Ctrl-C, leaving `shown` on the
# row), read_key() -> key code, and `rewinds`: True when, after read(), the
# cursor is back at the start of the row so the shell re-types the line.

def is_dumb():
    return os.environ.get("TERM", "").lower() in ("dumb", "unknown")


def make_terminal(out, m=None, status_line=None):
    """prompt_toolkit when both ends are terminals, else plain input()."""
    if sys.stdin.isatty() and out.stream.isatty():
        try:
            return PromptTerminal(out, m, status_line)
        except Exception:
            pass
    return PlainTerminal(out)


def shows_status(out):
    """A status line needs a capable terminal and prompt_toolkit's prompt."""
    try:
        import prompt_toolkit  # noqa: F401
    except Exception:
        return False
    return sys.stdin.isatty() and out.stream.isatty() and not is_dumb()


def hold_keys(term):
    """From now on the terminal's echo and line editing are off (Ctrl-C
    still interrupts) except while the prompt reads, so keys typed while a
    word runs, or between two prompts, stay queued for the next prompt,
    unechoed and unchanged. -> a function that gives the terminal back as
    it was (also run at exit)."""
    if not isinstance(term, PromptTerminal):
        return lambda: None                      # input() needs a cooked line
    try:
        import termios
        fd = sys.stdin.fileno()
        saved = termios.tcgetattr(fd)
        quiet = list(saved)
        quiet[0] &= ~termios.ICRNL               # Enter stays Enter for the prompt
        quiet[3] &= ~(termios.ECHO | termios.ICANON)
        termios.tcsetattr(fd, termios.TCSANOW, quiet)
    except Exception:
        return lambda: None

    def restore():
        try:
            termios.tcsetattr(fd, termios.TCSANOW, saved)
        except Exception:
            pass
    atexit.register(restore)
    return restore


def history_path():
    """The prompt's history, in the user's data directory."""
    if sys.platform == "win32":
        base = os.environ.get("APPDATA") or os.path.expanduser("~")
    elif sys.platform == "darwin":
        base = os.path.expanduser("~/Library/Application Support")
    else:
        base = os.environ.get("XDG_DATA_HOME") or os.path.expanduser("~/.local/share")
    return os.path.join(base, "rcl", "history")


def read_tty_key():
    """One key from the terminal, unechoed and unbuffered (cbreak: Ctrl-C
    still interrupts). Enter reads as 13, as on F83's keyboard."""
    try:
        import termios
        import tty
        fd = sys.stdin.fileno()
        saved = termios.tcgetattr(fd)
    except Exception:                             # not a POSIX terminal
        c = sys.stdin.read(1)
        if not c:
            raise rcl.ForthError(-39, "No input")
        return 13 if c == "\n" else ord(c)
    try:
        tty.setcbreak(fd, termios.TCSANOW)      # keep keys typed ahead
        c = os.read(fd, 1)
    finally:
        termios.tcsetattr(fd, termios.TCSADRAIN, saved)
    if not c:
        raise rcl.ForthError(-39, "No input")
    return 13 if c == b"\n" else c[0]


class PromptTerminal:
    """prompt_toolkit: line editing, TAB completion of the words in the
    search order, history (Ctrl-R searches it) in the user's data directory.
    Started at column 0 it draws `shown` and the typed line, and erases it
    all when done (so it rewinds), except on a dumb terminal, where it only
    echoes and moves on. With a status line it redraws it after each of its
    renders, and renders each second (the clock may run)."""

    def __init__(self, out, m=None, status_line=None):
        from prompt_toolkit import PromptSession
        self.out = out
        self.rewinds = not is_dumb()
        extra = {}
        if status_line is not None:
            extra["refresh_interval"] = 1.0
        self.session = PromptSession(history=quiet_history(), erase_when_done=True,
                                     completer=word_completer(m) if m else None,
                                     complete_while_typing=False, **extra)
        if status_line is not None:
            self.session.app.after_render += lambda app: status_line.draw_idle()

    def read(self, shown):
        if not self.rewinds:
            return self.session.prompt("")
        # It draws from where the cursor is but counts columns from 0.
        self.out.redraw("\r")
        try:
            return self.session.prompt(shown)
        except (KeyboardInterrupt, EOFError):
            self.out.redraw(shown)               # it erased the row: put it back
            raise

    def read_key(self):
        return read_tty_key()


def quiet_history():
    """FileHistory that never fails: a history it cannot read or write is
    simply not kept."""
    from prompt_toolkit.history import FileHistory

    class QuietFileHistory(FileHistory):
        def load_history_strings(self):
            try:
                return list(super().load_history_strings())
            except Exception:
                return []

        def store_string(self, string):
            try:
                super().store_string(string)
            except Exception:
                pass

    path = history_path()
    try:
        os.makedirs(os.path.dirname(path), exist_ok=True)
    except OSError:
        pass
    return QuietFileHistory(path)


def word_completer(m):
    """TAB: the words of the current search order that start with what is
    typed, in any case, first vocabulary first, newest first."""
    from prompt_toolkit.completion import Completer, Completion

    class WordCompleter(Completer):
        def get_completions(self, document, complete_event):
            typed = document.get_word_before_cursor(WORD=True)
            if not typed:
                return
            key = typed.upper()
            for name in search_order_names(m):
                if name.upper().startswith(key):
                    yield Completion(name, start_position=-len(typed))

    return WordCompleter()


def search_order_names(m):
    d, seen = m.dictionary, set()
    for wid in d.order():
        for lfa in d.lfas(wid):
            if d.flags(lfa) & HIDDEN:
                continue
            name = d.name_of((lfa + 2) & 0xFFFF)
            if name and name.upper() not in seen:
                seen.add(name.upper())
                yield name


class PlainTerminal:
    """input() on the terminal's own line editing (backspace, Ctrl-U: what
    F83 offers). Its echo always ends with a new line; on a capable screen
    the cursor is moved back up (ANSI `ESC [ n A`) so the shell re-types
    the line the F83 way. Not readline: it leaves out that new line after
    an empty line, so the rows to go back could not be known."""

    def __init__(self, out):
        self.out = out
        self.rewinds = out.stream.isatty() and not is_dumb()

    def read(self, shown):
        if not self.rewinds:
            return input()
        self.out.redraw("\r")                    # input() re-types `shown`
        try:
            line = input(shown)
        except KeyboardInterrupt:
            self.out.redraw("\r\x1b[K" + shown)
            raise
        width = max(shutil.get_terminal_size().columns, 1)
        rows = max(1, math.ceil((len(shown) + len(line)) / width))
        self.out.redraw("\x1b[%dA\r" % rows)
        return line

    def read_key(self):
        return read_tty_key()
