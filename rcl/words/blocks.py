"""Blocks and screens: 1024-byte blocks from a block file, shown as 16
lines of 64 characters (f83-semantics.md section 10).

Two buffers in memory (memory.BLOCK_BUFFERS). A block file is a raw
concatenation of blocks; a plain-text file (one with newlines) is read as
screens too, each line padded or cut to 64 columns, 16 lines a block.
Block 0 can never be loaded (BLK = 0 means the terminal).
"""
from rcl.errors import ForthError
from rcl.forth.memory import BLOCK_BUFFERS, signed
from rcl.forth.outer import Source
from rcl.forth.primitives import prim
from rcl.words.compiling import parse_word

BLOCK = 1024
NBUF = 2


class BlockFile:
    """The open block file and the two block buffers."""

    def __init__(self, machine):
        self.m = machine
        self.path = None
        self.data = bytearray()
        self.buffers = [[None, False] for _ in range(NBUF)]   # [block, updated]
        self.current = 0

    def open(self, path):
        with open(path, "rb") as f:
            raw = f.read()
        if b"\n" in raw:                      # text: every 16 lines are a screen
            lines = raw.decode("latin-1").splitlines()
            raw = b"".join(l.expandtabs(8)[:64].ljust(64).encode("latin-1") for l in lines)
            raw += b" " * (-len(raw) % BLOCK)
        self.flush()
        self.path, self.data = path, bytearray(raw[:len(raw) - len(raw) % BLOCK])
        self.buffers = [[None, False] for _ in range(NBUF)]

    @property
    def count(self):
        return len(self.data) // BLOCK

    def addr(self, i):
        return BLOCK_BUFFERS + i * BLOCK

    def buffer(self, n):
        """A buffer assigned to block n, written back first if updated."""
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
        if self.path is None:
            raise ForthError(-35, "No block file")
        if not 0 <= n < self.count:
            raise ForthError(-35, "Block %d out of range" % n)
        for i, (blk, _) in enumerate(self.buffers):
            if blk == n:
                self.current = i
                return self.addr(i)
        a = self.buffer(n)
        self.m.memory.write(a, bytes(self.data[n * BLOCK:(n + 1) * BLOCK]))
        return a

    def write_back(self, i):
        blk, updated = self.buffers[i]
        if updated and blk is not None:
            self.data[blk * BLOCK:(blk + 1) * BLOCK] = self.m.memory.read(self.addr(i), BLOCK)
            with open(self.path, "wb") as f:
                f.write(self.data)
            self.buffers[i][1] = False

    def flush(self):
        for i in range(NBUF):
            if self.path:
                self.write_back(i)

    def load(self, n):
        if n == 0:
            raise ForthError(-35, "Block 0 cannot be loaded")
        m = self.m
        self.block(n)
        m.push_source(Source("block", source_id=0, name=self.path))
        m.memory.store(m.a_blk, n)
        try:
            m.interpret()
        except ForthError as e:
            if e.file is None:
                e.file = self.path
                e.line = "block %d line %d" % (m.memory.fetch(m.a_blk),
                                               m.memory.fetch(m.a_in) // 64)
            raise
        finally:
            m.pop_source()


def bf(m):
    return m.blocks


def need(m, n):
    """F83's check in THRU, LIST, LOAD and friends."""
    if len(m.s) < n:
        raise ForthError(-258, "Not enough Parameters")


@prim("USING", "( -- ) open the block file named next")
def using(m):
    name = parse_word(m)
    try:
        bf(m).open(name)
    except (OSError, ValueError):
        raise ForthError(-38, "File not found", name.replace("\0", "?")) from None


@prim("BLOCK", "( n -- addr ) the buffer holding block n")
def block(m):
    need(m, 1)
    m.s.append(bf(m).block(m.s.pop()))


@prim("BUFFER", "( n -- addr ) a buffer for block n, not read")
def buffer(m):
    need(m, 1)
    m.s.append(bf(m).buffer(m.s.pop()))


@prim("UPDATE", "( -- ) mark the current buffer modified")
def update(m):
    bf(m).buffers[bf(m).current][1] = True


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


@prim("LOAD", "( n -- ) interpret block n", kind="call")
def load(m):
    need(m, 1)
    bf(m).load(m.s.pop())


@prim("THRU", "( first last -- ) load a range of blocks", kind="call")
def thru(m):
    need(m, 2)
    last, first = m.s.pop(), m.s.pop()
    for n in range(first, last + 1):
        bf(m).load(n)


@prim("+THRU", "( lo hi -- ) load blocks relative to the one being loaded",
      kind="call")
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
        m.memory.store(m.a_blk, blk + 1)
        bf(m).block(blk + 1)
        m.memory.store(m.a_in, 0)


@prim("LIST", "( n -- ) show screen n")
def list_(m):
    need(m, 1)
    n = m.s.pop()
    a = bf(m).block(n)
    m.memory.store(m.a_scr, n)
    rows = ["Scr # %d   %s" % (n, bf(m).path)]
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
