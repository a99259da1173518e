"""The frame protocol between rcl (the host) and a board: framing, CRC, and
the one declarative table of messages both ends import (docs/protocol.md
is the specification; this module is its executable form).

    byte  0      1      2      3      4 .. 4+LEN-1    4+LEN   5+LEN
        +------+------+------+------+---------------+-------+-------+
        | SYNC | LEN  | SEQ  | TYPE | PAYLOAD (LEN) | CRC hi| CRC lo|
        +------+------+------+------+---------------+-------+-------+
    SYNC = 0xA5; LEN = payload bytes (0..MAX_PAYLOAD); CRC-16/CCITT-FALSE
    (poly 0x1021, init 0xFFFF, no reflection, no final xor) over LEN, SEQ,
    TYPE and the payload, sent high byte first. check: b"123456789" -> 0x29B1.

Payload fields are little-endian: B (u8), H (u16), I (u32), `s` (the rest
of the payload as text) and a trailing repeated group, written `*HB` (as
many (u16, u8) records as the rest of the payload holds).
"""
import struct

from rcl.errors import RclError

VERSION = 1                 # protocol version: HELLO and IDENTIFY carry it
SYNC = 0xA5
MAX_PAYLOAD = 64          # small, so a corrupted LEN delays the resync little
FRAME_GAP_MS = 50           # a frame still incomplete this long after its SYNC is no frame
HEADER, TRAILER = 4, 2      # SYNC LEN SEQ TYPE, then CRC
WATCHDOG_MS = 250           # board: no valid frame from the host this long -> safe state
HEARTBEAT_MS = 50           # board: a HEARTBEAT at least this often when not ticking
KEEPALIVE_MS = 100          # host: a PING when nothing else was sent this long
LOST_MS = 250               # host: nothing valid from the board this long -> Link lost
RETRY_MS = 10               # host: resend a request not answered this long

# The board's safe state (docs/protocol.md "Safe states"): the MOTOR latch
# all off (both wheels braked and disabled), and on the AUX latch the arm,
# gripper and beeper bits cleared, the other AUX bits kept.
SAFE_MOTOR_PORT, SAFE_MOTOR_VALUE = 0x88, 0x00
SAFE_AUX_PORT, SAFE_AUX_CLEAR = 0x89, 0x15    # ARM-ON GRIP-ON BEEPER


class LinkError(RclError):
    """The link to a board failed or the board refused us."""


class ProtocolError(LinkError):
    """A frame that does not fit the table (decoding it failed)."""


# ------------------------------------------------------------- messages
class Message:
    """One row of the table: name, type id, who sends it, whether it is
    sequenced (acknowledged and retransmitted) and its payload fields."""

    def __init__(self, name, type_id, sender, fields, sequenced=True, doc="", lockstep=False):
        self.name, self.id, self.sender = name, type_id, sender
        self.fields = [f.split(":") for f in fields.split()] if fields else []
        self.sequenced, self.doc = sequenced, doc
        self.lockstep = lockstep    # known only to lockstep (simulated) boards

    def encode(self, **values):
        out = bytearray()
        for name, fmt in self.fields:
            value = values[name]
            if fmt == "s":
                out += value.encode("latin-1")
            elif fmt.startswith("*"):
                for record in value:
                    out += struct.pack("<" + fmt[1:], *record)
            else:
                out += struct.pack("<" + fmt, value)
        if len(out) > MAX_PAYLOAD:
            raise ProtocolError("%s payload of %d bytes is too long" % (self.name, len(out)))
        return bytes(out)

    def decode(self, payload):
        values, at = {}, 0
        try:
            for name, fmt in self.fields:
                if fmt == "s":
                    values[name], at = payload[at:].decode("latin-1"), len(payload)
                elif fmt.startswith("*"):
                    size = struct.calcsize("<" + fmt[1:])
                    if (len(payload) - at) % size:
                        raise ProtocolError("%s: ragged records" % self.name)
                    values[name] = [struct.unpack_from("<" + fmt[1:], payload, i)
                                    for i in range(at, len(payload), size)]
                    at = len(payload)
                else:
                    values[name] = struct.unpack_from("<" + fmt, payload, at)[0]
                    at += struct.calcsize("<" + fmt)
        except struct.error:
            raise ProtocolError("%s: payload too short" % self.name) from None
        if at != len(payload):
            raise ProtocolError("%s: %d bytes too many" % (self.name, len(payload) - at))
        return values


HOST, BOARD = "host", "board"

#   name          id    sender  fields                          sequenced
TABLE = [
    Message("HELLO", 0x01, HOST, "version:B", False,
            "start a session: sequences restart at 1; the board answers IDENTIFY"),
    Message("OUT8", 0x02, HOST, "port:H value:B", doc="8-bit OUT (PC!); answer ACK"),
    Message("OUT16", 0x03, HOST, "port:H value:H", doc="16-bit OUT (P!); answer ACK"),
    Message("IN8", 0x04, HOST, "port:H", doc="8-bit IN (PC@); answer VALUE"),
    Message("IN16", 0x05, HOST, "port:H", doc="16-bit IN (P@); answer VALUE"),
    Message("FAR_STORE", 0x06, HOST, "seg:H off:H value:B",
            doc="store a byte of the board's memory (LC!); answer ACK"),
    Message("FAR_FETCH", 0x07, HOST, "seg:H off:H",
            doc="fetch a byte of the board's memory (LC@); answer VALUE"),
    Message("SNAPSHOT", 0x08, HOST, "ops:*BHB",
            doc="the per-tick script: (0, port, value) OUT8, (1, port, 0) IN8; answer ACK"),
    Message("TICK_DONE", 0x09, HOST, "tick:H final:B us:H writes:*HB",
            doc="the tick handler's OUT8s, in order (final: the handler ended; us: "
                "its time since the tick so far); answer ACK"),
    Message("SAFE", 0x0A, HOST, "", doc="safe state now (motors off); answer ACK"),
    Message("TICK_FAILED", 0x0B, HOST, "",
            doc="safe state, and timer 0 stops interrupting; answer ACK"),
    Message("PING", 0x0C, HOST, "", False, doc="keep the watchdog fed; no answer"),
    Message("RUN", 0x0E, HOST, "ops:*BHB",
            doc="port operations as one, as SNAPSHOT's; answer RESULTS"),
    Message("WAIT", 0x0F, HOST, "tick:H", False,
            doc="the host waits for tick `tick`; a lockstep board lets its time run; no answer"),
    Message("CLOCK", 0x10, HOST, "us:I", lockstep=True,
            doc="lockstep boards only: the host's time has reached `us` (µs since HELLO); "
                "while timer 0 does not tick, the board's time follows it; answer ACK"),
    Message("NAK", 0x0D, HOST, "seq:B", False,
            doc="board frame `seq` was not received: send it again"),
    Message("IDENTIFY", 0x81, BOARD, "version:B tick_us:H flags:B name:s", False,
            doc="answer to HELLO: the board's protocol version, tick period, flags "
                "(FLAG_LOCKSTEP), name"),
    Message("ACK", 0x82, BOARD, "ack:B", doc="host frame `ack` was acted on"),
    Message("VALUE", 0x83, BOARD, "ack:B value:H", doc="host frame `ack` read `value`"),
    Message("TICK", 0x84, BOARD, "tick:H off:H results:*B",
            doc="timer 0 ticked, the BIOS counted it, INT 1Ch is FORTH_CS:off; "
                "the script's IN8 results"),
    Message("HEARTBEAT", 0x85, BOARD, "time_us:I ticking:B",
            doc="sent when nothing was sent for HEARTBEAT_MS; ticking: a TICK will come"),
    Message("RESULTS", 0x87, BOARD, "ack:B results:*B",
            doc="host frame `ack` (RUN) read these bytes"),
    Message("REFUSED", 0x86, BOARD, "ack:B reason:s",
            doc="host frame `ack` could not be acted on (bad payload, script too long)"),
]
BY_NAME = {m.name: m for m in TABLE}
BY_ID = {m.id: m for m in TABLE}
# The lockstep extension (docs/protocol.md section 5): a simulated board
# only sets this flag; CLOCK (lockstep=True above) and WAIT go only to it
FLAG_LOCKSTEP = 0x01        # IDENTIFY: the board holds its time for WAIT and CLOCK
SCRIPT_OUT, SCRIPT_IN = 0, 1     # as rcl.board.OUT8 and IN8


def received_by(end, lockstep=False):
    """The types `end` (HOST or BOARD) knows (docs/protocol.md section 1):
    what the other end sends; CLOCK only on a lockstep board. Any other
    TYPE, the end's own types included, is no frame to it."""
    return {m.id for m in TABLE if m.sender != end and (lockstep or not m.lockstep)}


# ---------------------------------------------------------------- frames
def _crc_byte(crc):
    for _ in range(8):
        crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else crc << 1
    return crc & 0xFFFF


# a byte at a time, not a bit (a fifth of the time): the host computes two
# CRCs every tick, the TICK it reads and the TICK_DONE it sends
_CRC_TABLE = [_crc_byte(i << 8) for i in range(256)]


def crc16(data, crc=0xFFFF):
    """CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, MSB first, no xor out."""
    table = _CRC_TABLE
    for byte in data:
        crc = ((crc << 8) & 0xFFFF) ^ table[(crc >> 8) ^ byte]
    return crc


def frame(seq, message, /, **values):
    """The bytes of one frame of `message` (a name in the table)."""
    msg = BY_NAME[message]
    payload = msg.encode(**values)
    body = bytes((len(payload), seq & 0xFF, msg.id)) + payload
    crc = crc16(body)
    return bytes((SYNC,)) + body + bytes((crc >> 8, crc & 0xFF))


class Frame:
    """A received frame: seq, the message row, its decoded values."""

    def __init__(self, seq, message, values, error=None):
        self.seq, self.message, self.values = seq, message, values
        self.error = error         # the payload does not fit (values is None)

    @property
    def name(self):
        return self.message.name

    def __getitem__(self, key):
        return self.values[key]

    def __repr__(self):
        return "Frame(%d, %s, %r)" % (self.seq, self.name, self.values)


class FrameReader:
    """Turns a byte stream into frames. After garbage, a bad CRC or a type
    not in `types` (None: any in the table) it drops one byte and looks for
    the next SYNC, so it resynchronises on its own; a frame is only ever
    returned whole and with a good CRC. A good frame whose payload does not
    fit its message is dropped, or with keep_bad returned with `error` set
    and no values (a board answers it REFUSED, section 1 step 5).

    A board's reader is given `now`: the host writes each frame whole, so
    its bytes come together, and one still incomplete FRAME_GAP_MS after
    its SYNC was read is no frame (a corrupted LEN, section 1 step 3).
    Without that rule a PING whose LEN turned from 0 into 32 would hide
    the next five PINGs, half a second, from a board whose watchdog waits
    250 ms. It is judged only after the caller has read everything
    waiting, so a frame that a stall of the board's split between two
    reads is still taken whole. The host's reader has no `now`: a board
    may write a frame byte by byte, and a simulated one stall mid-frame."""

    def __init__(self, types=None, keep_bad=False, gap=FRAME_GAP_MS / 1000):
        self.buf = bytearray()
        self.types, self.keep_bad, self.gap = types, keep_bad, gap
        self.bad = 0               # frames rejected: CRC, unknown type, payload
        self.skipped = 0           # bytes dropped looking for SYNC
        self.waiting_since = None  # when the frame at buf[0] was found incomplete

    def feed(self, data, now=None):
        """Add received bytes, everything that was waiting, read at `now`
        (seconds; None: no clock, a frame is waited for however long);
        -> the complete good frames among them."""
        self.buf += data
        frames = []
        while True:
            got = self._next(now)
            if got is None:
                return frames
            frames.append(got)

    def _next(self, now):
        buf = self.buf
        while buf:
            if buf[0] != SYNC:
                start = buf.find(SYNC)
                drop = len(buf) if start < 0 else start
                self.skipped += drop
                del buf[:drop]
                self.waiting_since = None
                continue
            if len(buf) < 2:
                return None
            length = buf[1]
            if length > MAX_PAYLOAD:
                self._drop_one()
                continue
            end = HEADER + length + TRAILER
            if len(buf) < end:
                if not self.waited_too_long(now):
                    return None
                self._drop_one()
                continue
            crc = (buf[end - 2] << 8) | buf[end - 1]
            msg = BY_ID.get(buf[3])
            known = msg is not None and (self.types is None or msg.id in self.types)
            if not known or crc != crc16(buf[1:end - 2]):
                self._drop_one()
                continue
            seq, payload = buf[2], bytes(buf[HEADER:end - 2])
            del buf[:end]
            self.waiting_since = None
            try:
                return Frame(seq, msg, msg.decode(payload))
            except ProtocolError as e:
                self.bad += 1
                if self.keep_bad:
                    return Frame(seq, msg, None, error=str(e))
        return None

    def waited_too_long(self, now):
        """The frame at buf[0] is incomplete: has it been for FRAME_GAP_MS
        as of `now` (None: no clock, never)?"""
        if now is None:
            return False
        if self.waiting_since is None:
            self.waiting_since = now
        return now - self.waiting_since >= self.gap

    def _drop_one(self):
        self.bad += 1
        self.skipped += 1
        del self.buf[:1]
        self.waiting_since = None


def following(seq):
    """The host's next SEQ: 1..255 and round again; 0 is never used, so a
    frame with SEQ 0 from the host is always an unsequenced one."""
    return seq % 255 + 1


def previous(seq):
    return 255 if seq == 1 else seq - 1


def newer(seq, expected):
    """Where seq lies from expected, mod 256: 0 is it, 1..127 ahead (a gap),
    -128..-1 behind (already seen)."""
    d = (seq - expected) & 0xFF
    return d - 256 if d >= 128 else d
