"""The board side of the link: a simulated board (rcl.sim.board.SimBoard)
paced to the wall clock and serving the frame protocol over a byte stream,
as board firmware would (docs/protocol.md).

    host frames --> FrameReader --> act (ports, memory, script, safe state)
                                      |          --> ACK / VALUE / REFUSED
    wall clock --> BoardClock --> SimBoard.service (timer 0) --> BIOS tick
                                      --> INT 1Ch in the Forth segment?
                                      --> run the script --> TICK frame

BoardClock is the machine-side API of rcl/board.py for a board with no
Forth machine beside it: its clock follows the wall clock, and "running
the INT 1Ch handler" means sending a TICK to the host, whose Forth runs it.
Board time runs at `rate` times the wall clock (1: real time; more, for
quick tests). In lockstep (the default) board time stands still from a
TICK until the host, its handler done (final TICK_DONE), waits for the
next one (WAIT): the handler and the host's foreground work between ticks
take no board time, as in the simulation, where they take microseconds.
While timer 0 does not tick, board time stands still but for the host's
CLOCK frames, which carry the host's virtual time: the port accesses that
set the board up land where the simulation has them. What the served
board does then depends on the frames only, not on how fast the host or
the line is. A real board cannot wait; `lockstep=False` (rcl-board
--free-running) behaves as one.
Sessions (docs/protocol.md, "Sessions"): HELLO puts the board as at
power-on before IDENTIFY, so a host never meets what the last one left;
a host that goes (its connection closed, a pty hung up: at once; silent:
the watchdog's 250 ms) leaves it safe and quiet, relays open and timer 0
no longer interrupting.
Faults for tests and demonstrations: a byte corruption rate on both
directions, a cut of the link (silence, or for TCP a closed connection)
at a time for a time, a stalled wheel.
"""
import os
import random
import select
import time

from rcl.board import CLOCK_HZ, FORTH_CS
from rcl.hw import protocol as P
from rcl.i80188 import EN, INT, T0_CONTROL, TIMER_CONTROL_REG, TIMER_MASK, VECTOR_USER_TICK
from rcl.sim.board import SimBoard

US = CLOCK_HZ // 1_000_000
# THE LOCKSTEP EXTENSION (simulated boards only, docs/protocol.md section 5):
# the parts of this server marked "lockstep" are no part of what firmware
# does. The host's time 0 (HELLO) is put on a multiple of 3 ms, where
# the board's clocks line up as at the simulation's time 0 (the 80188's
# 0.5 us, the 8253s' 8 us and the physics' 1 ms), so CLOCK's times land on
# the same edges as the simulation's.
ALIGN = 3000 * US
STALL = 0.020                # s: a longer gap between the watchdog's looks is the board's stall


class HeldTick:
    """Lockstep: the tick whose handler the host runs; board time stands
    at `at` (its TICK's moment) until the host is done with it."""

    def __init__(self, tick, at):
        self.tick, self.at = tick, at
        self.done = False            # its final TICK_DONE has come


class BoardMemory:
    """The 64 KiB at segment FORTH_CS on the board: on a link it is the
    host's (the host serves those addresses itself), here only a store."""

    def __init__(self):
        self.mem = bytearray(0x10000)

    def cstore(self, a, byte):
        self.mem[a & 0xFFFF] = byte & 0xFF


class BoardClock:
    """The board's own time, in CLOCK_HZ units since start, following the
    wall clock; the machine API a SimBoard needs (rcl/board.py)."""

    waiting_until = None

    def __init__(self, server, wall=time.monotonic, rate=1.0):
        self.server, self.wall, self.rate = server, wall, rate
        self.start = wall()
        self.held_since = None       # wall time the clock stopped (lockstep)
        self.clock = 0
        self.memory = BoardMemory()
        self.mem = self.memory.mem
        self.board = None

    def attach(self, board):
        self.board = board

    def now(self):
        """Board time now: the wall clock's, less the time held."""
        if self.held_since is not None:
            return self.clock
        return int((self.wall() - self.start) * self.rate * CLOCK_HZ)

    def hold(self):
        """Stop board time where it is (the host runs this tick's handler)."""
        self.held_since = self.wall()

    def release(self):
        """Board time goes on from where it stopped."""
        if self.held_since is not None:
            self.start = self.wall() - self.clock / (self.rate * CLOCK_HZ)
            self.held_since = None

    def catch_up(self, t):
        self.clock = max(self.clock, t)

    def reschedule(self):
        pass

    def advance_to(self, t):
        self.catch_up(t)

    def run_handler(self, xt):
        """INT 1Ch points into the Forth segment: the host runs it."""
        self.server.send_tick(xt)


class BoardServer:
    """One simulated board behind one byte stream at a time."""

    def __init__(self, corrupt=0.0, seed=1, cut_at=None, cut_for=None,
                 version=P.VERSION, name="rcl-board (simulated R-E Robot)", lockstep=True,
                 rate=1.0):
        self.clock = BoardClock(self, rate=rate)
        self.board = SimBoard(port_log=True)     # for --report and the tests
        self.board.attach(self.clock)
        # only the host's types are frames here (CLOCK only in lockstep), and
        # a payload that does not fit is answered REFUSED (docs/protocol.md 1)
        self.reader = P.FrameReader(P.received_by(P.BOARD, lockstep), keep_bad=True)
        self.random = random.Random(seed)
        self.corrupt, self.cut_at, self.cut_for = corrupt, cut_at, cut_for
        self.version, self.name = version, name
        self.script = []
        self.expected = 1            # the host's next sequence number
        self.send_seq = 1
        self.window = {}             # seq -> frame, for NAK
        self.last_reply = None
        self.last_valid = None       # board clock of the last good host frame
        self.looked_at = time.monotonic()   # the watchdog's last look
        # A good frame came since the host last went. False: no host, or
        # one given up (watchdog, hang-up), and the relays forced off.
        self.host_present = False
        self.last_sent = 0.0
        self.started = time.monotonic()
        # lockstep (the extension, simulated boards only): board time waits
        # for each tick's final TICK_DONE and WAIT, and for CLOCK before ticks
        self.lockstep = lockstep
        self.held = None             # the HeldTick the host runs (lockstep)
        self.cutting = False
        self.host_at = self.host_us = None   # lockstep: where the host's CLOCK put the board
        self.moved_by_host = 0                # board time CLOCK moved on (not silence)
        self.hello_at = None                 # ... and the host's time 0 (for the tests)
        self.watchdog_at = self.last_valid_clock = None   # board times, for tests
        self.quiet_at = None                 # wall time the host was last given up
        self.out = bytearray()
        self.stats = {"acted": 0, "refused": 0, "duplicates": 0, "naks": 0,
                      "watchdog": 0, "hangups": 0, "sessions": 0, "ticks_sent": 0,
                      "late": 0, "bytes_in": 0, "bytes_out": 0}
        self.lateness = []           # seconds each tick was serviced after its time

    def board_seconds(self):
        """The board's time as far as this server has run it, in seconds: a
        host in the same process judges the board's silence by it, so a busy
        machine that keeps this thread waiting is not a lost link (a cut is:
        the board's time goes on, its frames do not come). Time a host's
        CLOCK moved the board on at once is not counted: the host, looking
        between that jump and the board's answer, would take it for 250 ms
        of silence."""
        return (self.clock.clock - self.moved_by_host) / CLOCK_HZ

    # ----------------------------------------------------------- the loop
    def run_until(self, now):
        """Bring the board to board-clock `now`: each tick at its own time
        (in lockstep, none while the host has not finished the last)."""
        b, c = self.board, self.clock
        while b.due is not None and b.due <= now and self.held is None:
            c.catch_up(b.due)
            late = (now - b.due) / CLOCK_HZ
            self.lateness.append(late)
            self.stats["late"] += late > 0.002
            b.service(c)
        if not self.lockstep or not self.host_present:
            c.catch_up(now)        # (in lockstep, serving a host, by ticks and frames only)
        wall = time.monotonic()
        if wall - self.last_sent >= P.HEARTBEAT_MS / 1000:
            self.send("HEARTBEAT", time_us=(c.clock // US) & 0xFFFFFFFF,
                      ticking=int(self.ticking()))

    def timeout(self):
        """Seconds until the board next needs to run (at most 5 ms)."""
        due = self.board.due
        if due is None or self.held is not None:
            return 0.005
        return max(0.0, min(0.005, (due - self.clock.now()) / CLOCK_HZ / self.clock.rate))

    def cut(self):
        """The link is cut: by cut_link(), or inside the fault option's
        window (seconds since start)."""
        if self.cutting:
            return True
        if self.cut_at is None:
            return False
        t = time.monotonic() - self.started
        return t >= self.cut_at and (self.cut_for is None or t < self.cut_at + self.cut_for)

    def cut_link(self, cut=True):
        """Cut the link now (cut=False: mend it); the board goes on."""
        self.cutting = cut

    def receive(self, data):
        """Bytes from the host: everything that was waiting (b"": nothing
        was, and a frame left incomplete too long is dropped, section 1)."""
        self.run_until(self.clock.now())
        if self.cut():
            return
        self.stats["bytes_in"] += len(data)
        for f in self.reader.feed(self.garble(data), time.monotonic()):
            self.handle(f)
        self.watchdog(time.monotonic())

    def take_output(self):
        """Bytes to send to the host now (nothing while the link is cut)."""
        data, self.out = bytes(self.out), bytearray()
        if self.cut():
            return b""
        self.stats["bytes_out"] += len(data)
        return self.garble(data)

    def garble(self, data):
        if not self.corrupt:
            return data
        out = bytearray(data)
        for i in range(len(out)):
            if self.random.random() < self.corrupt:
                out[i] ^= 1 << self.random.randrange(8)
        return bytes(out)

    # ------------------------------------------------------------ safety
    def watchdog(self, wall):
        """No valid frame from the host for WATCHDOG_MS: safe and quiet.
        Looked at every turn of the serving loop (5 ms at most), after the
        bytes waiting are taken; a longer gap since the last look is a stall
        of this board (a busy host kept its thread or process waiting), in
        which it could hear nothing: only 20 ms of it count as the host's
        silence."""
        stalled = wall - self.looked_at - STALL
        self.looked_at = wall
        if self.last_valid is not None and stalled > 0:
            self.last_valid += stalled
        if self.last_valid is not None and self.host_present \
                and wall - self.last_valid > P.WATCHDOG_MS / 1000:
            self.stats["watchdog"] += 1
            self.watchdog_at = self.clock.now()
            self.quiet()

    def hang_up(self):
        """The host's end closed (TCP) or hung up (pty): safe and quiet at
        once, not 250 ms later."""
        if self.host_present:
            self.stats["hangups"] += 1
            self.quiet()

    def quiet(self):
        """The host has gone: relays open, timer 0 no longer interrupts (no
        TICK into a host that is not there), board time runs free."""
        self.board.tick_failed()
        self.quiet_at = time.monotonic()     # (bench/relays_off.py)
        self.host_present = False
        self.held = None
        self.clock.release()

    def ticking(self):
        """Timer 0 interrupts, unmasked, into INT 1Ch in the Forth segment."""
        b = self.board
        pcb = b.pcb
        control = pcb.read16(T0_CONTROL, b.pcb_time())
        mask = pcb.read16(TIMER_CONTROL_REG, b.pcb_time())
        return control & (EN | INT) == EN | INT and not mask & TIMER_MASK \
            and b.vector(VECTOR_USER_TICK)[0] == FORTH_CS

    # ----------------------------------------------------------- sending
    def send(self, message, /, seq=None, **values):
        if seq is None:
            seq = self.send_seq
            self.send_seq = (self.send_seq + 1) & 0xFF
        data = P.frame(seq, message, **values)
        self.window[seq] = data
        self.window.pop((seq - 128) & 0xFF, None)
        self.out += data
        self.last_sent = time.monotonic()
        return data

    def send_tick(self, xt):
        b = self.board
        results = [(r,) for r in b.port_script(self.script)]
        self.stats["ticks_sent"] += 1
        self.last_tick_frame = self.send("TICK", tick=b.ticks & 0xFFFF, off=xt, results=results)
        if self.lockstep and self.host_present:
            self.host_at = None                  # the ticks are the clock now
            self.held = HeldTick(b.ticks & 0xFFFF, self.clock.clock)
            self.clock.hold()

    def reply(self, message, /, **values):
        self.last_reply = self.send(message, **values)

    # ---------------------------------------------------------- receiving
    def handle(self, f):
        self.last_valid = time.monotonic()
        self.last_valid_clock = self.clock.now()
        self.host_present = True
        if f.error is not None and not f.message.sequenced:
            return                                # an unsequenced misfit: no answer
        if f.name == "HELLO":
            self.new_session()
            self.out += P.frame(0, "IDENTIFY", version=self.version, tick_us=10_000,
                                flags=P.FLAG_LOCKSTEP if self.lockstep else 0, name=self.name)
            return
        if f.name == "PING":
            return
        if f.name == "WAIT":                          # (lockstep: firmware may ignore it)
            if self.held is None:                       # held by CLOCK: on to the tick
                if self.ticking():
                    self.clock.release()
                return
            if self.held.done and f["tick"] == (self.held.tick + 1) & 0xFFFF:
                self.held = None
                self.clock.release()
            elif f["tick"] == self.held.tick:           # the host never got that TICK
                self.out += self.last_tick_frame
            return
        if f.name == "NAK":
            self.stats["naks"] += 1
            if f["seq"] in self.window:           # that one frame again (selective repeat)
                self.out += self.window[f["seq"]]
            return
        if f.name == "SAFE":                      # idempotent: acted on whatever its SEQ
            self.board.stop_motors()
        if f.seq == P.previous(self.expected):
            self.stats["duplicates"] += 1
            if self.last_reply is not None:
                self.out += self.last_reply       # our answer was lost: again
            return
        if f.seq != self.expected:
            return                                # not ours to take (SEQ 0: unsequenced)
        self.expected = P.following(self.expected)
        if f.error is not None:
            self.stats["refused"] += 1
            self.reply("REFUSED", ack=f.seq, reason="bad payload")
            return
        self.stats["acted"] += 1
        self.act(f)

    def act(self, f):
        if self.held is None:                      # not held: the frame's own moment
            self.clock.catch_up(self.clock.now())
        b, v = self.board, f.values
        name = f.name
        if name == "OUT8":
            b.out8(v["port"], v["value"])
        elif name == "OUT16":
            b.out16(v["port"], v["value"])
        elif name == "IN8":
            return self.reply("VALUE", ack=f.seq, value=b.in8(v["port"]))
        elif name == "IN16":
            return self.reply("VALUE", ack=f.seq, value=b.in16(v["port"]))
        elif name == "FAR_STORE":
            b.far_store8(v["seg"], v["off"], v["value"])
        elif name == "FAR_FETCH":
            return self.reply("VALUE", ack=f.seq, value=b.far_fetch8(v["seg"], v["off"]))
        elif name == "RUN":
            results = [(r,) for r in b.port_script(v["ops"])]
            return self.reply("RESULTS", ack=f.seq, results=results)
        elif name == "SNAPSHOT":
            self.script = list(v["ops"])
        elif name == "TICK_DONE":
            held = self.held if self.held is not None and self.held.tick == v["tick"] else None
            if held is not None and not held.done:       # held: the handler's own time
                due = b.due if b.due is not None else float("inf")
                self.clock.catch_up(min(held.at + v["us"] * US, due))
            for port, value in v["writes"]:
                b.out8(port, value)
            if v["final"] and held is not None:
                held.done = True
        elif name == "SAFE":
            b.stop_motors()
        elif name == "CLOCK":                     # (a lockstep board's type only)
            self.host_time(v["us"])
        elif name == "TICK_FAILED":               # no TICK_DONE will come for this tick
            b.tick_failed()
            self.held = None
            self.clock.release()
        self.reply("ACK", ack=f.seq)

    # ------------------------------------------------------------ sessions
    def new_session(self):
        """HELLO: a new host. Before it hears IDENTIFY the board is as at
        power-on (SimBoard.power_on: relays open, timers, 8253s, vectors
        and BIOS data new; the robot where it stands), with no script and
        the sequences reset: nothing the last host left can run. A lockstep
        board's time then stands still on the next multiple of ALIGN, the
        host's time 0, and moves by CLOCK until timer 0 ticks."""
        self.stats["sessions"] += 1
        self.expected, self.send_seq, self.window = 1, 1, {}
        self.last_reply, self.script = None, []
        self.held = None
        self.host_at = None
        self.clock.release()
        start = self.clock.now()
        if self.lockstep:
            start = -(-start // ALIGN) * ALIGN
        self.board.stop_motors()                 # relays open now, not at `start`
        self.clock.catch_up(start)
        self.board.power_on()
        if self.lockstep:
            self.clock.hold()
            self.host_at, self.host_us = start, 0
            self.hello_at = start

    # ------------- the lockstep extension (simulated boards only): no ticks yet
    def host_time(self, us):
        """CLOCK: the host's time is `us` (mod 2**32) since HELLO; the
        board comes up to it, running whatever falls due on the way (a
        TICK, which then holds it), and holds there. Ignored while a tick
        holds the board; the first CLOCK after ticks only sets where the
        host's time is."""
        if self.held is not None:
            return
        if self.host_at is None:
            self.host_at, self.host_us = self.clock.now(), us
        self.host_at += ((us - self.host_us) & 0xFFFFFFFF) * US
        self.host_us = us
        # (counted before the jump, put right after: a look from the host's
        # reader thread meanwhile sees less time gone, never more)
        before, jump = self.clock.clock, max(0, self.host_at - self.clock.clock)
        self.moved_by_host += jump
        self.run_until(self.host_at)
        if self.held is None:
            self.clock.catch_up(self.host_at)
            self.clock.hold()
        self.moved_by_host += (self.clock.clock - before) - jump

    # ------------------------------------------------------------ serving
    def serve_fd(self, fd, stop, on_idle=None):
        """Serve the stream on file descriptor fd until stop() is true or
        the peer goes away (-> "closed"); a pty's master reads EIO while
        no one has the device open, which is waited out. Either end of a
        host (EOF, EIO) is a hang-up: safe and quiet at once."""
        while not stop():
            r, _, _ = select.select([fd], [], [], self.timeout())
            if r:
                try:
                    data = os.read(fd, 4096)
                except OSError:                   # pty: nobody on the other end
                    data = None
                    self.hang_up()
                    time.sleep(0.005)
                if data == b"":
                    self.hang_up()
                    return "closed"
                if data:
                    self.receive(data)
            else:
                self.receive(b"")
            self.run_until(self.clock.now())
            self.watchdog(time.monotonic())
            if self.cut() and on_idle == "close":
                return "cut"
            out = self.take_output()
            if out:
                try:
                    os.write(fd, out)
                except OSError:
                    pass
        return "stopped"
