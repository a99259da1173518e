"""The outer interpreter: where input comes from, and what is done with it.

Input sources nest (a terminal line, INCLUDE'd file lines, EVALUATE'd
strings, blocks). Each lives in memory, so SOURCE, >IN, WORD and friends
work on real addresses:

    terminal line / file line: a line buffer in the input area
    EVALUATE:                  the string where it already is
    block n:                   the block buffer (BLK = n)

The loop for one source (F83's INTERPRET):

    token := next blank-delimited name from SOURCE at >IN
    found?   compiling and not immediate -> compile it, else execute it
    number?  compiling -> compile a literal, else push it (DPL set)
    else     abort with the token and ` ?`

An error anywhere raises ForthError; `abort` then empties both stacks,
leaves compile state and drops every nested source, as F83's ABORT does.
"""
import re
from dataclasses import dataclass

from rcl.errors import Bye, ForthError
from rcl.forth.memory import INPUT_AREA, MASK, SIZE
from rcl.forth.numbers import convert

TOKEN = re.compile(rb"[\x00-\x20]*([^\x00-\x20]*)")   # blanks are 32 and below (F83)
ON_ABORT_LIMIT = 36_000_000 * 1000     # virtual time the ON-ABORT hook may take (1 s)


@dataclass
class Source:
    kind: str                 # "terminal", "file", "evaluate", "block"
    addr: int = 0
    length: int = 0
    buf: int = 0              # start of this source's line buffer
    lines: object = None      # iterator of further lines (terminal)
    text: list = None         # every line of a file (so RESTORE-INPUT can go back)
    name: str = None          # file name
    line: int = 0             # current line number in the file
    source_id: int = 0        # 0 terminal, -1 evaluate, >0 file
    saved: tuple = ()         # the enclosing source's >IN and BLK


class Outer:
    """The outer-interpreter half of the machine (mixed into Forth)."""

    def _init_outer(self):
        self.sources = [Source("terminal", INPUT_AREA, 0, INPUT_AREA, iter(()))]
        self.file_ids = 0
        self.locals = None        # the Locals word set's scope while compiling

    # ----------------------------------------------------------- sources
    @property
    def src(self):
        return self.sources[-1]

    def source(self):
        """( -- addr len ) of the current input."""
        blk = self.memory.fetch(self.a_blk)
        if blk:
            return self.blocks.block(blk), 1024
        return self.src.addr, self.src.length

    def buffer_top(self):
        """Where a new nested line buffer may start."""
        for s in reversed(self.sources):
            if s.kind in ("terminal", "file"):
                return s.buf + max(s.length, 0)
        return INPUT_AREA

    def set_line(self, src, text):
        """Put one line of text into src's line buffer and rewind >IN."""
        try:
            data = text.encode("latin-1")
        except UnicodeEncodeError as e:      # F83's characters are bytes
            raise ForthError(-13, "Not a Latin-1 character: %r" % text[e.start]) from None
        if src.buf + len(data) > SIZE:
            raise ForthError(-262, "Line too long")
        self.memory.mem[src.buf:src.buf + len(data)] = data
        src.addr, src.length = src.buf, len(data)
        self.memory.store(self.a_in, 0)

    def refill(self):
        """Next line of the current source; False at its end (REFILL)."""
        src = self.src
        if src.kind not in ("terminal", "file") or self.memory.fetch(self.a_blk):
            return False
        if src.text is not None:
            if src.line >= len(src.text):
                return False
            text = src.text[src.line]
        else:
            text = next(src.lines, None)
            if text is None:
                return False
        src.line += 1
        self.locations.mark(self.dictionary.here, src.name, src.line)
        self.set_line(src, text)
        return True

    def push_source(self, src):
        if len(self.sources) > 64:
            raise ForthError(-262, "Too many nested loads")
        fetch = self.memory.fetch
        src.saved = (fetch(self.a_in), fetch(self.a_blk))
        self.sources.append(src)
        self.memory.store(self.a_in, 0)
        self.memory.store(self.a_blk, 0)

    def pop_source(self):
        src = self.sources.pop()
        self.memory.store(self.a_in, src.saved[0])
        self.memory.store(self.a_blk, src.saved[1])
        if src.kind == "file" and hasattr(src.lines, "close"):
            src.lines.close()

    # ----------------------------------------------------------- parsing
    def parse_name(self):
        """Skip blanks, take a blank-delimited token; '' at the end."""
        addr, length = self.source()
        mem, i = self.memory.mem, self.memory.fetch(self.a_in)
        start = i                                    # (>IN at or past the end: '' there)
        if i < length:                               # one regex search, not a loop a byte
            buf, base = mem, addr
            if addr + length > SIZE:                 # the buffer wraps round: unroll it
                buf, base = mem[addr:] + mem[:addr + length - SIZE], 0
            token = TOKEN.match(buf, base + i, base + length)
            start, i = token.start(1) - base, token.end(1) - base
        self.memory.store(self.a_in, min(i + 1, length) if i < length else i)
        return self.memory.text((addr + start) & MASK, i - start), (addr + start) & MASK

    def parse(self, delim):
        """Text up to delim (not skipping leading blanks); -> (addr, len)."""
        addr, length = self.source()
        mem, i = self.memory.mem, self.memory.fetch(self.a_in)
        start = i
        while i < length and mem[(addr + i) & MASK] != delim:
            i += 1
        self.memory.store(self.a_in, i + 1 if i < length else i)
        return (addr + start) & MASK, i - start

    def parse_multiline(self, delim):
        """Skip up to delim, refilling from a file when the line ends (the
        File word set's `(`). Returns when found or the source is dry."""
        while True:
            addr, length = self.source()
            i = self.memory.fetch(self.a_in)
            self.parse(delim)
            found = self.memory.text((addr + i) & MASK, length - i).find(chr(delim)) >= 0
            if found or self.src.kind != "file" or not self.refill():
                return

    # -------------------------------------------------------- interpreting
    @property
    def compiling(self):
        return self.memory.fetch(self.a_state) != 0

    def interpret(self):
        """Interpret the current source to its end (or its REFILL's end)."""
        find, fetch = self.dictionary.find, self.memory.fetch
        while True:
            name, _ = self.parse_name()
            if not name:
                return
            if len(self.s) > 1000:
                del self.s[:]
                raise ForthError(-3)
            if self.locals is not None and fetch(self.a_state) \
                    and self.locals.compile(self, name):
                continue                  # a local's name shadows every word
            hit = find(name)
            if hit is not None:
                xt, immediate = hit
                if fetch(self.a_state) and not immediate:
                    self.dictionary.comma(xt)
                else:
                    self.execute(xt)
            else:
                self.number(name)

    def number(self, name):
        n = convert(name, self.memory.fetch(self.a_base))
        if n is None or not n.ok:
            if n is not None:
                self.memory.store(self.a_dpl, n.dpl & MASK)
            raise ForthError(-13, "?", name.upper())
        self.memory.store(self.a_dpl, n.dpl & MASK)
        self.memory.store(self.a_wide, MASK if n.wide else 0)
        lo, hi = n.value & MASK, n.value >> 16
        if self.compiling:
            self.compile_number(lo, hi, n.dpl, n.wide)
        elif n.double:
            self.s.extend((lo, hi))
        else:
            self.s.append(lo)

    def compile_number(self, lo, hi, dpl, wide=False):
        d, xt = self.dictionary, self.xt_of
        if self.memory.fetch(self.a_rcllit):
            if dpl < 0:
                d.comma(xt["(RWLIT)" if wide else "(RLIT)"])
                d.comma(lo)
            else:
                d.comma(xt["(RDLIT)"])
                d.comma(lo)
                d.comma(hi)
                d.comma(dpl)
        else:
            d.comma(xt["LIT"])
            d.comma(lo)
            if dpl >= 0:
                d.comma(xt["LIT"])
                d.comma(hi)

    # ------------------------------------------------------- entry points
    def interpret_line(self, text):
        """Interpret one line typed at the terminal."""
        src = self.sources[0]
        self.set_line(src, text)
        self.memory.store(self.a_blk, 0)
        self.interpret()

    def evaluate_string(self, addr, length):
        """EVALUATE: interpret the string at addr as a nested source."""
        self.push_source(Source("evaluate", addr, length, source_id=-1))
        try:
            self.interpret()
        finally:
            if self.sources and self.sources[-1].kind == "evaluate":
                self.pop_source()

    def include_lines(self, lines, name, source_id=None):
        """Interpret an iterator of lines as a file source named name
        (SOURCE-ID: source_id, the file id INCLUDE-FILE was given, or a new one)."""
        self.file_ids += 1
        src = Source("file", buf=self.buffer_top(), text=list(lines), name=name,
                     source_id=source_id or self.file_ids)
        self.push_source(src)
        try:
            while self.refill():
                self.interpret()
        except (Exception, KeyboardInterrupt) as exc:
            if isinstance(exc, Bye):
                raise
            e = self.traced(exc)
            if e.file is None:
                e.file, e.line = name, src.line
            raise e from None
        finally:
            if self.sources and self.sources[-1] is src:
                self.pop_source()

    def quit(self):
        """QUIT: empty the return stack, interpret from the terminal."""
        del self.rs[:]
        stack = list(self.s)
        self.abort()
        self.s.extend(stack)

    def abort(self):
        """F83's ABORT: empty both stacks, stop compiling, drop all loads."""
        del self.s[:]
        del self.rs[:]
        self.memory.store(self.a_state, 0)
        self.locals = None
        while len(self.sources) > 1:
            self.pop_source()
        self.memory.store(self.a_blk, 0)
        self.masked = False
        self.reschedule()
        self.safe_state()

    def safe_state(self):
        """After any error or Ctrl-C: the board's motors off, then the word
        in the kernel's SAFE-STATE (RCL's: clear its relay shadow and move
        state), then the kernel's DEFER ON-ABORT (the user's hook), then the
        motors off again, whatever the hooks did."""
        self.board.stop_motors()
        self.break_pending = bool(self.leave_signal)   # Ctrl-C is answered; a quit is not
        self.stop_error = None
        system = self.memory.fetch((self.xt_of["SAFE-STATE"] + 2) & MASK)
        self.in_safe_state = True
        try:
            for xt in ([system] if system else []) + [self.xt_of["ON-ABORT"]]:
                self.run_hook(xt)
        finally:
            self.in_safe_state = False
        self.board.stop_motors()

    def run_hook(self, xt):
        """Run an abort hook with a second of virtual time; a broken hook
        must not hide the error being reported."""
        limit = self.clock_limit
        self.clock_limit = min(limit, self.clock + ON_ABORT_LIMIT)
        try:
            self.execute(xt)
        except Exception:
            pass
        finally:
            self.clock_limit = limit
            self.masked = False
            del self.s[:]
            del self.rs[:]
            self.reschedule()

    def shutdown(self):
        """Leaving (BYE, end of input, a signal): the robot in its safe state."""
        self.abort()
