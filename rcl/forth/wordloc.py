"""Where code came from: the file and line each address of the dictionary
was laid down from, and the chain of words an error ran through.

As the outer interpreter reads each line it marks HERE with the line's
place; everything compiled from HERE up to the next mark came from that
line. Typed or evaluated lines mark "no file", so a file's mark never
reaches over code typed after it; a mark below older ones (after FORGET or
a MARKER) drops them.

    marks:  addr 4000  file rt.fs line 1     : FOO ( -- ) DROP ;
            addr 4012  file rt.fs line 2     : BAR FOO ;
            addr 4020  (typed)               : BAZ BAR ;

The backtrace is worked out only when an error is reported, from the
return stack as the error left it (compiled code and the reference loop
both keep it true: inner.py) and the dictionary: a return address r lies
in the word that made the call, and the cell before it holds what was
called. Nothing here runs while words run but one `mark` a line.
"""
import bisect

from rcl.forth.memory import MASK, PRIM_LIMIT


class Locations:
    """Source places of the dictionary's addresses (plain data: it is
    copied with the boot image and kept in the start cache)."""

    def __init__(self):
        self.addrs = []          # ascending
        self.places = []         # (file or None, line or None), one per addr

    def mark(self, addr, file, line):
        """Code from addr up comes from file:line (file None: not a file)."""
        i = bisect.bisect_left(self.addrs, addr)
        del self.addrs[i:], self.places[i:]
        self.addrs.append(addr)
        self.places.append((file, line))

    def at(self, addr):
        """(file, line) that laid down addr, or (None, None) if unknown."""
        i = bisect.bisect_right(self.addrs, addr) - 1
        return self.places[i] if i >= 0 else (None, None)

    def copy(self):
        other = Locations()
        other.addrs, other.places = list(self.addrs), list(self.places)
        return other


# ------------------------------------------------------------ words at addresses
def headers(m):
    """Every header's xt in the dictionary, ascending."""
    d = m.dictionary
    return sorted({(lfa + 2) & MASK for wid in d.wordlists() + [m.root_wid]
                   for lfa in d.lfas(wid)})


def containing(m, addr, xts=None):
    """The xt of the word whose code or data holds addr, or None."""
    xts = headers(m) if xts is None else xts
    i = bisect.bisect_right(xts, addr) - 1
    if i < 0 or addr >= m.dictionary.here:
        return None
    return xts[i]


def defined_at(m, xt):
    """(file, line) where the word xt was defined, or (None, None)."""
    return m.locations.at(m.dictionary.header_start(xt))


# ------------------------------------------------------------------ backtrace
def backtrace(m, rs):
    """The words an error ran through, innermost first: [(name, file, line)],
    file:line being where that word was running (its call of the next
    inner word), or where the innermost word was defined. From the return
    stack `rs` (bottom first) as the error left it; cells that are not
    return addresses into colon definitions (loop indexes, >R values) are
    passed over."""
    xts = headers(m)
    frames = []
    for r in reversed(rs):
        caller = return_site(m, r, xts)
        if caller is None:
            continue
        if not frames:                        # the word it called was running
            callee = called(m, (r - 2) & MASK)
            if callee is not None:
                frames.append(frame(m, callee, *defined_at(m, callee)))
        frames.append(frame(m, caller, *m.locations.at((r - 2) & MASK)))
    return frames


def return_site(m, r, xts):
    """The colon word r returns into, if r is a return address (the cell
    before it calls a word), else None."""
    if r < PRIM_LIMIT + 2:
        return None
    xt = containing(m, (r - 2) & MASK, xts)
    if xt is None or (r - 2) & MASK < xt + 2 or called(m, (r - 2) & MASK) is None:
        return None
    return xt


def called(m, cell):
    """The word the cell at `cell` calls, looked through DEFER, if it names
    a word; else None."""
    fetch = m.memory.fetch
    xt = fetch(cell)
    name = m.dictionary.name_of(xt)
    if name is None:
        return None
    cf = fetch(xt)
    if cf == runtime(m, "(DODEFER)"):
        action = fetch((xt + 2) & MASK)
        if m.dictionary.name_of(action):
            return action
    return xt


def runtime(m, name):
    from rcl.forth.inner import N
    return N[name]


def frame(m, xt, file, line):
    return (m.dictionary.name_of(xt) or "at %d" % xt, file, line)


def describe(frames):
    """Lines naming the word an error came from and its callers (gforth's
    backtrace, innermost first); [] when the error came from no word."""
    lines = []
    for i, (name, file, line) in enumerate(frames):
        where = "  %s:%s" % (file, line) if file else ""
        lines.append("%s %s%s" % ("in" if i == 0 else "  called from", name, where))
    return lines
