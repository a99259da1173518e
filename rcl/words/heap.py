"""Memory-Allocation word set (Forth 2012 chapter 14): ALLOCATE FREE RESIZE
on a heap inside the 64 KiB image.

    HERE ... PAD ...          floor                    DICT_LIMIT (0xCC00)
    | dictionary grows up ->  |  <- heap grows down  | blk | blk | ... |

The heap takes space from the top of the dictionary area, only as much as
it holds: the dictionary may grow up to the heap's floor (less PAD), the
heap down to HERE + PAD. Which blocks exist is kept here in Python (so a
program that scribbles over the heap cannot corrupt the allocator), the
bytes live in the image. Addresses are cells; sizes are rounded up to
whole cells. Exhaustion or a bad address gives the standard ior
(-59 ALLOCATE, -60 FREE, -61 RESIZE), never an exception.
"""
import bisect

from rcl.forth.memory import DICT_LIMIT, MASK, PAD_OFFSET
from rcl.forth import state
from rcl.forth.primitives import prim

ALLOCATE_IOR, FREE_IOR, RESIZE_IOR = -59, -60, -61
HEADROOM = PAD_OFFSET + 256     # kept between HERE and the heap, for PAD and WORD


class Heap:
    """Blocks by address, and a sorted free list, below DICT_LIMIT."""

    def __init__(self, machine):
        self.m = machine
        self.used = {}          # addr -> size
        self.free = []          # sorted [(addr, size)]
        machine.heap_floor = DICT_LIMIT

    @property
    def floor(self):
        return self.m.heap_floor

    def allocate(self, n):
        """-> address of n fresh bytes, or None."""
        n = max(2, n + (n & 1))
        for i, (a, size) in enumerate(self.free):
            if size >= n:
                if size - n >= 2:
                    self.free[i] = (a + n, size - n)
                else:
                    del self.free[i]
                    n = size
                self.used[a] = n
                return a
        a = self.floor - n
        if a < self.m.dictionary.here + HEADROOM:
            return None
        self.m.heap_floor = a
        self.used[a] = n
        return a

    def release(self, a):
        """Free the block at a; False if a is not a block's address."""
        n = self.used.pop(a, None)
        if n is None:
            return False
        bisect.insort(self.free, (a, n))
        self.coalesce()
        return True

    def coalesce(self):
        merged = []
        for a, n in self.free:
            if merged and merged[-1][0] + merged[-1][1] == a:
                merged[-1] = (merged[-1][0], merged[-1][1] + n)
            else:
                merged.append((a, n))
        if merged and merged[0][0] == self.floor:      # give the bottom back
            self.m.heap_floor += merged[0][1]
            del merged[0]
        self.free = merged

    def resize(self, a, n):
        """-> the block's new address (contents kept), or None (a untouched)."""
        old = self.used.get(a)
        if old is None:
            return None
        if n <= old:                         # shrinking: stay where it is
            return a
        b = self.allocate(n)
        if b is None:
            return None
        self.m.memory.write(b, self.m.memory.read(a, old))
        self.release(a)
        return b


    def plain(self):
        return {"used": sorted(self.used.items()), "free": [list(b) for b in self.free]}

    @classmethod
    def from_plain(cls, m, data):
        """The heap a snapshot holds (heap_floor is restored on its own)."""
        h, floor = cls.__new__(cls), m.heap_floor
        h.m = m
        h.used = {int(a): int(n) for a, n in data["used"]}
        h.free = [(int(a), int(n)) for a, n in data["free"]]
        m.heap = h
        return h


# The heap's blocks and floor are the system's: a saved system keeps them
# (its blocks' bytes are in the image), so FREE and ALLOCATE go on from there.
state.system("heap_floor", lambda m: DICT_LIMIT)
state.system("heap", Heap, lambda m: m.heap.plain(), Heap.from_plain)


def heap(m):
    return m.heap


@prim("ALLOCATE", "( u -- addr ior ) u bytes from the heap; ior -59 if there is no room")
def allocate(m):
    a = heap(m).allocate(m.s.pop())
    m.s.extend((a, 0) if a is not None else (0, ALLOCATE_IOR & MASK))


@prim("FREE", "( addr -- ior ) give back a block ALLOCATE gave; ior -60 if it is none")
def free(m):
    m.s.append(0 if heap(m).release(m.s.pop()) else FREE_IOR & MASK)


@prim("RESIZE", "( addr u -- addr' ior ) a block of u bytes holding the old contents")
def resize(m):
    u, a = m.s.pop(), m.s.pop()
    b = heap(m).resize(a, u)
    m.s.extend((b, 0) if b is not None else (a, RESIZE_IOR & MASK))


def dictionary_limit(m):
    """Where the dictionary must stop: the heap's floor (DICT_LIMIT when empty)."""
    return m.heap_floor
