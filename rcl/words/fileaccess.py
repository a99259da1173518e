"""File-Access word set (Forth 2012 chapter 11) on the host's files.

    file id (a cell)  --->  FileTable.open[id]  --->  Python file object
                            (a dict: an id not in it is simply "no file")

A file id is a number handed out by the table, never a Python object or
an address: a forged or stale id finds nothing and gives an ior. Every
word returns an ior (0, or a Forth 2012 THROW code) instead of raising;
no Python exception leaves a file word. Files are bytes (latin-1); a line
ends at LF, and a CR before it is dropped. BIN changes nothing.

The loading words (INCLUDE INCLUDED REQUIRE REQUIRED) are in files.py;
S" S\\" ( SOURCE-ID REFILL are in io.py and parsing.py.
"""
import os

from rcl.errors import ForthError
from rcl.forth.memory import MASK
from rcl.forth import state
from rcl.forth.primitives import CALL, prim
from rcl.words.core import pop2, push2

R_O, W_O, R_W, BIN = 1, 2, 3, 4
FIRST_ID = 0x1000            # apart from the ids INCLUDE gives its sources
MAX_OPEN = 64

# Forth 2012 table 9.1: the ior each word gives when the host refuses.
IOR = {"CLOSE-FILE": -62, "CREATE-FILE": -63, "DELETE-FILE": -64,
       "FILE-POSITION": -65, "FILE-SIZE": -66, "FILE-STATUS": -67,
       "FLUSH-FILE": -68, "OPEN-FILE": -69, "READ-FILE": -70, "READ-LINE": -71,
       "RENAME-FILE": -72, "REPOSITION-FILE": -73, "RESIZE-FILE": -74,
       "WRITE-FILE": -75, "WRITE-LINE": -76}
NO_FILE = -38                # non-existent file
IO_ERROR = -37               # file I/O exception (also: not an open file id)


class FileTable:
    """The open files of one machine, by file id."""

    def __init__(self):
        self.open = {}
        self.names = {}
        self.next_id = FIRST_ID

    def add(self, f, name):
        """-> a new file id for f, or 0 when too many are open."""
        if len(self.open) >= MAX_OPEN:
            f.close()
            return 0
        while self.next_id in self.open:
            self.next_id = FIRST_ID + (self.next_id + 1 - FIRST_ID) % 0x6000
        fid = self.next_id
        self.next_id = FIRST_ID + (fid + 1 - FIRST_ID) % 0x6000
        self.open[fid], self.names[fid] = f, name
        return fid

    def get(self, fid):
        return self.open.get(fid)

    def close(self, fid):
        f = self.open.pop(fid, None)
        self.names.pop(fid, None)
        if f is not None:
            f.close()
        return f is not None


# The open files are the session's (a restored system has none open).
state.session("files", lambda m: FileTable())


def files(m):
    return m.files


def host_name(m, a, u):
    """The file name in the string; None if the host could never take it."""
    name = m.memory.text(a, u)
    return name if name and "\0" not in name else None


def ior_of(exc, word):
    if isinstance(exc, FileNotFoundError):
        return NO_FILE
    return IOR.get(word, IO_ERROR)


def attempt(word, action):
    """(result, 0) from action(), or (None, ior) if the host refused."""
    try:
        return action(), 0
    except (OSError, ValueError, OverflowError) as exc:
        return None, ior_of(exc, word)


def with_file(m, fid, word, action):
    """action(f) on the open file fid -> (result, ior)."""
    f = files(m).get(fid)
    if f is None:
        return None, IO_ERROR
    return attempt(word, lambda: action(f))


def push_ior(m, ior):
    m.s.append(ior & MASK)


# ------------------------------------------------------------ access modes
@prim("R/O", "( -- fam ) read only")
def r_o(m):
    m.s.append(R_O)


@prim("W/O", "( -- fam ) write only")
def w_o(m):
    m.s.append(W_O)


@prim("R/W", "( -- fam ) read and write")
def r_w(m):
    m.s.append(R_W)


@prim("BIN", "( fam -- fam' ) binary: files are bytes here anyway")
def bin_(m):
    m.s[-1] |= BIN


def open_host(name, fam, create):
    mode = fam & R_W
    if create:
        return open(name, "w+b" if mode != W_O else "wb")
    if mode == R_O:
        return open(name, "rb")
    if mode == W_O:
        return os.fdopen(os.open(name, os.O_WRONLY), "wb")
    return open(name, "r+b")


def open_word(m, word, create):
    fam, u, a = m.s.pop(), m.s.pop(), m.s.pop()
    name = host_name(m, a, u)
    if name is None or not fam & R_W:
        m.s.append(0)
        push_ior(m, NO_FILE if name is None else IOR[word])
        return
    f, ior = attempt(word, lambda: open_host(name, fam, create))
    fid = files(m).add(f, name) if f is not None else 0
    if f is not None and not fid:
        ior = IOR[word]
    m.s.append(fid)
    push_ior(m, ior)


@prim("OPEN-FILE", "( addr u fam -- fileid ior ) open an existing file")
def open_file(m):
    open_word(m, "OPEN-FILE", create=False)


@prim("CREATE-FILE", "( addr u fam -- fileid ior ) create (or empty) a file and open it")
def create_file(m):
    open_word(m, "CREATE-FILE", create=True)


@prim("CLOSE-FILE", "( fileid -- ior )")
def close_file(m):
    fid = m.s.pop()
    if files(m).get(fid) is None:
        push_ior(m, IO_ERROR)
    else:
        push_ior(m, attempt("CLOSE-FILE", lambda: files(m).close(fid))[1])


@prim("DELETE-FILE", "( addr u -- ior )")
def delete_file(m):
    u, a = m.s.pop(), m.s.pop()
    name = host_name(m, a, u)
    push_ior(m, NO_FILE if name is None else attempt("DELETE-FILE", lambda: os.remove(name))[1])


@prim("RENAME-FILE", "( addr1 u1 addr2 u2 -- ior ) rename file 1 to name 2")
def rename_file(m):
    u2, a2, u1, a1 = m.s.pop(), m.s.pop(), m.s.pop(), m.s.pop()
    old, new = host_name(m, a1, u1), host_name(m, a2, u2)
    if old is None or new is None:
        push_ior(m, NO_FILE)
    elif os.path.exists(new):                 # never replace a file silently
        push_ior(m, IOR["RENAME-FILE"])
    else:
        push_ior(m, attempt("RENAME-FILE", lambda: os.rename(old, new))[1])


@prim("FILE-STATUS", "( addr u -- x ior ) x: the access a file allows; ior 0 if it exists")
def file_status(m):
    u, a = m.s.pop(), m.s.pop()
    name = host_name(m, a, u)
    if name is None or not os.path.exists(name):
        m.s.append(0)
        push_ior(m, NO_FILE)
        return
    x = (R_O if os.access(name, os.R_OK) else 0) | (W_O if os.access(name, os.W_OK) else 0)
    m.s.append(x)
    push_ior(m, 0)


# --------------------------------------------------------- position, size
def push_double(m, word, action):
    """( fileid -- ud ior ) for a word that asks the open file a number."""
    value, ior = with_file(m, m.s.pop(), word, action)
    push2(m.s, value or 0)
    push_ior(m, ior)


@prim("FILE-POSITION", "( fileid -- ud ior ) where the next read or write happens")
def file_position(m):
    push_double(m, "FILE-POSITION", lambda f: f.tell())


@prim("REPOSITION-FILE", "( ud fileid -- ior )")
def reposition_file(m):
    fid = m.s.pop()
    ud = pop2(m.s)
    push_ior(m, with_file(m, fid, "REPOSITION-FILE", lambda f: f.seek(ud))[1])


def size_of(f):
    f.flush()
    return os.fstat(f.fileno()).st_size


@prim("FILE-SIZE", "( fileid -- ud ior )")
def file_size(m):
    push_double(m, "FILE-SIZE", size_of)


@prim("RESIZE-FILE", "( ud fileid -- ior ) cut or extend (with zeros) to ud bytes")
def resize_file(m):
    fid = m.s.pop()
    ud = pop2(m.s)
    push_ior(m, with_file(m, fid, "RESIZE-FILE", lambda f: f.truncate(ud))[1])


@prim("FLUSH-FILE", "( fileid -- ior )")
def flush_file(m):
    push_ior(m, with_file(m, m.s.pop(), "FLUSH-FILE", lambda f: f.flush())[1])


# ------------------------------------------------------------ read, write
@prim("READ-FILE", "( addr u1 fileid -- u2 ior ) read up to u1 bytes; u2 = 0 at the end")
def read_file(m):
    fid, u1, a = m.s.pop(), m.s.pop(), m.s.pop()
    data, ior = with_file(m, fid, "READ-FILE", lambda f: f.read(u1))
    m.memory.write(a, data or b"")
    m.s.append(len(data or b""))
    push_ior(m, ior)


def next_line(f, u1):
    """(body, found): the next line, at most u1 bytes of it, without its
    end; a longer line is left for the next read past u1 bytes."""
    start = f.tell()
    data = f.read(u1 + 2)            # never more than the buffer takes (and its line end)
    if not data:
        return b"", False
    end = data.find(b"\n")
    body = data if end < 0 else data[:end]
    used = len(data) if end < 0 else end + 1
    if body.endswith(b"\r") and end >= 0:
        body = body[:-1]
    if len(body) > u1:
        body, used = body[:u1], u1
    f.seek(start + used)
    return body, True


@prim("READ-LINE", "( addr u1 fileid -- u2 flag ior ) the next line (at most u1 chars)")
def read_line(m):
    fid, u1, a = m.s.pop(), m.s.pop(), m.s.pop()
    got, ior = with_file(m, fid, "READ-LINE", lambda f: next_line(f, u1))
    body, found = got if got else (b"", False)
    m.memory.write(a, body)
    m.s.extend((len(body), MASK if found else 0))
    push_ior(m, ior)


def write_word(m, word, end):
    fid, u, a = m.s.pop(), m.s.pop(), m.s.pop()
    data = m.memory.read(a, u) + end
    push_ior(m, with_file(m, fid, word, lambda f: f.write(data))[1])


@prim("WRITE-FILE", "( addr u fileid -- ior )")
def write_file(m):
    write_word(m, "WRITE-FILE", b"")


@prim("WRITE-LINE", "( addr u fileid -- ior ) the string and a line end (LF)")
def write_line(m):
    write_word(m, "WRITE-LINE", b"\n")


# --------------------------------------------------------------- including
@prim("INCLUDE-FILE", "( fileid -- ) interpret the rest of the open file, then close it",
      kind=CALL)
def include_file(m):
    fid = m.s.pop()
    f = files(m).get(fid)
    if f is None:
        raise ForthError(IO_ERROR, "Not an open file")
    text, ior = attempt("READ-FILE", lambda: f.read().decode("latin-1"))
    name = files(m).names.get(fid)
    files(m).close(fid)
    if ior:
        raise ForthError(ior, "Cannot read " + name)
    m.include_lines(iter(text.splitlines()), name, source_id=fid)
