"""Intel 8253 programmable interval timer: three 16-bit down counters.

The control word, written to offset 3 (write-only; a read there gives 0xFF):

      7     6     5     4     3    2    1     0
    +-----+-----+-----+-----+----+----+----+-----+
    | SC1 | SC0 | RW1 | RW0 | M2 | M1 | M0 | BCD |
    +-----+-----+-----+-----+----+----+----+-----+
      counter     access      mode         count
      00 = 0      00 latch    000..101     0 = binary 0..65535
      01 = 1      01 LSB      = 0..5       1 = BCD 0..9999
      10 = 2      10 MSB      110 = 2
      11 ignored  11 LSB,MSB  111 = 3

    e.g. 0x36 = 00 11 011 0: counter 0, LSB then MSB, mode 3, binary
         0x74 = 01 11 010 0: counter 1, LSB then MSB, mode 2, binary
         0x40 = 01 00 ...  : counter 1 latch

Offsets 0, 1, 2 are the counters.  Each one:

    write --> CR (count register) --> CE (counting element, CLK steps it)
    read  <-- OL (output latch: follows CE, or frozen by a latch command)

Datasheet facts modelled (Intel's 8253 data sheet):

- control word decoding; SC=11 (the 8254's read-back) is ignored; M=110 and
  111 are modes 2 and 3; a control word resets both byte flip-flops, sets
  OUT (low in mode 0, high in modes 1-5) and leaves the counter waiting for
  a count (n is None again);
- RW=01 and RW=10 single-byte counts (the other byte 0), RW=11 LSB then MSB
  with separate read and write byte flip-flops; a count acts only when
  complete; count 0 means 65536 (binary) or 10000 (BCD); BCD counting;
- the counter latch command freezes OL until it is fully read, counting
  goes on, and a second latch before then is ignored;
- the six modes with GATE (Counter.set_gate): 0 interrupt on terminal count
  (GATE low pauses), 1 retriggerable one-shot, 2 rate generator (OUT low
  for the one CLK when CE is 1; GATE low stops it and forces OUT high, a
  rising edge reloads), 3 square wave (high (N+1)//2, low N//2; CE steps by
  2 per CLK from N rounded down to even), 4 software strobe, 5 hardware
  strobe; modes 0, 1, 4 and 5 keep wrapping after terminal count;
- rewriting a running count: mode 0's first byte stops counting and the
  last byte starts the new count; modes 2 and 3 take it at the next reload
  (mode 3: end of the current half-cycle); modes 1 and 5 at the next
  trigger; mode 4 restarts at once.

Time is lazy: Counter.clock(n) applies n CLK pulses at once, in O(1)
arithmetic, so the board can hand over thousands of pulses per access.

NOTES (not modelled):

- the one-CLK delay between a count completing and CE loading (2.3): the
  count loads at once, so mode 0 OUT goes high N clocks after the write
  (not N+1) and mode 1 OUT goes low at the trigger itself;
- tearing of plain two-byte reads: OL samples CE at the LSB read and the
  MSB comes from the same sample (the simulator rule of 2.4);
- interleaving reads and writes inside a two-byte sequence beyond what the
  independent flip-flops do; likewise a latch between the two bytes of a
  plain read freezes OL there and the MSB comes from the new latch;
- illegal counts: N = 1 in mode 2 holds OUT low, in mode 3 holds it high;
  non-BCD nibbles of a BCD count are weighed by place value, mod 10000;
- the state before the first control word: count writes are ignored, reads
  give CE (0), OUT is high;
- electrical timing: CLK rate limits, GATE sampling on CLK edges.
"""

HIGH = 1
LOW = 0


class Counter:
    """One counter: CR, CE, OL, the two byte flip-flops, GATE in, OUT out.

    Board-facing: n (last complete count 1..65536, None before one),
    mode, out, gate, frequency(f_clk), clock(n), set_gate(level),
    value (the live CE as a number; BCD mode gives the decimal count), and
    latched (OL frozen by a latch command until fully read: a read then
    does not depend on the CLKs since the latch).
    """

    RW_LATCH = 0b00
    RW_LSB = 0b01
    RW_MSB = 0b10
    RW_BOTH = 0b11
    BYTE_MASK = 0xFF
    NIBBLE_MASK = 0xF
    BINARY_MODULUS = 0x10000
    BCD_MODULUS = 10000
    MODE_ALIASES = {6: 2, 7: 3}       # M2 is "don't care" for 11x
    GATE_LEVEL_MODES = (0, 2, 3, 4)   # GATE low pauses counting
    TRIGGER_MODES = (1, 5)            # GATE rising edge (re)starts the count
    RELOAD_MODES = (2, 3)             # free-running periods; GATE edge reloads
    LOW_UNTIL_TERMINAL = (0, 1)       # OUT low while counting down, then high

    def __init__(self):
        self.mode = None
        self.bcd = False
        self.rw = self.RW_BOTH
        self.n = None
        self.gate = HIGH
        self.out = HIGH
        self.running = False
        self._ce = 0             # CE; in mode 2 kept as 1..N (N = 65536 too)
        self._period = None      # N of the running mode 3 cycle
        self._half_pos = 0       # mode 3: CLKs into the current half-cycle
        self._fired = False      # modes 0, 1, 4, 5: terminal count reached
        self._holding = False    # mode 0: new count's LSB written, MSB not
        self._lsb = 0
        self._write_lsb_next = True
        self._read_lsb_next = True
        self._ol = 0
        self.latched = False

    def __repr__(self):
        return "<Counter mode=%s n=%s value=%d out=%d>" % (
            self.mode, self.n, self.value, self.out)

    # ------------------------------------------------------------------
    # NUMBERS: modulus, CE value, BCD coding
    # ------------------------------------------------------------------

    @property
    def modulus(self):
        """The count that 0 stands for, and the CE's wrap-around."""
        return self.BCD_MODULUS if self.bcd else self.BINARY_MODULUS

    @property
    def value(self):
        """The live CE as a number 0..modulus-1."""
        if self.mode == 3 and self.running:
            # mode 3 loads N rounded down to even, then steps by 2 per CLK
            top = self._period & ~1
            return (top - 2 * self._half_pos) % self.modulus
        return self._ce % self.modulus

    def _encoded(self):
        """CE as the 16-bit word on the bus (four BCD digits in BCD mode)."""
        if self.bcd:
            return int("%04d" % self.value, 16)
        if self.mode == 3 and self.running:
            return self.value
        return self._ce & 0xFFFF            # the binary modulus, 0x10000

    def _decoded(self, word):
        """A written 16-bit count as a number (BCD digits by place value)."""
        if not self.bcd:
            return word
        digits = [(word >> shift) & self.NIBBLE_MASK for shift in (12, 8, 4, 0)]
        number = 0
        for digit in digits:
            number = number * 10 + digit
        return number % self.BCD_MODULUS

    # ------------------------------------------------------------------
    # CONTROL WORD: program and latch
    # ------------------------------------------------------------------

    def program(self, rw, mode, bcd):
        """A control word with RW != 00 for this counter."""
        self._ce = self.value
        self.rw = rw
        self.mode = self.MODE_ALIASES.get(mode, mode)
        self.bcd = bool(bcd)
        self._write_lsb_next = self._read_lsb_next = True
        self.latched = self._holding = self.running = False
        self.out = LOW if self.mode == 0 else HIGH
        self.n = None

    def latch(self):
        """Counter latch command: freeze OL unless already frozen."""
        if not self.latched:
            self._ol = self._encoded()
            self.latched = True

    # ------------------------------------------------------------------
    # BUS: count writes and reads, one byte at a time
    # ------------------------------------------------------------------

    def write(self, byte):
        """A byte written to this counter's address (2.3); -> True if it
        completed a count (only then may n, and so OUT's frequency, change)."""
        if self.mode is None:
            return False
        byte &= self.BYTE_MASK
        rw = self.rw
        if rw == self.RW_LSB:
            self._complete(byte)
        elif rw == self.RW_MSB:
            self._complete(byte << 8)
        elif self._write_lsb_next:
            self._lsb = byte
            self._write_lsb_next = False
            self._holding = self.mode == 0
            return False
        else:
            self._write_lsb_next = True
            self._complete(self._lsb | byte << 8)
        return True

    def write_acts(self, byte):
        """Would `byte` written now act on the counting at once? Not the
        first byte of a two-byte count outside mode 0 (it is only kept
        until the second comes), nor a byte that completes the very count
        a running mode 2 or 3 counter already reloads from (the control
        word's speed writes every tick): such a write changes nothing
        CLK or OUT's frequency depends on, so the board need not bring
        CLK up for it, nor look at the frequency again."""
        rw = self.rw
        if rw == self.RW_BOTH:
            if self._write_lsb_next:
                return self.mode == 0
            word = self._lsb | (byte & self.BYTE_MASK) << 8
        else:
            word = (byte & self.BYTE_MASK) << (8 if rw == self.RW_MSB else 0)
        return not (self.running and self.mode in self.RELOAD_MODES
                    and (self._decoded(word) or self.modulus) == self.n)

    def read(self):
        """A byte read from this counter's address (2.4)."""
        rw, lsb_next = self.rw, self._read_lsb_next
        if lsb_next and not self.latched:
            self._ol = self._encoded()      # OL follows CE: sample per read
        if rw == RW_BOTH:                   # LSB, then MSB
            byte = self._ol & 0xFF if lsb_next else self._ol >> 8
            lsb_next = self._read_lsb_next = not lsb_next
        else:
            byte = self._ol >> 8 if rw == RW_MSB else self._ol & 0xFF
        if lsb_next:
            self.latched = False           # fully read: OL follows CE again
        return byte

    def _complete(self, word):
        """A whole count has been written: act on it as the mode says."""
        self.n = self._decoded(word) or self.modulus
        self._holding = False
        if self.mode in (0, 4):
            self._start_countdown()
        elif self.mode in self.RELOAD_MODES and not self.running:
            self._start_period()
        # modes 1 and 5 wait for a trigger; running modes 2 and 3 pick
        # self.n up at their next reload

    # ------------------------------------------------------------------
    # GATE
    # ------------------------------------------------------------------

    def set_gate(self, level):
        """Drive the GATE input high (truthy) or low."""
        level = HIGH if level else LOW
        rising = level == HIGH and self.gate == LOW
        self.gate = level
        if self.mode in self.RELOAD_MODES:
            if level == LOW:
                self.out = HIGH
            elif rising and self.running:
                self._start_period()
        elif rising and self.mode in self.TRIGGER_MODES and self.n is not None:
            self._start_countdown()

    # ------------------------------------------------------------------
    # CLK: n pulses at once, O(1)
    # ------------------------------------------------------------------

    def clock(self, n):
        """Apply n CLK pulses."""
        if n <= 0 or not self.running or self._holding:
            return
        if self.gate == LOW and self.mode in self.GATE_LEVEL_MODES:
            return
        if self.mode == 2:
            self._advance_rate(n)
        elif self.mode == 3:
            self._advance_square(n)
        else:
            self._advance_countdown(n)

    def frequency(self, f_clk):
        """OUT's frequency for a CLK of f_clk Hz: f_clk/N in a counting
        mode 2 or 3, else 0.0.  Uses the last complete count (2.7)."""
        if self.mode in self.RELOAD_MODES and self.running and self.gate:
            return f_clk / self.n
        return 0.0

    # --- modes 0, 1, 4, 5: count down once, then keep wrapping ---------

    def _start_countdown(self):
        self._ce = self.n % self.modulus
        self._fired = False
        self.running = True
        self.out = LOW if self.mode in self.LOW_UNTIL_TERMINAL else HIGH

    def _advance_countdown(self, n):
        to_terminal = self._ce or self.modulus
        if not self._fired and n >= to_terminal:
            self._fired = True
            self.out = self._terminal_out(n - to_terminal)
        elif self._fired:
            self.out = HIGH         # a mode 4/5 strobe lasts one CLK
        self._ce = (self._ce - n) % self.modulus

    def _terminal_out(self, clocks_after):
        """OUT `clocks_after` CLKs past terminal count."""
        if self.mode in self.LOW_UNTIL_TERMINAL:
            return HIGH
        return LOW if clocks_after == 0 else HIGH

    # --- modes 2 and 3: periods of N, reloading from self.n ------------

    def _start_period(self):
        self._period = self.n
        self._ce = self.n
        self._half_pos = 0
        self.running = True
        self.out = LOW if self.mode == 2 and self._ce == 1 else HIGH

    def _advance_rate(self, n):
        # CE runs N..1 (OUT low at 1), and the pulse after 1 reloads
        if n >= self._ce:
            n -= self._ce
            self._ce = self.n - n % self.n
        else:
            self._ce -= n
        self.out = LOW if self._ce == 1 else HIGH

    def _half_length(self):
        """CLKs in the current half-cycle: odd N makes the high half longer."""
        if self.out == HIGH:
            return (self._period + 1) // 2
        return self._period // 2

    def _advance_square(self, n):
        rest = self._half_length() - self._half_pos
        if n < rest:
            self._half_pos += n
            return
        self._period = self.n       # a rewritten count starts here
        self._flip_half()
        n = (n - rest) % self._period
        first = self._half_length()
        if n >= first:
            self._flip_half()
            n -= first
        self._half_pos = n

    def _flip_half(self):
        self.out = LOW if self.out == HIGH else HIGH
        self._half_pos = 0


class I8253:
    """The chip: three counters and the control word register.

    read(offset) and write(offset, byte) take offsets from the chip's base
    port; only A1 A0 reach the chip, so the offset is taken mod 4.

    What a board wires to it, bound once (its port map and its clocks call
    these on every tick, so no per-access dispatch on the offset):
      clk(i) -> pulse(n)            counter i's CLK input: n pulses at once
      port(i) -> (write, read, acts)  counter i's address: write(byte) ->
                                    True if it completed a count; read() ->
                                    a byte of the count as read back;
                                    acts(byte): would that write act on the
                                    counting now (Counter.write_acts), so
                                    that CLK must be brought up first
      write_control(byte)           the control word (offset 3)
      out_frequency(i, f_clk)       OUT's frequency for a CLK of f_clk Hz
    """

    OFFSET_MASK = 0b11
    CONTROL = 3
    SC_SHIFT = 6
    RW_SHIFT = 4
    M_SHIFT = 1
    SC_MASK = 0b11
    RW_MASK = 0b11
    M_MASK = 0b111
    BCD_MASK = 0b1
    SC_ILLEGAL = 0b11
    CONTROL_READ = 0xFF

    def __init__(self):
        self.counters = (Counter(), Counter(), Counter())

    def read(self, offset):
        offset &= self.OFFSET_MASK
        if offset == self.CONTROL:
            return self.CONTROL_READ
        return self.counters[offset].read()

    def write(self, offset, byte):
        """-> True if a count was completed (see Counter.write)."""
        offset &= self.OFFSET_MASK
        if offset == self.CONTROL:
            self.write_control(byte)
            return False
        return self.counters[offset].write(byte)

    def clk(self, i):
        """Counter i's CLK input: a function taking n pulses."""
        return self.counters[i].clock

    def port(self, i):
        """Counter i's address: (write(byte), read(), acts(byte))."""
        counter = self.counters[i]
        return counter.write, counter.read, counter.write_acts

    def out_frequency(self, i, f_clk):
        """Counter i's OUT frequency for a CLK of f_clk Hz (0.0 if it
        does not run in mode 2 or 3)."""
        return self.counters[i].frequency(f_clk)

    @classmethod
    def decode(cls, byte):
        """A control byte as (sc, rw, m, bcd), fields as written."""
        return ((byte >> cls.SC_SHIFT) & cls.SC_MASK,
                (byte >> cls.RW_SHIFT) & cls.RW_MASK,
                (byte >> cls.M_SHIFT) & cls.M_MASK,
                byte & cls.BCD_MASK)

    def write_control(self, byte):
        sc = byte >> SC_SHIFT       # (the fields one at a time: four latches a tick)
        if sc == SC_ILLEGAL:
            return                  # the 8254's read-back; an 8253 ignores it
        if not byte & RW_FIELD:     # RW 00: the counter latch command
            self.counters[sc].latch()
        else:
            self.counters[sc].program(*self.decode(byte)[1:])


# The fields the hot paths test, as module names (a global is looked up
# faster than a class attribute through self).
RW_BOTH, RW_MSB = Counter.RW_BOTH, Counter.RW_MSB
SC_SHIFT, SC_ILLEGAL = I8253.SC_SHIFT, I8253.SC_ILLEGAL
RW_FIELD = I8253.RW_MASK << I8253.RW_SHIFT
