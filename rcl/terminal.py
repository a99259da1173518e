"""Terminal handling, in one place, for the prompt (rcl/repl.py).

A terminal has read(shown) -> str (EOFError at Ctrl-D, KeyboardInterrupt
at Ctrl-C, leaving `shown` on the row), read_key() -> key code, and
`rewinds`: True when, after read(), the cursor is back at the start of the
row so the shell re-types the line.

    PromptTerminal   prompt_toolkit: editing, TAB completion, history
    PlainTerminal    input() on the terminal's own line editing

hold_keys() keeps the terminal quiet between prompts, so that typed-ahead
keys wait for the next one.
"""
import atexit
import math
import os
import select
import shutil
import sys

import rcl
from rcl.forth.dictionary import HIDDEN


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


def read_tty_key(interrupted=lambda: False):
    """One key from the terminal, unechoed and unbuffered (cbreak: Ctrl-C
    still interrupts). Enter reads as 13, as on F83's keyboard. The wait
    looks at interrupted() ten times a second: a Ctrl-C whose KeyboardInterrupt
    Python swallowed (raised inside a finalizer: "Exception ignored") still
    ends it, where a blocking read was resumed and waited for a key."""
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
        while not select.select([fd], [], [], 0.1)[0]:
            if interrupted():
                raise KeyboardInterrupt
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
            extra.update(refresh_interval=1.0, output=output_above_status())
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

    def read_key(self, interrupted=lambda: False):
        return read_tty_key(interrupted)


def output_above_status():
    """prompt_toolkit's output to the terminal, one row shorter than the
    screen: the last row is the status line's, outside the scroll region,
    and a prompt drawn down to it would scroll the session up."""
    from prompt_toolkit.data_structures import Size
    from prompt_toolkit.output.vt100 import Vt100_Output
    output = Vt100_Output.from_pty(sys.stdout, term=os.environ.get("TERM"))
    full = output.get_size
    output.get_size = lambda: Size(rows=max(1, full().rows - 1), columns=full().columns)
    return output


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

    def read_key(self, interrupted=lambda: False):
        return read_tty_key(interrupted)
