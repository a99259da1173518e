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
        self.places.append((file, line if file else None))

    def at(self, addr):
        """(file, line) that laid down addr, or (None, None) if unknown."""
        i = bisect.bisect_right(self.addrs, addr) - 1
        return self.places[i] if i >= 0 else (None, None)

    def copy(self):
        other = Locations()
        other.addrs, other.places = list(self.addrs), list(self.places)
        return other

    def plain(self):
        """[[addr, file, line], ...]: what a snapshot holds."""
        return [[a, f, n] for a, (f, n) in zip(self.addrs, self.places)]

    @classmethod
    def from_plain(cls, marks):
        other = cls()
        for a, f, n in marks:
            other.addrs.append(a)
            other.places.append((f, n))
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
def backtrace(m, rs, tb=None):
    """The words an error ran through, innermost first: [(name, file,
    line)]: the innermost with the place it is defined, each caller with
    the place of its call. Each running colon word has a Python frame in
    the error's traceback `tb` (its compiled function, or the reference
    loop), and small words pasted into their caller are named on the
    compiled line (compiler.INLINED); the place of each call is the return
    address the call left on the return stack `rs` (bottom first), as the
    error left it. Without tb, the return stack alone."""
    xts = headers(m)
    if tb is None:
        return from_return_stack(m, rs, xts)
    running = activations(m, tb, xts)          # [[xt, call cell or None]], outermost first
    returns = [r for r in rs if return_site(m, r, xts) is not None]
    used = 0
    for act in running[:-1]:
        if act[1] is not None:
            continue
        for i in range(used, len(returns)):
            if containing(m, (returns[i] - 2) & MASK, xts) == act[0]:
                act[1], used = (returns[i] - 2) & MASK, i + 1
                break
    # Calls pasted into compiled code whose slow path ran them (a stack too
    # short for the fast path, an interrupt due) left their return
    # addresses, as the reference loop does: the innermost word's calls.
    for r in returns[used:]:
        cell = (r - 2) & MASK
        callee = called(m, cell)
        if running and callee is not None and containing(m, cell, xts) == running[-1][0]:
            running[-1][1] = cell
            running.append([callee, None])
    frames = []
    for i, (xt, cell) in enumerate(running):
        place = defined_at(m, xt) if i == len(running) - 1 or cell is None \
            else m.locations.at(cell)
        frames.append(frame(m, xt, *place))
    return frames[::-1]


def activations(m, tb, xts):
    """[[xt, the cell of its call of the next one, if known]] of the colon
    words running at the error, outermost first, from its traceback."""
    from rcl.forth import inner
    bodies = {f.__code__: (a, f) for a, f in m.fn.items() if hasattr(f, "__code__")}
    running = []
    while tb is not None:
        code = tb.tb_frame.f_code
        if code.co_filename == inner.COMPILED and code in bodies:
            entry, f = bodies[code]
            xt = containing(m, entry, xts)
            if xt is not None:
                running.append([xt, None])
            for call in pasted_calls(getattr(f, "source", ""), tb.tb_lineno):
                callee = called(m, call)
                if callee is None:
                    break
                if running:
                    running[-1][1] = call
                running.append([callee, None])
        elif code.co_filename == inner.__file__ and code.co_name == "run_from":
            xt = containing(m, (tb.tb_frame.f_locals.get("ip", 0) - 2) & MASK, xts)
            if xt is not None:
                running.append([xt, None])
        tb = tb.tb_next
    return running


def pasted_calls(source, lineno):
    """The call cells of the words pasted into compiled code at its line
    lineno (compiler.INLINED), outermost first."""
    from rcl.forth.compiler import INLINED
    lines = (source or "").split("\n")
    text = lines[lineno - 1] if 0 < lineno <= len(lines) else ""
    return [int(a) for a in text.split(INLINED, 1)[1].split()] if INLINED in text else []


def from_return_stack(m, rs, xts):
    """The backtrace from the return stack alone (no traceback)."""
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
    """Lines naming the word an error came from and its callers, innermost
    first, as gforth's backtrace does; [] when it came from no word:

          in FOO  rt.fs:1              (where FOO is defined)
          called from BAR  rt.fs:3     (where BAR calls FOO)
    """
    lines = []
    for i, (name, file, line) in enumerate(frames or ()):
        where = "  %s:%s" % (file, line) if file else ""
        lines.append("  %s %s%s" % ("in" if i == 0 else "called from", name, where))
    return lines
