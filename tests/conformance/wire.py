"""The board protocol's bytes, written from docs/protocol.md alone (no rcl
import): the CRC, a frame, the receiver of section 1, and a session that
speaks to a board over its pseudo-terminal as a host would.

    s = Session(path)               # the board's pty, raw
    ident = s.hello()               # -> IDENTIFY's fields
    s.request(OUT8, u16(0x88) + b"\\x0f")  -> the answer frame
    s.send(raw_bytes)               # anything at all, for the bad cases
    s.frames                        # every board frame received, in order
"""
import os
import select
import struct
import time
import tty

SYNC = 0xA5
MAX_PAYLOAD = 64

# section 4's table: host types, then board types
HELLO, OUT8, OUT16, IN8, IN16, FAR_STORE, FAR_FETCH, SNAPSHOT = range(1, 9)
TICK_DONE, SAFE, TICK_FAILED, PING, NAK, RUN, WAIT, CLOCK = range(9, 17)
IDENTIFY, ACK, VALUE, TICK, HEARTBEAT, REFUSED, RESULTS = range(0x81, 0x88)
BOARD_TYPES = set(range(0x81, 0x88))
ANSWERS = {ACK, VALUE, REFUSED, RESULTS}

LOCKSTEP = 0x01                 # IDENTIFY flags bit 0
# How long a wait for an answer may last before the board is taken for
# broken: a bound, never a measure, generous for a busy machine (a board
# process starved of CPU answers late, not wrongly).
BOUND = 10.0


def crc16(data):
    """CRC-16/CCITT-FALSE, as the document's C."""
    crc = 0xFFFF
    for byte in data:
        crc ^= byte << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else crc << 1
        crc &= 0xFFFF
    return crc


def frame(seq, type_, payload=b""):
    body = bytes((len(payload), seq & 0xFF, type_)) + bytes(payload)
    crc = crc16(body)
    return bytes((SYNC,)) + body + bytes((crc >> 8, crc & 0xFF))


def u16(v):
    return struct.pack("<H", v & 0xFFFF)


def u32(v):
    return struct.pack("<I", v & 0xFFFFFFFF)


def ops(records):
    """SNAPSHOT / RUN records (op, port, value) as *BHB."""
    return b"".join(struct.pack("<BHB", *r) for r in records)


class Frame:
    def __init__(self, seq, type_, payload, raw, at):
        self.seq, self.type, self.payload, self.raw, self.at = seq, type_, payload, raw, at

    @property
    def ack(self):
        return self.payload[0]

    @property
    def value(self):                # VALUE
        return struct.unpack_from("<H", self.payload, 1)[0]

    @property
    def reason(self):               # REFUSED
        return self.payload[1:].decode("latin-1")

    @property
    def results(self):              # RESULTS
        return list(self.payload[1:])

    def tick(self):                 # TICK -> (tick, off, results)
        tick, off = struct.unpack_from("<HH", self.payload)
        return tick, off, list(self.payload[4:])

    def heartbeat(self):            # HEARTBEAT -> (time_us, ticking)
        return struct.unpack("<IB", self.payload)

    def identify(self):
        version, tick_us, flags = struct.unpack_from("<BHB", self.payload)
        return {"version": version, "tick_us": tick_us, "flags": flags,
                "name": self.payload[4:].decode("latin-1")}

    def __repr__(self):
        return "Frame(seq=%d, type=0x%02X, %s)" % (self.seq, self.type, self.payload.hex())


class Receiver:
    """Section 1's receiver, for the host's end: known types are the
    board's; a bad frame loses only its SYNC."""

    def __init__(self):
        self.buf = bytearray()

    def feed(self, data, at):
        self.buf += data
        out = []
        while True:
            i = self.buf.find(SYNC)
            if i < 0:
                del self.buf[:]
                return out
            del self.buf[:i]
            if len(self.buf) < 2:
                return out
            n = self.buf[1]
            if n > MAX_PAYLOAD:
                del self.buf[:1]
                continue
            if len(self.buf) < n + 6:
                return out
            raw = bytes(self.buf[:n + 6])
            if raw[3] not in BOARD_TYPES or crc16(raw[1:n + 4]) != (raw[-2] << 8 | raw[-1]):
                del self.buf[:1]
                continue
            del self.buf[:n + 6]
            out.append(Frame(raw[2], raw[3], raw[4:4 + n], raw, at))


class Session:
    """A host's end of the line, raw: it sends what it is told and keeps
    every frame the board sends (`frames`), in order of arrival."""

    def __init__(self, path):
        self.fd = os.open(path, os.O_RDWR | os.O_NOCTTY | os.O_NONBLOCK)
        tty.setraw(self.fd)
        self.rx = Receiver()
        self.frames = []
        self.unread = []                # frames not yet taken by receive()
        self.raw = bytearray()
        self.seq = 1                    # the host's next SEQ
        self.lockstep = False
        self.host_us = 0                # the time CLOCK last told a lockstep board
        self.last_sent = time.monotonic()
        self.longest_silence = 0.0      # s between two of our writes, the longest (reset by rules)

    # ------------------------------------------------------------ bytes
    def send(self, data):
        view = memoryview(bytes(data))
        while view:
            try:
                n = os.write(self.fd, view)
            except BlockingIOError:
                select.select([], [self.fd], [], 0.05)
                continue
            view = view[n:]
        now = time.monotonic()
        self.longest_silence = max(self.longest_silence, now - self.last_sent)
        self.last_sent = now

    def poll(self, timeout):
        ready, _, _ = select.select([self.fd], [], [], timeout)
        if not ready:
            return
        try:
            data = os.read(self.fd, 4096)
        except (BlockingIOError, OSError):
            return
        self.raw += data
        got = self.rx.feed(data, time.monotonic())
        self.frames += got
        self.unread += got

    def receive(self, want=None, seconds=BOUND, keep_alive=True):
        """The next unread frame of a type in `want` (None: any); None
        after `seconds` (a bound for a broken board, not a measure).
        With keep_alive a PING goes out every 100 ms meanwhile."""
        end = time.monotonic() + seconds
        while True:
            while self.unread:
                f = self.unread.pop(0)
                if want is None or f.type in want:
                    return f
            if time.monotonic() >= end:
                return None
            if keep_alive and time.monotonic() - self.last_sent > 0.1:
                self.send(frame(0, PING))
            self.poll(0.01)

    def quiet(self, seconds, keep_alive=True, chatter=None):
        """Take what comes for `seconds` of wall time; -> those frames.
        Silent (no keep_alive), the host's own time passes as the wall
        clock's (for CLOCK after it: a lockstep board whose watchdog
        tripped lets its time run)."""
        start = len(self.frames)
        began = time.monotonic()
        end = began + seconds
        while time.monotonic() < end:
            self.keep(keep_alive, chatter)
            self.poll(min(0.01, max(0.0, end - time.monotonic())))
        if not keep_alive:
            self.host_us += int((time.monotonic() - began) * 1e6) // 10_000 * 10_000
        self.unread = []
        return self.frames[start:]

    def receive_raw(self, raw, seconds=BOUND):
        """The next frame that is `raw`, byte for byte (None: none came)."""
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            f = self.receive(None, end - time.monotonic())
            if f is not None and f.raw == raw:
                return f
        return None

    def drain(self):
        self.poll(0)
        while self.unread:
            self.unread = []
            self.poll(0.005)

    # ---------------------------------------------------------- session
    def hello(self, version=1):
        """HELLO until IDENTIFY; -> its fields. Sequences restart."""
        for _ in range(20):
            self.drain()
            self.send(frame(0, HELLO, bytes((version,))))
            f = self.receive({IDENTIFY}, 0.5)
            if f is not None:
                self.ident = f
                self.frames = self.frames[self.frames.index(f):]     # this session's
                fields = f.identify()
                self.lockstep = bool(fields["flags"] & LOCKSTEP)
                self.seq, self.host_us = 1, 0
                return fields
        raise AssertionError("no IDENTIFY to HELLO")

    def next_seq(self):
        seq, self.seq = self.seq, self.seq % 255 + 1
        return seq

    def request(self, type_, payload=b"", seq=None, seconds=BOUND):
        """One sequenced frame; -> its answer (ACK, VALUE, RESULTS or
        REFUSED carrying ack = SEQ), or None. TICKs and HEARTBEATs that
        come meanwhile stay unread for receive()."""
        if seq is None:
            seq = self.next_seq()
        self.send(frame(seq, type_, payload))
        end = time.monotonic() + seconds
        skipped = []
        try:
            while time.monotonic() < end:
                f = self.receive(None, end - time.monotonic())
                if f is None:
                    return None
                if f.type in ANSWERS and f.ack == seq:
                    return f
                if f.type not in ANSWERS:
                    skipped.append(f)
            return None
        finally:
            self.unread = skipped + self.unread

    def answers(self, seconds):
        """Answer frames (ACK, VALUE, RESULTS, REFUSED) in `seconds`."""
        return [f for f in self.quiet(seconds) if f.type in ANSWERS]

    # ------------------------------------------------- board operations
    def out8(self, port, value):
        return self.request(OUT8, u16(port) + bytes((value,)))

    def out16(self, port, value):
        return self.request(OUT16, u16(port) + u16(value))

    def in8(self, port):
        return self.request(IN8, u16(port)).value

    def in16(self, port):
        return self.request(IN16, u16(port)).value

    def store(self, seg, off, value):
        return self.request(FAR_STORE, u16(seg) + u16(off) + bytes((value,)))

    def fetch(self, seg, off):
        return self.request(FAR_FETCH, u16(seg) + u16(off)).value

    def store32(self, seg, off, value):
        for i in range(4):
            assert self.store(seg, off + i, (value >> 8 * i) & 0xFF).type == ACK

    def fetch32(self, seg, off):
        return sum(self.fetch(seg, off + i) << 8 * i for i in range(4))

    def run(self, records):
        return self.request(RUN, ops(records))

    def keep(self, keep_alive, chatter):
        """A PING every 100 ms (keep_alive), or `chatter` every 40 ms."""
        if chatter is not None and time.monotonic() - self.last_sent > 0.04:
            self.send(chatter)
        elif keep_alive and time.monotonic() - self.last_sent > 0.1:
            self.send(frame(0, PING))

    def advance(self, ms, keep_alive=True, chatter=None):
        """Let at least `ms` of board time pass. A lockstep board that does
        not tick keeps the host's time (CLOCK, section 4); any other board
        keeps its own, which its HEARTBEATs tell (a board slowed by a busy
        machine is waited for). Silent (no keep_alive: nothing, or only
        `chatter`), a lockstep board is waited for on the wall clock, as
        its watchdog counts."""
        if self.lockstep and (chatter is not None or not keep_alive):
            self.quiet(ms / 1000, keep_alive=False, chatter=chatter)
        elif self.lockstep:
            for _ in range(ms // 50):
                self.host_us += 50_000
                assert self.request(CLOCK, u32(self.host_us)).type == ACK
        else:
            self.board_time(ms, keep_alive, chatter)

    def board_time(self, ms, keep_alive=True, chatter=None):
        """Wait until the board's HEARTBEAT time has moved `ms` (the wall
        clock bounds it only for a broken board: ten times, and 5 s)."""
        self.unread = [f for f in self.unread if f.type != HEARTBEAT]
        first = None
        end = time.monotonic() + ms / 100 + 5
        while time.monotonic() < end:
            self.keep(keep_alive, chatter)
            f = self.receive({HEARTBEAT}, 0.02, keep_alive and chatter is None)
            if f is None:
                continue
            now = f.heartbeat()[0]
            if first is None:
                first = now
            elif (now - first) & 0xFFFFFFFF >= ms * 1000:
                return
        raise AssertionError("the board's time did not move %d ms" % ms)

    def close(self):
        os.close(self.fd)
