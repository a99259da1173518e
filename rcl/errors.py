"""Errors of rcl: one base class, and the Forth error every layer raises.

A Forth error travels as a Python exception carrying a Forth 2012 THROW
code, so CATCH can catch it; at the top the machine prints it the F83 way
(a blank, the message, a blank) and aborts.
"""


class RclError(Exception):
    """Base of every rcl error."""


# Standard THROW codes used by the machine, with the F83 text for each.
MESSAGES = {
    -1: "",                       # ABORT: F83 prints two blanks
    -3: "Stack Overflow",
    -4: "Stack Underflow",
    -5: "Return Stack Overflow",
    -6: "Return Stack Underflow",
    -9: "Invalid memory address",
    -13: "?",
    -14: "Compile only",
    -15: "Below fence",
    -16: "Name expected",
    -22: "Conditionals Wrong",
    -28: "Interrupted",
    -37: "File I/O exception",
    -38: "File not found",
    -256: "Stack Changed",
    -257: "Uninitialized execution vector.",
    -258: "Not enough Parameters",
    -259: "Step limit",
    -260: "Invalid execution token",
    -8: "Dictionary full",
    -262: "Line too long",
    -263: "No CODE for",
    -290: "Tick fault",
    -291: "Runs too long",
    -293: "Host too slow",
}


class ForthError(RclError):
    """A Forth error: THROW code, F83 message, offending word, and where.

    str() gives what F83 shows: `FOO  ?` for an unknown word, the message
    alone otherwise, prefixed with `file:line: ` inside a loaded file.
    """

    def __init__(self, code, message=None, word=None):
        if message is None:
            message = MESSAGES.get(code, "Error %d" % code)
        super().__init__(message)
        self.code = code
        self.message = message
        self.word = word
        self.output = ""
        self.file = None
        self.line = None
        self.backtrace = None     # [(word, file, line)] innermost first (forth/wordloc.py)
        self.why = None           # more than the message says, where known (a lost link's cause)

    def display(self):
        """The text F83 prints between the blanks, with the word if any."""
        if self.word is not None:
            return "%s  %s" % (self.word, self.message)
        return self.message

    def screen(self):
        """Exactly what F83 prints for this error: `FOO  ? ` for an unknown
        word (the token, then the abort's blank, ` ?` and a blank), else
        a blank, the message, a blank."""
        if self.word is not None:
            return "%s  %s " % (self.word, self.message)
        return " %s " % self.message

    def words(self):
        """The words the error came from, innermost first ([(word, file,
        line)]), if worth showing: not for ABORT and ABORT" (-1, -2), whose
        message is the program's own word to the user, as F83 shows it."""
        return [] if self.code in (-1, -2) else (self.backtrace or [])

    def __str__(self):
        where = "%s:%s: " % (self.file, self.line) if self.file else ""
        return where + self.display()


def as_forth_error(exc):
    """Any failure inside Forth code, as the Forth error it amounts to."""
    if isinstance(exc, ForthError):
        return exc
    if isinstance(exc, IndexError):         # a pop from an empty stack
        return ForthError(-4)
    if isinstance(exc, RecursionError):
        return ForthError(-5)
    if isinstance(exc, KeyboardInterrupt):
        return ForthError(-28, "Interrupted")
    return ForthError(-4095, "Internal error: %s: %s" % (type(exc).__name__, exc))


def file_error(exc, name):
    """The Forth error for an OSError opening file `name`: File not found,
    or what the system said (a directory, no permission)."""
    if isinstance(exc, FileNotFoundError):
        return ForthError(-38, "File not found", name)
    return ForthError(-37, exc.strerror or "File I/O exception", name)


MAX_SOURCE = 16 << 20     # a Forth source file is read whole (RESTORE-INPUT): at most this


def open_source(path, name=None):
    """A Forth source file opened for INCLUDE (latin-1 text): a regular file
    of at most MAX_SOURCE bytes, else the Forth error saying why (a FIFO or
    /dev/zero would be waited on or read forever)."""
    import os
    import stat
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))   # (a FIFO: no wait)
        f = os.fdopen(fd, encoding="latin-1")
    except OSError as exc:
        raise file_error(exc, name or path) from None
    info = os.fstat(f.fileno())
    if not stat.S_ISREG(info.st_mode) or info.st_size > MAX_SOURCE:
        f.close()
        why = "not a regular file" if not stat.S_ISREG(info.st_mode) else \
            "larger than %d MiB" % (MAX_SOURCE >> 20)
        raise ForthError(-37, "Cannot load: %s" % why, name or path)
    return f


class Bye(RclError):
    """BYE was executed: the caller should leave. `output`: what the call
    printed before BYE (as ForthError's), not left for the next call."""

    output = ""


class Terminated(BaseException):
    """A signal (SIGTERM, SIGHUP) asked rcl to leave. Not an Exception, so
    no error handling on the way stops it; it is raised only at a primitive
    boundary of the foreground or while nothing runs."""
