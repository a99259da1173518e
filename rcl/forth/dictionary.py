"""The dictionary: headers in memory, word lists, the search order.

A header, as laid down in memory (one word, SQ, defined as `: SQ DUP * ;`):

      lfa-3    lfa-1   lfa        lfa+2 = xt          lfa+4
    +-------+-------+----------+------------------+-----------------------+
    | S  Q  | count | link     | code field       | body: xt DUP, xt *,   |
    | name  | 0x82  | prev lfa | (DOCOL)          | xt EXIT               |
    +-------+-------+----------+------------------+-----------------------+

    count byte: 0x80 always | 0x40 IMMEDIATE | 0x20 HIDDEN | length (<= 31)

Everything is found from the link field address (lfa): the name lies just
below the count byte, so an xt leads back to its name (xt - 2 = lfa).
A word list is a cell holding the lfa of its newest header (its wid is the
cell's address); a vocabulary's body holds that cell and a link to the
previous vocabulary (VOC-LINK chains them all, for FORGET).

The search order is CONTEXT (8 cells, first searched first) with #ORDER
cells in use; CURRENT receives new definitions. Name lookups go through a
Python cache per word list, checked against the list's head and a
generation count that any store into a header bumps: memory stays the truth.
"""
from rcl.errors import ForthError
from rcl.forth.memory import (DICT_LIMIT, MASK, PAD_OFFSET, PRIM_LIMIT,
                              WATCH_HEADER)

IMMEDIATE = 0x40
HIDDEN = 0x20
NAME_MAX = 31
CLEAR_HEADER = bytes(b & ~WATCH_HEADER for b in range(256))
ORDER_MAX = 8


class Dictionary:
    """Headers, word lists and the search order of one machine."""

    def __init__(self, machine):
        self.m = machine
        self.memory = machine.memory
        self.cache = {}          # wid -> (head, generation, {name: [lfa...]})
        self.generation = 0
        self.rebuilds = 0        # name tables built from memory (a cost worth watching)

    # ------------------------------------------------------------ space
    @property
    def here(self):
        return self.memory.fetch(self.m.a_dp)

    @here.setter
    def here(self, a):
        self.memory.store(self.m.a_dp, a & MASK)

    def allot(self, n):
        h = self.here + n
        # The heap (ALLOCATE) may hold the top of the dictionary area.
        if h > getattr(self.m, "heap_floor", DICT_LIMIT) - PAD_OFFSET:
            raise ForthError(-8, "Dictionary full")
        if h < self.memory.fetch(self.m.a_fence):
            raise ForthError(-15, "Below fence")
        if n < 0 and h < self.last + 4:
            # Giving back data space may not eat the newest header: the next
            # definition would overwrite its link and cut the dictionary.
            raise ForthError(-9, "ALLOT into a header")
        self.here = h

    def comma(self, v):
        h = self.here
        self.allot(2)
        self.memory.store(h, v & MASK)

    def ccomma(self, c):
        h = self.here
        self.allot(1)
        self.memory.cstore(h, c)

    # ---------------------------------------------------------- headers
    def create(self, name, cf, wid=None):
        """Lay down a header for name with code field cf; -> xt."""
        m, mem = self.m, self.memory
        raw = name.upper()[:NAME_MAX].encode("latin-1", "replace")
        if wid is None:
            wid = mem.fetch(m.a_current)
        if self.m.warning_on() and raw and self.find_in(wid, raw.decode("latin-1")):
            m.type("%s isn't unique " % raw.decode("latin-1"))
        start = self.here
        self.allot(len(raw) + 5)
        lfa = start + len(raw) + 1
        mem.mem[start:start + len(raw)] = raw
        mem.mem[lfa - 1] = 0x80 | len(raw)
        head = mem.fetch(wid)
        mem.store(lfa, head)
        mem.store(lfa + 2, cf)
        for a in range(start, lfa + 2):
            mem.watch[a] |= WATCH_HEADER
        mem.store(wid, lfa)
        mem.store(m.a_last, lfa)
        self._cache_add(wid, head, lfa, raw.decode("latin-1"))
        return lfa + 2

    def name_of(self, xt):
        """The name of the word whose code field is at xt, or None."""
        mem = self.memory.mem
        lfa = (xt - 2) & MASK
        count = mem[(lfa - 1) & MASK]
        n = count & 0x1F
        if not count & 0x80 or lfa - 1 - n < 0 or xt < PRIM_LIMIT:
            return None
        name = bytes(mem[lfa - 1 - n:lfa - 1]).decode("latin-1")
        return name if name.isprintable() else None

    def flags(self, lfa):
        return self.memory.mem[(lfa - 1) & MASK]

    def set_flag(self, lfa, bit, on=True):
        mem = self.memory.mem
        a = (lfa - 1) & MASK
        mem[a] = (mem[a] | bit) if on else (mem[a] & ~bit)

    @property
    def last(self):
        return self.memory.fetch(self.m.a_last)

    def set_does(self, addr):
        """( -- ) point the newest word's code field at the code after DOES>."""
        self.memory.store((self.last + 2) & MASK, addr)

    # ----------------------------------------------------------- lookup
    def lfas(self, wid):
        """The word list's headers, newest first."""
        fetch, lfa, seen = self.memory.fetch, self.memory.fetch(wid), 0
        while lfa and seen < 20000:
            yield lfa
            lfa = fetch(lfa)
            seen += 1

    def _table(self, wid):
        head = self.memory.fetch(wid)
        c = self.cache.get(wid)
        if c is None or c[0] != head or c[1] != self.generation:
            table = {}
            self.rebuilds += 1
            for lfa in self.lfas(wid):
                name = self.name_of((lfa + 2) & MASK)
                if name is not None:
                    table.setdefault(name, []).append(lfa)
            c = (head, self.generation, table)
            self.cache[wid] = c
        return c[2]

    def _cache_add(self, wid, old_head, lfa, name):
        c = self.cache.get(wid)
        if c is not None and c[0] == old_head and c[1] == self.generation:
            c[2].setdefault(name, []).insert(0, lfa)
            self.cache[wid] = (lfa, c[1], c[2])

    def _cache_forget(self, wid, old_head, new_head, gone):
        """The headers gone (newest first) left wid's list: its cached
        table loses them rather than being built again."""
        c = self.cache.get(wid)
        if c is None or c[0] != old_head or c[1] != self.generation:
            return
        table = c[2]
        for lfa in gone:
            name = self.name_of((lfa + 2) & MASK)
            lfas = table.get(name)
            if lfas and lfa in lfas:
                lfas.remove(lfa)
                if not lfas:
                    del table[name]
        self.cache[wid] = (new_head, c[1], table)

    def find_in(self, wid, name):
        """The newest visible lfa named name in wid, or 0."""
        mem = self.memory.mem
        for lfa in self._table(wid).get(name.upper()[:NAME_MAX], ()):
            if not mem[(lfa - 1) & MASK] & HIDDEN:
                return lfa
        return 0

    def find(self, name):
        """(xt, immediate) for name in the search order, or None."""
        for wid in self.order():
            lfa = self.find_in(wid, name)
            if lfa:
                return (lfa + 2) & MASK, bool(self.flags(lfa) & IMMEDIATE)
        return None

    def header_stored(self, addr):
        """A store hit a header: every cached table must be rebuilt."""
        self.generation += 1

    # ----------------------------------------------------- search order
    def order(self):
        fetch, a = self.memory.fetch, self.m.a_context
        n = min(fetch(self.m.a_norder), ORDER_MAX)
        return [fetch(a + 2 * i) for i in range(n)]

    def check_wid(self, wid):
        """A word list id must name a word list: anything else would have the
        next definition store its link at a random address."""
        if wid not in self.wordlists():
            raise ForthError(-32, "Not a word list")
        return wid

    def set_order(self, wids):
        if len(wids) > ORDER_MAX:
            raise ForthError(-49, "Search order overflow")
        for w in wids:
            self.check_wid(w)
        store, a = self.memory.store, self.m.a_context
        for i, w in enumerate(wids):
            store(a + 2 * i, w)
        store(self.m.a_norder, len(wids))

    def set_context_top(self, wid):
        order = self.order() or [wid]
        order[0] = wid
        self.set_order(order)

    # ------------------------------------------------------ forgetting
    def forget_to(self, addr):
        """Remove every word at or above addr from every word list."""
        m, mem = self.m, self.memory
        if addr < mem.fetch(m.a_fence):
            raise ForthError(-15, "Below fence")
        old_here = self.here
        voc = mem.fetch(m.a_voclink)
        while voc and voc >= addr:             # vocabularies defined later go
            voc = mem.fetch(voc)
        mem.store(m.a_voclink, voc)
        wids = self.wordlists()
        for wid in wids:
            head = lfa = mem.fetch(wid)
            gone = []
            while lfa >= addr:
                gone.append(lfa)
                lfa = mem.fetch(lfa)
            mem.store(wid, lfa)
            self._cache_forget(wid, head, lfa, gone)
        alive = set(wids)
        for wid in [w for w in self.cache if w not in alive]:
            del self.cache[wid]
        order = [w for w in self.order() if w in alive] or [m.forth_wid]
        self.set_order(order)
        if mem.fetch(m.a_current) not in alive:
            mem.store(m.a_current, m.forth_wid)
        lfa = max((mem.fetch(w) for w in wids), default=0)
        mem.store(m.a_last, lfa)
        self.here = addr
        # The forgotten headers are gone: their bytes become plain data space
        # again, so new definitions stored there do not flush the name cache.
        end = DICT_LIMIT
        mem.watch[addr:end] = mem.watch[addr:end].translate(CLEAR_HEADER)
        m.invalidate(addr, max(old_here, addr))     # only the code resting on what went

    def wordlists(self):
        """Every word list: the vocabularies on VOC-LINK (wid = link + 2... see
        `vocabulary`) and the root list."""
        fetch, out, voc, n = self.memory.fetch, [], self.memory.fetch(self.m.a_voclink), 0
        while voc and n < 1000:
            out.append((voc - 2) & MASK)
            voc = fetch(voc)
            n += 1
        return out

    def header_start(self, xt):
        lfa = (xt - 2) & MASK
        return lfa - 1 - (self.memory.mem[(lfa - 1) & MASK] & 0x1F)

    def restore_marker(self, body):
        """A MARKER's body holds HERE before its own header: forget back to it
        (word lists, search order and CURRENT are pruned as FORGET does)."""
        self.forget_to(self.memory.fetch(body))

    def new_wordlist(self):
        """Allot a word list (head cell + VOC-LINK cell); -> wid."""
        m, mem = self.m, self.memory
        wid = self.here
        self.comma(0)
        self.comma(mem.fetch(m.a_voclink))
        mem.store(m.a_voclink, wid + 2)
        return wid
