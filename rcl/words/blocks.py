"""Blocks and screens: 1024-byte blocks from a block file, shown as 16
lines of 64 characters (F83's, and Forth 2012's Block word set).

Two buffers in memory (memory.BLOCK_BUFFERS). Where the blocks come from:

  no file opened   a scratch file in memory (SCRATCH_BLOCKS blank blocks,
                   made as they are touched), so BLOCK works at once
  USING x.blk      an F83 block file: raw 1024-byte blocks; UPDATE FLUSH
                   write a block back in place (n CREATE-BLOCKS x.blk makes
                   one of n blank screens, n MORE adds n to the open one)
  USING x.fs       a text file, read as rcl.blocks converts it (screen 0 a
                   title, its lines from screen 1): read only, UPDATE is
                   refused, so the text file is never rewritten

Block 0 can never be loaded (BLK = 0 means the terminal). An error in a
loaded screen names the file, the screen and the line.
"""
import os
import stat

from rcl.blocks import LINE, LINES, BlockFormatError, is_block_file, text_to_blocks
from rcl.errors import ForthError, RclError
from rcl.forth.memory import BLOCK_BUFFERS, MASK, signed
from rcl.forth.outer import Source
from rcl.forth import state
from rcl.forth.primitives import CALL, prim
from rcl.words.compiling import parse_word

BLOCK = 1024
NBUF = 2
SCRATCH_BLOCKS = 1024          # the scratch file: 1 MiB of host memory at most
SNIFF = 64 * BLOCK             # what USING reads to tell text from blocks
MAX_TEXT = 1 << 20             # a text file USING keeps in memory as screens
MAX_NEW = 4096                 # CREATE-BLOCKS and MORE add at most this many at once
FILE_ERROR = -37


class BlockFile:
    """The open block file and the two block buffers."""

    def __init__(self, machine):
        self.m = machine
        self.path = None               # None: the scratch file
        self.data = bytearray()        # the scratch blocks, or a text file's screens
        self.blocks = 0                # blocks in the file
        self.readonly = False
        self.buffers = [[None, False] for _ in range(NBUF)]   # [block, updated]
        self.current = 0

    def open(self, path):
        """Open path as the block file (a text file read only). A block file
        stays on disk, read a block at a time; a text file's screens are
        kept in memory, so it may hold at most MAX_TEXT bytes."""
        size = regular_size(path)
        with open(path, "rb") as f:
            head = f.read(SNIFF)               # (a line end in it: a text file)
            readonly = not is_block_file(path, head)
            if readonly:
                if size > MAX_TEXT:
                    raise ForthError(FILE_ERROR, "%s is a text file of %d bytes: USING reads "
                                     "at most %d of text" % (path, size, MAX_TEXT))
                raw = text_to_blocks((head + f.read(MAX_TEXT)).decode("latin-1"), path)
        self.flush()
        self.path, self.readonly = path, readonly
        self.data = bytearray(raw[:len(raw) - len(raw) % BLOCK]) if readonly else bytearray()
        self.blocks = len(self.data) // BLOCK if readonly else size // BLOCK   # (a CP/M tail
        self.buffers = [[None, False] for _ in range(NBUF)]                    # is not a block)

    def create(self, path, n):
        """A new block file of n blank screens, then open it."""
        with open(path, "xb") as f:
            f.write(b" " * (BLOCK * n))
        self.open(path)

    def more(self, n):
        """F83's MORE: n blank blocks at the end of the open file; if they
        cannot all be written (a full disk), the file keeps its old size."""
        self.check_writable()
        self.write_file(self.blocks * BLOCK, b" " * (BLOCK * n), truncate_on_error=True)
        self.blocks += n

    @property
    def name(self):
        return self.path if self.path is not None else "(scratch blocks in memory)"

    @property
    def count(self):
        return SCRATCH_BLOCKS if self.path is None else self.blocks

    def addr(self, i):
        return BLOCK_BUFFERS + i * BLOCK

    def check(self, n):
        if self.path is not None and not self.readonly and n >= self.blocks:
            self.blocks = self.file_blocks()      # another writer may have made it longer
        if not 0 <= n < self.count:
            raise ForthError(-35, "Block %d out of range (%s has %d)" % (n, self.name, self.count))

    def check_writable(self):
        if self.readonly:
            raise ForthError(FILE_ERROR, "%s is a text file, read only here "
                             "(python -m rcl.blocks makes a block file of it)" % self.path)

    def buffer(self, n):
        """A buffer assigned to block n, written back first if updated."""
        self.check(n)
        for i, (blk, _) in enumerate(self.buffers):
            if blk == n:
                self.current = i
                return self.addr(i)
        i = (self.current + 1) % NBUF
        self.write_back(i)
        self.buffers[i] = [n, False]
        self.current = i
        return self.addr(i)

    def block(self, n):
        self.check(n)
        for i, (blk, _) in enumerate(self.buffers):
            if blk == n:
                self.current = i
                return self.addr(i)
        a = self.buffer(n)
        self.m.memory.write(a, self.read(n))
        return a

    def read(self, n):
        """Block n as it is now: from the file itself (another program, or
        the File-Access words, may have written it), else from memory."""
        if self.path is None or self.readonly:
            return bytes(self.data[n * BLOCK:(n + 1) * BLOCK]).ljust(BLOCK)   # scratch: blank
        try:
            with open(self.path, "rb") as f:
                f.seek(n * BLOCK)
                return f.read(BLOCK).ljust(BLOCK)
        except OSError as exc:
            raise ForthError(FILE_ERROR, "Cannot read %s: %s" % (self.path, exc.strerror)) from None

    def file_blocks(self):
        try:
            return os.path.getsize(self.path) // BLOCK
        except OSError:
            return self.blocks

    def update(self):
        self.check_writable()
        if self.buffers[self.current][0] is not None:
            self.buffers[self.current][1] = True

    def write_back(self, i):
        blk, updated = self.buffers[i]
        if not updated or blk is None:
            return
        data = self.m.memory.read(self.addr(i), BLOCK)
        if self.path is not None:
            self.write_file(blk * BLOCK, data)
        else:
            if len(self.data) < (blk + 1) * BLOCK:
                self.data += b" " * ((blk + 1) * BLOCK - len(self.data))
            self.data[blk * BLOCK:(blk + 1) * BLOCK] = data
        self.buffers[i][1] = False

    def write_file(self, offset, data, truncate_on_error=False):
        """Write data at offset of the block file in place (nothing else
        moves); growing it (truncate_on_error), a failed write is undone."""
        try:
            with open_file(self.path, "r+b") as f:
                f.seek(offset)
                try:
                    f.write(data)
                    f.flush()
                except OSError:
                    if truncate_on_error:
                        f.truncate(offset)
                    raise
        except OSError as exc:
            raise ForthError(FILE_ERROR, "Cannot write %s: %s" % (self.path, exc.strerror)) from None

    def flush(self):
        for i in range(NBUF):
            self.write_back(i)

    def where(self, n, offset):
        """`screen n line k` for an error at offset in screen n (and the
        text file's own line when the screens come from one)."""
        line = min(max(offset - 1, 0) // LINE, LINES - 1)
        text = " (line %d of the text)" % ((n - 1) * LINES + line + 1) if self.readonly else ""
        return "screen %d line %d%s" % (n, line, text)

    def load(self, n):
        if n == 0:
            raise ForthError(-35, "Block 0 cannot be loaded")
        m = self.m
        self.block(n)
        m.push_source(Source("block", source_id=0, name=self.name))
        m.memory.store(m.a_blk, n)
        try:
            m.interpret()
        except ForthError as e:
            if e.file is None:
                e.file = self.name
                e.line = self.where(m.memory.fetch(m.a_blk), m.memory.fetch(m.a_in))
            raise
        finally:
            m.pop_source()


def reopen_blocks(m, path):
    """The block file open when the system was saved, if it is still there."""
    m.blocks = BlockFile(m)
    if path:
        try:
            m.blocks.open(path)
        except (OSError, RclError, ValueError):   # gone, or no longer a block file
            pass


# The open block file is the system's (an image names it; its buffers start empty).
state.system("blocks", BlockFile, lambda m: m.blocks.path, reopen_blocks)


def open_file(path, mode):
    """open(), kept a name of its own so a test can give a file that fails."""
    return open(path, mode)


def regular_size(path):
    """The size of path if it is a regular file; else a Forth error (a FIFO,
    /dev/zero or a directory would be read forever or not at all)."""
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise                          # USING says how to make one
    except OSError as exc:
        raise ForthError(FILE_ERROR, "Cannot open %s: %s" % (path, exc.strerror)) from None
    if not stat.S_ISREG(info.st_mode):
        raise ForthError(FILE_ERROR, "%s is not a regular file" % path)
    return info.st_size


def bf(m):
    return m.blocks


def need(m, n):
    """F83's check in THRU, LIST, LOAD and friends."""
    if len(m.s) < n:
        raise ForthError(-258, "Not enough Parameters")


def file_name(m):
    name = parse_word(m)
    if "\0" in name:
        raise ForthError(-38, "File not found", name.replace("\0", "?"))
    return name


def screens(n):
    """A count of new screens: at least 1, at most MAX_NEW at once (4 MiB)."""
    if not 1 <= n <= MAX_NEW:
        raise ForthError(-24, "%d screens? 1 to %d at a time" % (signed(n), MAX_NEW))
    return n


@prim("USING", "( -- ) open the block file named next (a text file: read only)")
def using(m):
    name = file_name(m)
    try:
        bf(m).open(name)
    except FileNotFoundError:
        raise ForthError(-38, "File not found (n CREATE-BLOCKS %s makes one)" % name,
                         name) from None
    except BlockFormatError as exc:
        raise ForthError(-37, str(exc)) from None
    except OSError as exc:
        raise ForthError(-37, "Cannot open %s: %s" % (name, exc.strerror)) from None


@prim("CREATE-BLOCKS", "( n -- ) make the block file named next, n blank screens, "
      "and use it")
def create_blocks(m):
    need(m, 1)
    n = screens(m.s.pop())
    name = file_name(m)
    if os.path.exists(name):
        raise ForthError(-37, "%s exists: USING %s opens it" % (name, name))
    try:
        bf(m).create(name, n)
    except OSError as exc:
        raise ForthError(-37, "Cannot create %s: %s" % (name, exc.strerror)) from None


@prim("MORE", "( n -- ) add n blank screens to the end of the block file (F83)")
def more(m):
    need(m, 1)
    if bf(m).path is None:
        raise ForthError(-35, "The scratch blocks have %d screens, no more" % SCRATCH_BLOCKS)
    bf(m).more(screens(m.s.pop()))


@prim("BLOCK", "( n -- addr ) the buffer holding block n")
def block(m):
    need(m, 1)
    m.s.append(bf(m).block(m.s.pop()))


@prim("BUFFER", "( n -- addr ) a buffer for block n, not read")
def buffer(m):
    need(m, 1)
    m.s.append(bf(m).buffer(m.s.pop()))


@prim("UPDATE", "( -- ) mark the current buffer modified (refused for a text file)")
def update(m):
    bf(m).update()


@prim("SAVE-BUFFERS", "( -- ) write modified buffers")
def save_buffers(m):
    bf(m).flush()


@prim("FLUSH", "( -- ) write modified buffers and unassign them")
def flush(m):
    bf(m).flush()
    bf(m).buffers = [[None, False] for _ in range(NBUF)]


@prim("EMPTY-BUFFERS", "( -- ) unassign every buffer without writing")
def empty_buffers(m):
    bf(m).buffers = [[None, False] for _ in range(NBUF)]


@prim("LOAD", "( n -- ) interpret block n", kind=CALL)
def load(m):
    need(m, 1)
    bf(m).load(m.s.pop())


@prim("THRU", "( first last -- ) load a range of blocks", kind=CALL)
def thru(m):
    need(m, 2)
    last, first = m.s.pop(), m.s.pop()
    for n in range(first, last + 1):
        bf(m).load(n)


@prim("+THRU", "( lo hi -- ) load blocks relative to the one being loaded",
      kind=CALL)
def plus_thru(m):
    need(m, 2)
    hi, lo = m.s.pop(), m.s.pop()
    base = m.memory.fetch(m.a_blk)
    for n in range(base + signed(lo), base + signed(hi) + 1):
        bf(m).load(n)


@prim("-->", "( -- ) go on with the next block", immediate=True)
def next_block(m):
    blk = m.memory.fetch(m.a_blk)
    if blk:
        next_block_source(m, blk)


def next_block_source(m, blk):
    """--> and REFILL in a block: go on at the start of block blk + 1."""
    bf(m).block(blk + 1)
    m.memory.store(m.a_blk, (blk + 1) & MASK)
    m.memory.store(m.a_in, 0)


@prim("LIST", "( n -- ) show screen n")
def list_(m):
    need(m, 1)
    n = m.s.pop()
    a = bf(m).block(n)
    m.memory.store(m.a_scr, n)
    rows = ["Scr # %d   %s" % (n, bf(m).name)]
    for i in range(16):
        rows.append("%3d %s" % (i, m.memory.text(a + 64 * i, 64).rstrip()))
    m.type("\n" + "\n".join(rows) + "\n")


@prim("INDEX", "( first last -- ) line 0 of each screen")
def index(m):
    need(m, 2)
    last, first = m.s.pop(), m.s.pop()
    for n in range(first, min(last, bf(m).count - 1) + 1):
        m.type("\n%3d %s" % (n, m.memory.text(bf(m).block(n), 64).rstrip()))
    m.type("\n")
