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
"""
import math
import os
import shutil
import sys

import rcl

HISTORY = "~/.rcl_history"


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


@meta("#bye", "leave rcl (as BYE or Ctrl-D)")
def meta_bye(shell, arg):
    return False


# ------------------------------------------------------------------- shell
class Repl:
    """The ok prompt over machine `m`, drawing on `out` (cli.Output)."""

    def __init__(self, m, out, term=None):
        self.m, self.out = m, out
        self.term = term or make_terminal(out)
        self.pending = []             # further lines of a multi-line paste
        m.read_line = self.accept_line
        m.read_key = self.read_key

    def run(self):
        """Read, interpret, show; until Ctrl-D, BYE or #bye."""
        while True:
            try:
                if not self.onecmd(self.next_line(self.begin_line())):
                    break
            except KeyboardInterrupt:            # Ctrl-C at the prompt: clear the line
                self.pending.clear()
            except EOFError:
                break
        self.out.end_line()

    def onecmd(self, line):
        """Run one line and show how it ended. -> False to leave. Nothing
        raised here may leave the loop."""
        name, arg = (line.split(None, 1) + ["", ""])[:2]
        command = META.get(name.lower())
        try:
            if command:
                return command[0](self, arg.strip())
            self.m.evaluate(line)
            if not self.m.compiling:
                self.out.write(" ok")
        except rcl.ForthError as e:
            self.out.write(e.screen())
        except rcl.Bye:
            return False
        except KeyboardInterrupt:
            self.abort()
            self.out.write(" Interrupted ")
        except Exception as e:
            self.abort()
            self.out.write(" Internal error: %s: %s " % (type(e).__name__, e))
        return True

    def abort(self):
        try:
            self.m.abort()
        except Exception:
            pass

    # --------------------------------------------------------- screen lines
    def begin_line(self):
        """F83's CR before each read; -> '' (the new line holds nothing)."""
        self.out.end_line()
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


# ---------------------------------------------------------------- terminals
# Terminal handling, in one place. A terminal has read(shown) -> str
# (EOFError at Ctrl-D, KeyboardInterrupt at Ctrl-C, leaving `shown` on the
# row), read_key() -> key code, and `rewinds`: True when, after read(), the
# cursor is back at the start of the row so the shell re-types the line.

def is_dumb():
    return os.environ.get("TERM", "").lower() in ("dumb", "unknown")


def make_terminal(out):
    """prompt_toolkit when both ends are terminals, else plain input()."""
    if sys.stdin.isatty() and out.stream.isatty():
        try:
            return PromptTerminal(out)
        except Exception:
            pass
    return PlainTerminal(out)


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
    """prompt_toolkit: line editing, history in ~/.rcl_history. Started at
    column 0 it draws `shown` and the typed line, and erases it all when
    done (so it rewinds), except on a dumb terminal, where it only echoes
    and moves on."""

    def __init__(self, out):
        from prompt_toolkit import PromptSession
        self.out = out
        self.rewinds = not is_dumb()
        self.session = PromptSession(history=quiet_history(),
                                     erase_when_done=True)

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

    return QuietFileHistory(os.path.expanduser(HISTORY))


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
