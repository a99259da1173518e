"""Which compiled code rests on which bytes of memory, and what a store
there throws away.

A compiled function (compiler.compile_code) is right only while the bytes
it was made from hold what they held: its threaded code and that of the
calls pasted into it, the code fields of the words it calls, a CONSTANT's
cell, the code field of the colon word a vector held (its `marks`). Those
bytes are marked WATCH_CODE in `watch`; a store that hits one
(Forth.watched) drops exactly the functions resting on it:

* they leave m.fn, so the next call compiles the code as memory has it now;
* their STALE flag is set, so a call of theirs still running (the caller
  of the word that stored, a loop whose body stored into a word it calls)
  goes on in the reference loop from the next primitive (compiler.py: a
  running definition that finds its code changed).

Forgetting (FORGET, a MARKER) drops only what rests on the forgotten bytes;
a word defined before keeps its compiled code.
"""
from rcl.forth.memory import MASK, WATCH_CODE

KEEP_OTHERS = 0xFF & ~WATCH_CODE


class CodeDeps:
    """The functions of one machine's m.fn and the bytes each rests on."""
    __slots__ = ("by_byte", "funcs")

    def __reduce__(self):
        return CodeDeps, ()      # compiled code is never saved (a snapshot has none)

    def __init__(self):
        self.by_byte = {}        # address -> entries of the functions resting on it
        self.funcs = {}          # entry -> (function, its marks)

    def add(self, m, entry, f):
        """f, compiled from the code at entry, is now m.fn[entry]."""
        if entry in self.funcs:
            self.drop(m, entry)
        marks = f.marks
        self.funcs[entry] = (f, marks)
        by, watch = self.by_byte, m.watch
        for a in marks:
            s = by.get(a)
            if s is None:
                by[a] = {entry}
                watch[a] |= WATCH_CODE
            else:
                s.add(entry)

    def drop(self, m, entry):
        """Forget the function compiled from entry; one still running finds
        itself stale."""
        f, marks = self.funcs.pop(entry)
        f.__globals__["STALE"] = True
        if m.fn.get(entry) is f:
            del m.fn[entry]
        by, watch = self.by_byte, m.watch
        for a in marks:
            s = by[a]
            s.discard(entry)
            if not s:
                del by[a]
                watch[a] &= KEEP_OTHERS

    def resting_on(self, lo, n):
        """The entries of the functions resting on any of the n bytes from lo."""
        by, out = self.by_byte, set()
        for a in range(lo, lo + n):
            s = by.get(a & MASK)
            if s:
                out |= s
        return out

    def hit(self, m, lo, n):
        """A store changed the n bytes from lo: drop what rests on them."""
        for entry in self.resting_on(lo, n):
            self.drop(m, entry)

    def drop_all(self, m):
        """Every function goes (the costs changed, a system was loaded)."""
        for f, _ in self.funcs.values():
            f.__globals__["STALE"] = True
        self.funcs.clear()
        self.by_byte.clear()
