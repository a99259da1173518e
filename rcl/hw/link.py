"""LinkBoard: the host's rcl.board.Board for a board at the other end of a
serial link (any pyserial URL or device), speaking the frame protocol of
docs/protocol.md.

    Forth machine --- out8/in8/... ---> LinkBoard --- request ---> port
                  <-- service: TICK ---            <-- reader thread --
                                                       (frames, NAK, PING)

Requests are stop-and-wait: one sequenced frame out, resent every RETRY_MS
until its ACK or VALUE comes. The reader thread decodes what the board
sends, keeps board frames in order (go-back-N with NAK), sends a PING when
nothing went out for KEEPALIVE_MS, and notices a silent board.

Time: the board's ticks are the clock. `due` is the virtual time of the
next tick (the last tick's board time plus the period); when the machine
gets there, `service` waits for the real TICK, moves the machine's clock to
the board's time (catch_up, never back) and runs INT 1Ch. Inside that
handler, reads the per-tick script covers are served from the TICK's
results, and the handler's writes go back as one TICK_DONE.

A silent link (LOST_MS) or a failed port is "Link lost": the running word
is stopped at its next primitive boundary (machine.request_stop), the board
is told SAFE where it can still hear (its watchdog does it otherwise), and
RECONNECT, or the next command a second later, connects again.
"""
import queue
import threading
import time

import serial

from rcl.board import CLOCK_HZ, FORTH_CS, Board
from rcl.errors import ForthError
from rcl.hw import protocol as P
from rcl.i80188 import INH, PCB_BASE

US = CLOCK_HZ // 1_000_000
T0_STOPPED = INH             # T0CON: EN off (INH set to write it), INT off: no tick
BACKLOG = 25                 # ticks queued beyond this (the host was away) are counted, not run
REQUEST_GIVE_UP = 1.0        # seconds of unanswered retries before Link lost (silence_clock's)
HELLO_WAIT = 3.0             # seconds to wait for IDENTIFY (a board resetting on open)
RECONNECT_AFTER = 0.5        # a lost link is tried again at most this often
STALL = 0.030                # s: a longer gap between the reader's reads is this process's stall
# A tick answered later than HOST_LATE is noted: 10 ticks in which RCL's
# control did not act, at 2 MPH its whole 100-count following limit
HOST_LATE = 0.100
LATE_WINDOW = 100            # ticks: a late answer this recent explains the error after it

class LinkLost(P.LinkError):
    """The board stopped answering."""


def link_lost():
    return ForthError(-292, "Link lost")


class LinkBoard(Board):
    """A board over a link; `open_port()` -> an open pyserial port."""

    def __init__(self, open_port, script=()):
        self.open_port, self.script = open_port, list(script)
        self.port = None
        self.lock = threading.Lock()          # one writer on the port at a time
        self.replies = queue.Queue()
        self.events = queue.Queue()           # TICK and HEARTBEAT frames, in order
        self.identify = queue.Queue()
        self.reader = None
        self.stopping = threading.Event()
        self.lost, self.lost_at, self.why = False, 0.0, ""
        self.ticks = self.skipped = self.retries = 0
        self.late = 0                         # ticks run more than 2 ms after they came
        self.late_answer = None               # (delay s, tick, self.ticks): the worst recent
        self.period = 10_000 * US
        self.board_clock = None               # virtual time of the last tick
        self.sent_writes = []                 # (port, value): every OUT8 the board did for us
        self.bytes_out = self.bytes_in = 0
        self.in_tick = False
        self.name = ""
        try:
            self.connect()
        except BaseException:
            self.close()                      # no thread or open port left behind
            raise

    # ------------------------------------------------------------ session
    def connect(self, reopen=True):
        """Open the port (reopen=False: keep the one open), HELLO until
        IDENTIFY, register the tick script."""
        if reopen:
            self.port = self.open_port()
        self.seq, self.expected, self.last_nak, self.held = 1, 1, 0.0, {}
        self.pending = None                   # [seq, frame, name, give up, sent at]: not yet answered
        self.last_tx = time.monotonic()
        # Silence is judged on the board's own clock where the port can
        # tell it (rclsim://: a board in this process, which a busy host
        # may keep from running), else on the wall clock.
        self.silence_clock = getattr(self.port, "board_seconds", time.monotonic)
        self.last_rx = self.silence_clock()
        for q in (self.replies, self.events, self.identify):
            drain(q)
        self.lost, self.why = True, ""         # until IDENTIFY: the reader keeps quiet
        if reopen or not self.reader.is_alive():
            self.stopping.clear()
            self.reader = threading.Thread(target=self.read_loop, daemon=True,
                                           name="rcl-link-reader")
            self.reader.start()
        # (the port kept: a board that only went silent gets what any
        # request gets, not half a second, too little on a loaded machine)
        ident = self.hello(HELLO_WAIT if reopen else REQUEST_GIVE_UP)
        if ident["version"] != P.VERSION:
            self.close()
            raise P.LinkError("The board speaks protocol version %d; this rcl speaks "
                              "version %d. Update the board's firmware or rcl."
                              % (ident["version"], P.VERSION))
        self.name, self.period = ident["name"], ident["tick_us"] * US
        self.lockstep = bool(ident["flags"] & P.FLAG_LOCKSTEP)
        self.lost = False
        self.request("SNAPSHOT", ops=self.script)
        self.board_clock, self.ticking, self.last_us = None, False, None
        self.follows = self.lockstep          # lockstep, no tick yet: the board keeps our time
        self.told_us = 0                      # ... and has it up to here (CLOCK)
        if self.machine is not None:
            self.time_zero = self.machine.clock
            self.due = self.machine.clock      # is it ticking? service finds out
            self.machine.reschedule()

    def hello(self, wait):
        deadline = time.monotonic() + wait
        while time.monotonic() < deadline:
            self.send(P.frame(0, "HELLO", version=P.VERSION))
            try:
                ident = self.identify.get(timeout=0.1)
            except queue.Empty:
                if self.lost and self.why.startswith("port"):
                    break
                continue
            if "reason" in ident:                 # REFUSED, SEQ 0: no session for us
                raise P.LinkError("The board on %s refused a session: %s"
                                  % (self.port_name(), ident["reason"]))
            return ident
        raise P.LinkError("No answer from a board on %s (is rcl-board or the "
                          "firmware running, at 115200 baud?)" % self.port_name())

    def port_name(self):
        return getattr(self.port, "portstr", None) or getattr(self.port, "port", "?")

    def close(self):
        """Leaving: a board that still hears is left safe and quiet (SAFE,
        then timer 0 stopped), then the port closed."""
        if self.port is not None and not self.lost and self.machine is not None \
                and self.reader is not threading.current_thread():
            try:
                self.request("SAFE")
                self.request("OUT16", port=PCB_BASE + 0x56, value=T0_STOPPED)
            except (P.LinkError, serial.SerialException, OSError):
                pass
        self.stopping.set()
        if self.port is None:
            return
        if self.reader is not None and self.reader is not threading.current_thread():
            self.reader.join(1.0)
        try:
            self.port.close()
        except Exception:          # noqa: BLE001  (closing a failed port)
            pass

    def reconnect(self):
        try:
            self.reopen()
        except (P.LinkError, serial.SerialException, OSError) as e:
            self.lost, self.lost_at, self.why = True, time.monotonic(), str(e)
            self.due = None
            return "Link lost: %s" % e
        return "Link up: %s, protocol %d" % (self.name, P.VERSION)

    def reopen(self):
        """Connect again: the same port if it still works (the board was
        only silent), else the port opened anew (a closed connection)."""
        failed = self.why.startswith("port") or not getattr(self.port, "is_open", False)
        if failed:
            self.close()
        self.connect(reopen=failed)

    def attach(self, machine):
        super().attach(machine)
        self.time_zero = machine.clock        # HELLO's moment, in the host's time
        self.due = machine.clock
        machine.reschedule()

    # ------------------------------------------------------- reader thread
    def read_loop(self):
        reader = P.FrameReader(P.received_by(P.HOST))    # board types only (section 1)
        looked_at = time.monotonic()
        while not self.stopping.is_set():
            try:
                data = self.port.read(max(1, self.port.in_waiting))
            except (serial.SerialException, OSError, TypeError, AttributeError) as e:
                self.why = "port: %s" % e
                self.lose(self.why)
                return
            now = time.monotonic()
            self.was_away(now - looked_at)
            looked_at = now
            if data:
                self.bytes_in += len(data)
                for f in reader.feed(data):
                    self.dispatch(f, now)
            if now - self.last_tx > P.KEEPALIVE_MS / 1000:
                self.send(P.frame(0, "PING"))
            if self.silent() and not self.lost:
                self.lose("no frame from the board for %d ms" % P.LOST_MS)
            if self.held and now - self.gap_since > REQUEST_GIVE_UP and not self.lost:
                # the board no longer keeps it (section 3): never wait on
                self.lose("board frame %d was not sent again" % self.expected)

    def was_away(self, seconds):
        """This thread's last read came back this much later (a read waits
        10 ms at most): beyond STALL it was a busy machine keeping this
        process waiting, most likely the board's as well, and a wall-clock
        silence does not count that time (it still counts STALL of each)."""
        if seconds > STALL and self.silence_clock is time.monotonic:
            self.last_rx += seconds - STALL

    def silent(self):
        """Nothing from the board for LOST_MS (of its own time, where known)."""
        return self.silence_clock() - self.last_rx > P.LOST_MS / 1000

    def dispatch(self, f, now):
        """Board frames are taken in sequence order: one that comes early is
        held, and the missing one asked for again (NAK)."""
        f.arrived = now
        self.last_rx = self.silence_clock()
        if f.name == "IDENTIFY":
            self.expected, self.held = 1, {}
            self.identify.put(f.values)
            return
        if f.name == "REFUSED" and f.seq == 0:      # a HELLO refused (a busy board)
            self.identify.put(f.values)
            return
        d = P.newer(f.seq, self.expected)
        if d > 0:
            if not self.held:
                self.gap_since = now          # a frame is missing from here
            self.held[f.seq] = f
            if now - self.last_nak > P.RETRY_MS / 1000:
                self.last_nak = now
                self.send(P.frame(0, "NAK", seq=self.expected))
            return
        if d < 0:
            return
        while f is not None:
            self.expected = (self.expected + 1) & 0xFF
            (self.events if f.name in ("TICK", "HEARTBEAT") else self.replies).put(f)
            f = self.held.pop(self.expected, None)
        self.last_nak = 0.0
        self.gap_since = now                  # (another gap's time starts now)

    def send(self, data):
        with self.lock:
            try:
                self.port.write(data)
            except (serial.SerialException, OSError, TypeError, AttributeError) as e:
                self.lost, self.why = True, "port: %s" % e
                return
            self.bytes_out += len(data)
            self.last_tx = time.monotonic()

    # ----------------------------------------------------------- requests
    def request(self, name, /, **values):
        """One sequenced frame, resent until answered; -> the answer."""
        self.post(name, **values)
        return self.settle()

    def post(self, name, /, **values):
        """Send a sequenced frame without waiting for its answer (the
        answer to the one before is waited for first: one in flight)."""
        self.settle()
        if self.lost:
            raise LinkLost(self.why)
        seq, self.seq = self.seq, P.following(self.seq)
        data = P.frame(seq, name, **values)
        self.pending = [seq, data, name, self.silence_clock() + REQUEST_GIVE_UP, time.monotonic()]
        self.send(data)

    def settle(self, block=True):
        """Wait for the answer to the frame in flight, resending it every
        RETRY_MS; -> the answer (None: nothing in flight, or not yet)."""
        while self.pending is not None:
            seq, data, name, give_up, sent_at = self.pending
            try:
                reply = self.replies.get(timeout=P.RETRY_MS / 1000 if block else 0)
            except queue.Empty:
                if self.lost or self.silence_clock() > give_up:
                    self.pending = None
                    raise LinkLost(self.why or "no answer") from None
                if time.monotonic() - sent_at >= P.RETRY_MS / 1000:
                    self.retries += 1
                    self.pending[4] = time.monotonic()
                    self.send(data)
                if not block:
                    return None
                continue
            if reply["ack"] == seq:
                self.pending = None
                if reply.name == "REFUSED":
                    raise P.LinkError("The board refused %s: %s" % (name, reply["reason"]))
                return reply
        return None

    def lose(self, why, stop=True):
        """The link is gone: say so once, stop the running word."""
        if not self.lost:
            self.lost, self.lost_at, self.why = True, time.monotonic(), why
            self.send(P.frame(self.seq, "SAFE"))       # if the board still hears
            m = self.machine
            if stop and m is not None and (m.in_forth or m.masked):
                m.request_stop(link_lost())
        self.due = None

    def usable(self):
        """True when the link is up. A lost link is tried again, at most
        every RECONNECT_AFTER seconds: the abort that follows the loss
        (its safe-state relay writes) finds it quietly unusable; any other
        request finds it reconnected, or is stopped with Link lost (a read
        on a lost link has no true answer to give)."""
        if not self.lost:
            return True
        if self.in_tick or self.machine.in_safe_state:
            return False
        if time.monotonic() - self.lost_at < RECONNECT_AFTER:
            self.machine.request_stop(link_lost())
            return False
        self.lost_at = time.monotonic()
        try:
            self.reopen()
        except (P.LinkError, serial.SerialException, OSError) as e:
            self.lost, self.lost_at, self.why = True, time.monotonic(), str(e)
            self.machine.request_stop(link_lost())   # taken at the next primitive boundary
            return False
        # A new session: the board is as at power-on, so the word that was
        # running cannot go on as if nothing had happened.
        self.machine.request_stop(ForthError(-292, "Link up again, the board reset: "
                                             "RECONNECT sets it up"))
        return True

    def io(self, name, /, wait=True, **values):
        """A request from a port word: on a lost link, stop the word.
        -> the answer (True when not waited for), None when lost."""
        if not self.usable():
            return None
        try:
            self.tell_time()
            if not wait:
                self.post(name, **values)
                return True
            return self.request(name, **values)
        except LinkLost as e:
            self.lose(str(e))
            return None

    def tell_time(self):
        """A lockstep board whose timer does not tick keeps the host's time:
        before a port or memory access, tell it how far the host has come
        (CLOCK), so the access lands where the simulation has it."""
        if not self.follows or self.in_tick or self.machine is None:
            return
        us = (self.machine.clock - self.time_zero) // US
        if us != self.told_us:
            self.post("CLOCK", us=us & 0xFFFFFFFF)
            self.told_us = us

    def tick_reads(self, ops):
        """What the software's tick handler reads first (RCL's counter
        words say it): the board does it at every tick and sends the bytes
        with the TICK, so a tick costs no round trip. Kept for the next
        connect."""
        ops = [tuple(op) for op in ops]
        if ops == self.script:                # this session has it already
            return
        self.script = ops
        if not self.usable():
            return
        try:                                  # not a port access: no CLOCK before it, so
            self.request("SNAPSHOT", ops=self.script)   # a lockstep board's time moves as before
        except LinkLost as e:
            self.lose(str(e))

    # ------------------------------------------------------------ port I/O
    def out8(self, port, byte):
        if self.in_tick:
            return self.tick_out8(port, byte)
        if self.io("OUT8", port=port, value=byte) is not None:
            self.sent_writes.append((port, byte))

    def in8(self, port):
        if self.in_tick:
            return self.tick_in8(port)
        reply = self.io("IN8", port=port)
        return 0xFF if reply is None else reply["value"] & 0xFF

    def out16(self, port, word):
        if port < PCB_BASE:
            return super().out16(port, word)
        self.flush_tick_writes()
        self.io("OUT16", port=port, value=word)
        if not self.in_tick and not self.lost:
            # The timer may tick now: wait for its first tick a period on (a
            # HEARTBEAT says if none comes), so the host's time meets it there.
            self.ticking = True
            self.due = self.machine.clock + self.period
            self.machine.reschedule()

    def in16(self, port):
        if port < PCB_BASE:
            return super().in16(port)
        self.flush_tick_writes()
        reply = self.io("IN16", port=port)
        return 0xFFFF if reply is None else reply["value"]

    def port_script(self, ops):
        if self.in_tick:
            return super().port_script(ops)    # from the tick's results where it can
        ops = list(ops)
        reply = self.io("RUN", ops=ops)
        if reply is None:
            return [0xFF] * sum(op == P.SCRIPT_IN for op, _, _ in ops)
        self.sent_writes.extend((port, value) for op, port, value in ops if op == P.SCRIPT_OUT)
        return [r for (r,) in reply["results"]]

    def far_fetch8(self, seg, off):
        if seg == FORTH_CS:
            return super().far_fetch8(seg, off)
        self.flush_tick_writes()
        reply = self.io("FAR_FETCH", seg=seg, off=off)
        return 0xFF if reply is None else reply["value"] & 0xFF

    def far_store8(self, seg, off, byte):
        if seg == FORTH_CS:
            return super().far_store8(seg, off, byte)
        self.flush_tick_writes()
        self.io("FAR_STORE", seg=seg, off=off, value=byte)

    # ----------------------------------------------------------- the tick
    def service(self, m):
        """The next tick. While the board says it is not ticking, this only
        looks (every tick period of virtual time) for what has come. A
        lockstep board that keeps the host's time is told it first: a tick
        that falls due on the way comes before CLOCK's answer, so it is
        here to be run, whatever the wall clock did."""
        if not self.usable():
            self.due = None
            return
        if self.follows:
            try:
                self.tell_time()
                self.settle()
            except LinkLost as e:
                self.lose(str(e))
                return
        while True:
            event = self.next_event(block=self.ticking and not self.follows)
            if event is None:
                if not self.lost:
                    self.due = m.clock + self.period
                return
            if event.name == "TICK":
                self.ticking = True
                return self.run_tick(m, event)
            self.ticking = bool(event["ticking"])
            if not self.ticking and self.lockstep:
                self.follows = True            # the board keeps our time again
            elif not self.ticking:
                m.catch_up(self.heartbeat_time(event["time_us"]))

    def next_event(self, block):
        """The next TICK or HEARTBEAT (None: none waiting, when not to
        block); a backlog beyond BACKLOG ticks (the host was away, at the
        prompt) is counted, not run."""
        while self.events.qsize() > BACKLOG:
            f = self.events.get()
            if f.name == "TICK":
                self.skipped += 1
                self.log_script_writes()
        waited = 0.0
        # a lockstep board waits for our WAIT: look often; a free-running
        # one ticks on its own: wake only to resend a lost TICK_DONE
        poll = 0.002 if self.lockstep or not block else P.RETRY_MS / 2000
        try:
            while True:
                try:
                    return self.events.get(timeout=poll)
                except queue.Empty:
                    self.settle(block=False)      # the last TICK_DONE, resent if lost
                    if not block:
                        return None
                    if self.lockstep and time.monotonic() - waited > P.RETRY_MS / 1000:
                        waited = time.monotonic()
                        self.send(P.frame(0, "WAIT", tick=self.next_tick()))
                    # Silence is the reader thread's to judge, after it has
                    # read what waits: a process that was not scheduled for a
                    # while would find last_rx old here with frames unread.
                    if self.lost:
                        raise LinkLost(self.why or "no tick") from None
        except LinkLost as e:
            self.lose(str(e))
            return None

    def next_tick(self):
        """The number of the tick waited for (0xFFFF: not known yet)."""
        return 0xFFFF if self.board_clock is None else (self.last_tick + 1) & 0xFFFF

    def board_time(self, tick):
        """The virtual time of tick number `tick` (ticks are a period apart;
        the number wraps at 2**16)."""
        if self.board_clock is None:
            self.board_clock, self.last_tick = self.machine.clock, tick
        self.board_clock += ((tick - self.last_tick) & 0xFFFF) * self.period
        self.last_tick = tick
        return self.board_clock

    def heartbeat_time(self, time_us):
        """The virtual time of a HEARTBEAT while no tick comes."""
        if self.last_us is None:
            self.last_us = time_us
        t = self.machine.clock + ((time_us - self.last_us) & 0xFFFFFFFF) * US
        self.last_us = time_us
        return t

    def run_tick(self, m, tick):
        self.ticks += 1
        self.follows = False                  # from here the ticks are the clock
        self.late += time.monotonic() - tick.arrived > 0.002
        m.catch_up(self.board_time(tick["tick"]))
        self.log_script_writes()
        self.results = [r for (r,) in tick["results"]]
        self.at, self.taken, self.writes = 0, 0, []
        self.tick_number = tick["tick"]
        self.in_tick = True
        try:
            m.run_handler(tick["off"])
        finally:
            self.flush_tick_writes(final=True)
            self.in_tick = False
            self.note_answer(tick)
        self.due = self.board_clock + self.period         # the next tick's time, queued or not

    # ------------------------------------------------ a host that is late
    def note_answer(self, tick):
        """The host's own delay answering a tick (its TICK read to the final
        TICK_DONE sent). A board that does not wait for the host (no
        lockstep flag) runs on meanwhile: a delay over HOST_LATE is noted,
        the worst of the last LATE_WINDOW ticks kept."""
        delay = time.monotonic() - tick.arrived
        worst = self.late_answer
        if delay > HOST_LATE and not self.lockstep and (
                worst is None or delay >= worst[0] or self.ticks - worst[2] > LATE_WINDOW):
            self.late_answer = (delay, tick["tick"], self.ticks)

    def explain(self, error):
        """A following error that comes after the host answered a tick
        late is the host's doing, not the motors': say so, with the figure
        (docs/protocol.md section 5). A lost link stays Link lost: a cut
        line is the truth whatever the host did before it."""
        late, self.late_answer = self.late_answer, None
        if late is None or self.ticks - late[2] > LATE_WINDOW \
                or error.message != "Following error":
            return error
        e = ForthError(-293, "Host too slow: answered tick %d after %d ms"
                       % (late[1], round(late[0] * 1000)))
        e.file, e.line = error.file, error.line
        return e

    def log_script_writes(self):
        self.sent_writes.extend((port, value) for op, port, value in self.script
                                if op == P.SCRIPT_OUT)

    def tick_out8(self, port, byte):
        if self.at < len(self.script) and self.script[self.at] == (P.SCRIPT_OUT, port, byte):
            self.at += 1                      # the board did it at the tick
            return
        self.at = len(self.script)            # off the script from here on
        self.writes.append((port, byte))

    def tick_in8(self, port):
        s = self.script
        if self.at < len(s) and s[self.at][0] == P.SCRIPT_IN and s[self.at][1] == port:
            self.at += 1
            self.taken += 1
            return self.results[self.taken - 1]
        self.at = len(s)
        self.flush_tick_writes()
        reply = self.io("IN8", port=port)
        return 0xFF if reply is None else reply["value"] & 0xFF

    def flush_tick_writes(self, final=False):
        """The handler's writes so far, in order, as TICK_DONE frames; the
        last one (final) also tells a lockstep board the handler ended."""
        if not self.in_tick or not (self.writes or final):
            return
        writes, self.writes = self.writes, []
        for i in range(0, max(1, len(writes)), 20):
            part = writes[i:i + 20]
            last = final and i + 20 >= len(writes)
            us = min(0xFFFF, (self.machine.clock - self.board_clock) // US)
            if self.io("TICK_DONE", wait=False, tick=self.tick_number, final=int(last),
                       us=max(0, us), writes=part) is None:
                return
            self.sent_writes.extend(part)

    # -------------------------------------------------------------- safety
    def stop_motors(self):
        if self.pending is not None:              # inside a request (a signal came): no wait
            return self.send(P.frame(0, "SAFE"))
        if not self.lost:
            try:
                self.request("SAFE")
            except (LinkLost, P.LinkError):
                self.lose("no answer to SAFE")

    def tick_failed(self):
        self.in_tick = False
        if not self.lost:
            try:
                self.request("TICK_FAILED")
            except (LinkLost, P.LinkError):
                self.lose("no answer to TICK_FAILED")
        self.due = None

    def status(self):
        state = "lost (%s)" % self.why if self.lost else "up"
        return "link %s: %s, %d ticks, %d skipped, %d resent" % (
            state, self.name, self.ticks, self.skipped, self.retries)


def drain(q):
    while not q.empty():
        q.get_nowait()
