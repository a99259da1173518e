"""The memory image: one 64 KiB byte-addressed segment, 16-bit cells.

    0x0000 +-----------------------------+
           | unused: code-field values    |  a code field holding a value below
           | below 0x0400 name primitives |  PRIM_LIMIT names a Python primitive
    0x0400 +-----------------------------+
           | system variables (BASE ...)  |
    0x0480 +-----------------------------+
           | dictionary: headers, code,   |  grows up; HERE is its end
           | data   ...   HERE            |
           | WORD buffer at HERE, hold    |
           | area below PAD = HERE + 340  |
    0xCC00 +-----------------------------+  DICT_LIMIT
           | S" buffers (4 x 256)         |
    0xD000 +-----------------------------+
           | block buffers (2 x 1024)     |
    0xD800 +-----------------------------+
           | input buffers: TIB, then one |  a stack of line buffers for
           | line buffer per nested file  |  INCLUDE nesting
    0xFFFF +-----------------------------+

Cells are little-endian; a double in memory keeps its high cell at the lower
address (F83). Every store from Python goes through `store`/`cstore`/`write`
so that a store into compiled code or a header is seen (`watch` marks).
"""

SIZE = 0x10000
MASK = 0xFFFF
PRIM_LIMIT = 0x0400          # code-field values below this are primitives
USER_AREA = 0x0400           # BASE, STATE, DPL ... one cell each
DICT_START = 0x0480
DICT_LIMIT = 0xCC00
STRING_BUFFERS = 0xCC00      # four 256-byte buffers for interpreted S"
BLOCK_BUFFERS = 0xD000       # two 1024-byte block buffers
INPUT_AREA = 0xD800          # TIB and the line-buffer stack (10 KiB)
TIB_SIZE = 256
PAD_OFFSET = 340             # PAD is this far above HERE
HOLD_SIZE = 80               # pictured numeric output grows down from PAD

WATCH_CODE = 1               # byte belongs to threaded code compiled to Python
WATCH_HEADER = 2             # byte belongs to a header (name lookup cache)


def signed(v):
    """A cell as a signed int."""
    return v - 0x10000 if v & 0x8000 else v


def dsigned(v):
    """A 32-bit double as a signed int."""
    return v - 0x100000000 if v & 0x80000000 else v


class Memory:
    """The 64 KiB segment with its watch marks.

    `mem` is the bytearray itself; the inner interpreter's compiled code
    indexes it directly. `on_watched(addr, n)` is called after a store of n
    bytes (2 unless said) that hit a watched byte.
    """

    def __init__(self, on_watched=lambda addr, n=2: None):
        self.mem = bytearray(SIZE)
        self.watch = bytearray(SIZE)
        self.on_watched = on_watched

    def fetch(self, a):
        m = self.mem
        return m[a] | (m[(a + 1) & MASK] << 8)

    def store(self, a, v):
        m = self.mem
        a2 = (a + 1) & MASK
        m[a] = v & 0xFF
        m[a2] = (v >> 8) & 0xFF
        if self.watch[a] or self.watch[a2]:
            self.on_watched(a)

    def cfetch(self, a):
        return self.mem[a]

    def cstore(self, a, c):
        self.mem[a] = c & 0xFF
        if self.watch[a]:
            self.on_watched(a)

    def dfetch(self, a):
        """( addr -- lo hi ) as F83's 2@: the high cell is at addr."""
        return self.fetch((a + 2) & MASK), self.fetch(a)

    def dstore(self, a, lo, hi):
        self.store(a, hi)
        self.store((a + 2) & MASK, lo)

    def read(self, a, n):
        """n bytes from a, wrapping at the top of the segment."""
        if n <= 0:
            return b""
        if a + n <= SIZE:
            return bytes(self.mem[a:a + n])
        return bytes(self.mem[a:]) + self.read(0, n - (SIZE - a))

    def write(self, a, data):
        """Store bytes at a, wrapping; one watch check for the whole range."""
        n = len(data)
        if n == 0:
            return
        if a + n <= SIZE:
            self.mem[a:a + n] = data
            if any(self.watch[a:a + n]):
                self.on_watched(a, n)
        else:
            k = SIZE - a
            self.write(a, data[:k])
            self.write(0, data[k:])

    def text(self, a, n):
        return self.read(a, n).decode("latin-1")
