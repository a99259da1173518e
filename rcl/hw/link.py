"""LinkBoard: the host's rcl.board.Board for a board at the other end of a
serial link (any pyserial URL or device, or usb://), speaking the frame
protocol of docs/protocol.md.

    Forth machine --- out8/in8/... ---> LinkBoard --- Request ---> port
                  <-- service: TICK ---     |      <-- reader thread --
                                            |          (frames, NAK, PING)
              session.py  the state machine (CLOSED .. RUNNING .. LOST)
              liveness.py is the board still there (250 ms, 1 s)
              tickreplay.py  what runs per TICK, and TICK_DONE
              lockstep.py    CLOCK and WAIT: simulated boards only

Requests are stop-and-wait: one sequenced frame out (a Request), resent
every RETRY_MS until its ACK or VALUE comes. The reader thread decodes what
the board sends, keeps board frames in order (go-back-N with NAK), sends a
PING when nothing went out for KEEPALIVE_MS, and judges a silent board.

Time: the board's ticks are the clock. `due` is the virtual time of the
next tick (the last tick's board time plus the period); when the machine
gets there, `service` waits for the real TICK, moves the machine's clock to
the board's time (catch_up, never back) and runs INT 1Ch through the
TickReplay.

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
from rcl.hw.connect import close_port
from rcl.hw.inorder import InOrder
from rcl.hw.lockstep import HostTime
from rcl.hw.liveness import Liveness
from rcl.hw.session import Cause, Loss, Request, Session, State
from rcl.hw.tickreplay import TickReplay
from rcl.i80188 import INH, PCB_BASE, T0_CONTROL

US = CLOCK_HZ // 1_000_000
T0_STOPPED = INH             # T0CON: EN off (INH set to write it), INT off: no tick
BACKLOG = 25                 # ticks queued beyond this (the host was away) are counted, not run
REQUEST_GIVE_UP = 1.0        # s of link time with a request unanswered: Link lost (section 3)
WALL_GIVE_UP = 10.0          # s of wall time waited: a request or HELLO given up, whatever the clocks
HELLO_WAIT = 3.0             # seconds to wait for IDENTIFY (a board resetting on open)
RECONNECT_AFTER = 0.5        # a lost link is tried again at most this often
PORT_ERRORS = (serial.SerialException, OSError, TypeError, AttributeError)
S = State


class LinkLost(P.LinkError):
    """The board stopped answering (`loss` says how)."""

    def __init__(self, loss):
        super().__init__(str(loss))
        self.loss = loss


# The link failed our way: the board stopped its tick by its watchdog (section 6)
UNHEARD = ("Link lost: the board heard nothing good from us for its %d ms watchdog; it stopped "
           "the motors and its tick (INSTALL starts it)" % P.WATCHDOG_MS)


def link_lost(loss=None):
    """The running word's error: RCL's two words; the loss, when known,
    in its `why` (the status line says it too)."""
    error = ForthError(-292, "Link lost")
    error.why = str(loss) if loss is not None else None
    return error


class LinkBoard(Board):
    """A board over a link; `open_port()` -> an open pyserial port."""

    def __init__(self, open_port, script=()):
        self.open_port = open_port
        self.session = Session()
        self.replay = TickReplay(script)
        self.port = self.reader = self.pending = self.lockstep = None
        self.lock = threading.Lock()          # one writer on the port at a time
        self.replies = queue.Queue()
        self.events = queue.Queue()           # TICK and HEARTBEAT frames, in order
        self.identify = queue.Queue()
        self.stopping = threading.Event()
        self.live = Liveness()
        self.loss, self.lost_at = None, 0.0
        self.skipped = self.retries = 0
        self.period = self.replay.period = 10_000 * US
        self.ticking = False
        self.ticked = False                   # TICKs came since we last wrote the timer
        self.taken = 0                        # board frames taken in order, each numbered
        self.timer_written = 0                # the number of the answer to that write
        self.silent_for = 0.0                 # s: our longest silence past the board's watchdog
        self.heard_again = 0.0                # when a frame went out after it
        self.sent_writes = []                 # (port, value): every OUT8 the board did for us
        self.bytes_out = self.bytes_in = 0
        self.name = ""
        try:
            self.connect()
        except BaseException:
            self.close()                      # no thread or open port left behind
            raise

    # ------------------------------------------------------- what it is in
    @property
    def lost(self):
        """The board cannot be asked (lost, closed, or not yet identified)."""
        return not self.session.asking

    @property
    def why(self):
        return str(self.loss) if self.loss is not None else ""

    @property
    def ticks(self):
        return self.replay.ticks

    @property
    def late(self):
        return self.replay.late

    @property
    def late_answer(self):
        return self.replay.late_answer

    @property
    def slowest_answer(self):
        """s from a TICK read to its last TICK_DONE sent, the slowest yet."""
        return self.replay.slowest

    @property
    def in_tick(self):
        return self.replay.active

    # ------------------------------------------------------------ session
    def connect(self, reopen=True):
        """Open the port (reopen=False: keep the one open), HELLO until
        IDENTIFY, register the tick script."""
        if reopen:
            self.session.go(S.OPENING)
            try:
                self.port = self.open_port()
            except BaseException:
                self.session.go(S.CLOSED)
                raise
        self.seq, self.pending = 1, None
        self.last_tx, self.silent_for = time.monotonic(), 0.0
        # Silence is judged on the board's own clock where the port can
        # tell it (rclsim://: a board in this process, which a busy host
        # may keep from running), else on the wall clock less our stalls.
        self.live = Liveness(getattr(self.port, "board_seconds", None))
        self.frames = InOrder()               # until IDENTIFY: the last session's, dropped
        for q in (self.replies, self.events, self.identify):
            drain(q)
        self.session.go(S.HELLO_SENT)
        if reopen or not self.reader.is_alive():
            self.stopping.clear()
            self.reader = threading.Thread(target=self.read_loop, daemon=True,
                                           name="rcl-link-reader")
            self.reader.start()
        # (the port kept: a board that only went silent gets what any
        # request gets, not half a second, too little on a loaded machine)
        ident = self.hello(HELLO_WAIT if reopen else REQUEST_GIVE_UP)
        if ident["version"] != P.VERSION:
            self.no_session("The board speaks protocol version %d; this rcl speaks "
                            "version %d. Update the board's firmware or rcl."
                            % (ident["version"], P.VERSION))
            self.close()
            raise P.LinkError(str(self.loss))
        self.name, self.period = ident["name"], ident["tick_us"] * US
        self.replay.period = self.period
        self.replay.new_session()
        # the lockstep extension: only a board that says it is simulated
        self.lockstep = HostTime() if ident["flags"] & P.FLAG_LOCKSTEP else None
        self.loss, self.ticking, self.ticked = None, False, False
        self.session.go(S.IDENTIFIED)
        try:
            self.request("SNAPSHOT", ops=self.replay.script)
        except LinkLost as e:
            self.lose(e.loss, stop=False)
            raise
        self.session.go(S.RUNNING)
        if self.machine is not None:
            if self.lockstep is not None:
                self.lockstep.time_zero = self.machine.clock
            self.due = self.machine.clock      # is it ticking? service finds out
            self.machine.reschedule()

    def hello(self, wait):
        """HELLO every 100 ms until IDENTIFY, for `wait` seconds of this
        process's own time; -> IDENTIFY's values."""
        begun, wall = self.live.host_time(), time.monotonic()
        while self.live.host_time() - begun < wait and time.monotonic() - wall < WALL_GIVE_UP:
            self.send(P.frame(0, "HELLO", version=P.VERSION))
            try:
                ident = self.identify.get(timeout=0.1)
            except queue.Empty:
                if self.session.state is not S.HELLO_SENT or not self.reader.is_alive():
                    break                     # the port failed
                continue
            if "reason" in ident:                 # REFUSED, SEQ 0: no session for us
                raise P.LinkError(self.no_session("The board on %s refused a session: %s"
                                                  % (self.port_name(), ident["reason"])))
            return ident
        raise P.LinkError(self.no_session(
            "No answer from a board on %s (is rcl-board or the firmware running, at "
            "115200 baud?)" % self.port_name()))

    def no_session(self, text):
        """HELLO got no session: the link is lost, for this reason; -> text."""
        if self.session.leave({S.HELLO_SENT}, S.LOST):
            self.loss, self.lost_at = Loss(Cause.NO_SESSION, text), time.monotonic()
        return text

    def port_name(self):
        return getattr(self.port, "portstr", None) or getattr(self.port, "port", "?")

    def close(self):
        """Leaving: a board that still hears is left safe and quiet (SAFE,
        then timer 0 stopped), then the port closed."""
        if self.session.leave({S.RUNNING}, S.LEAVING) and self.machine is not None \
                and self.reader is not threading.current_thread():
            try:
                self.request("SAFE")
                self.request("OUT16", port=PCB_BASE + T0_CONTROL, value=T0_STOPPED)
            except (P.LinkError, serial.SerialException, OSError):
                pass
        self.session.leave({S.HELLO_SENT, S.IDENTIFIED}, S.LOST)
        self.session.leave({S.LEAVING, S.LOST}, S.CLOSED)
        self.stopping.set()
        if self.port is None:
            return
        if self.reader is not None and self.reader is not threading.current_thread():
            self.reader.join(1.0)
        try:
            close_port(self.port)
        except Exception:          # noqa: BLE001  (closing a failed port)
            pass

    def reconnect(self):
        try:
            self.reopen()
        except (P.LinkError, serial.SerialException, OSError) as e:
            self.not_reconnected(e)
            self.due = None
            return "Link lost: %s" % e
        return "Link up: %s, protocol %d" % (self.name, P.VERSION)

    def reopen(self):
        """Connect again: the same port if it still works (the board was
        only silent), else the port opened anew (a closed connection)."""
        failed = (self.loss is not None and self.loss.cause is Cause.PORT) \
            or not getattr(self.port, "is_open", False)
        if failed:
            self.close()
        self.connect(reopen=failed)

    def not_reconnected(self, e):
        """Connecting again failed: the port would not open (CLOSED), or
        the board gave no session on it (LOST)."""
        cause = Cause.PORT if self.session.state is S.CLOSED else Cause.NO_SESSION
        self.loss, self.lost_at = Loss(cause, str(e)), time.monotonic()

    def attach(self, machine):
        super().attach(machine)
        if self.lockstep is not None:
            self.lockstep.time_zero = machine.clock     # HELLO's moment, in the host's time
        self.due = machine.clock
        machine.reschedule()

    # ------------------------------------------------------- reader thread
    def read_loop(self):
        reader = P.FrameReader(P.received_by(P.HOST))    # board types only (section 1)
        while not self.stopping.is_set():
            try:
                data = self.port.read(max(1, self.port.in_waiting))
            except PORT_ERRORS as e:
                self.port_failed(e)
                return
            live = self.live
            at = live.look()                  # everything waiting is read: judge now
            if data:
                self.bytes_in += len(data)
                # no clock: a board may write a frame byte by byte, and a
                # simulated one on a busy machine stall mid-frame (section 1)
                for f in reader.feed(data):
                    self.dispatch(f, live)
            if time.monotonic() - self.last_tx > P.KEEPALIVE_MS / 1000:
                self.send(P.frame(0, "PING"))
            if not self.session.asking:
                continue
            if live.silent(P.LOST_MS / 1000):
                self.lose(Loss(Cause.SILENT, "no frame from the board for %d ms" % P.LOST_MS))
            elif self.frames.gone(at):
                # the board no longer keeps it (section 3): never wait on
                self.lose(Loss(Cause.FRAME_GONE,
                               "board frame %d was not sent again" % self.frames.expected))

    def dispatch(self, f, live):
        """A board frame read: IDENTIFY (or a HELLO refused) for hello(),
        the others in sequence order (inorder.py), asking for a missing
        one again (NAK)."""
        f.arrived = live.looked_at
        live.heard()
        if f.name == "IDENTIFY":
            self.frames.restart()
            drain(self.replies)               # (a HELLO sent again: the session before it)
            drain(self.events)
            self.identify.put(f.values)
            return
        if f.name == "REFUSED" and f.seq == 0:      # a HELLO refused (a busy board)
            self.identify.put(f.values)
            return
        ready, nak = self.frames.take(f, live.at, f.arrived)
        if nak is not None:
            self.send(P.frame(0, "NAK", seq=nak))
        for f in ready:
            self.taken += 1
            f.order = self.taken              # (which came before our last timer write)
            (self.events if f.name in ("TICK", "HEARTBEAT") else self.replies).put(f)

    def send(self, data):
        with self.lock:
            began = time.monotonic()
            try:
                self.port.write(data)
            except PORT_ERRORS as e:
                failed = e
            else:
                self.bytes_out += len(data)
                self.heard_from_us(began, time.monotonic())
                return
        self.port_failed(failed)              # (outside the lock: it sends SAFE)

    def heard_from_us(self, began, ended):
        """A frame was written from `began` to `ended`. A gap from the last
        write's end to this one's start beyond the board's watchdog (this
        whole process stopped: a long garbage collection, a machine that did
        not schedule it) is kept: if the board's tick then stops, that is
        why. A write that waited (the port took no bytes: the board, or the
        line, did not read) is not our silence."""
        if self.kept_silence(began - self.last_tx):
            self.heard_again = ended
        self.last_tx = ended

    def kept_silence(self, gap):
        """A gap of ours beyond the board's watchdog, while running, is
        kept in silent_for; -> whether it was."""
        if gap > P.WATCHDOG_MS / 1000 and self.session.state is S.RUNNING:
            self.silent_for = max(self.silent_for, gap)
            return True
        return False

    def port_failed(self, e):
        loss = Loss(Cause.PORT, "port: %s" % e)
        if self.session.leave({S.HELLO_SENT}, S.LOST):
            self.loss, self.lost_at = loss, time.monotonic()
        else:
            self.lose(loss)

    # ----------------------------------------------------------- requests
    def request(self, name, /, **values):
        """One sequenced frame, resent until answered; -> the answer."""
        self.post(name, **values)
        return self.settle()

    def post(self, name, /, **values):
        """Send a sequenced frame without waiting for its answer (the
        answer to the one before is waited for first: one in flight)."""
        self.settle()
        if not self.session.asking:
            raise LinkLost(self.loss or Loss(Cause.NO_ANSWER, "no answer"))
        data = P.frame(self.seq, name, **values)     # (a frame that cannot be made uses no SEQ)
        seq, self.seq = self.seq, P.following(self.seq)
        now = time.monotonic()
        self.pending = Request(seq, name, data, posted=now, sent_at=now,
                               give_up=self.live.at + REQUEST_GIVE_UP)
        self.send(data)

    def settle(self, block=True):
        """Wait for the answer to the frame in flight, resending it every
        RETRY_MS; -> the answer (None: nothing in flight, or not yet)."""
        while self.pending is not None:
            req = self.pending
            began = time.monotonic()
            try:
                reply = self.replies.get(timeout=P.RETRY_MS / 1000 if block else 0)
            except queue.Empty:
                req.waited += time.monotonic() - began
                if self.unanswered(req):
                    self.pending = None
                    raise LinkLost(self.loss or Loss(Cause.NO_ANSWER, "no answer")) from None
                if time.monotonic() - req.sent_at >= P.RETRY_MS / 1000:
                    req.retries += 1
                    self.retries += 1
                    req.sent_at = time.monotonic()
                    self.send(req.data)
                if not block:
                    return None
                continue
            if reply["ack"] == req.seq:
                req.reply, self.pending = reply, None
                if reply.name == "REFUSED":
                    raise P.LinkError("The board refused %s: %s" % (req.name, reply["reason"]))
                return reply
        return None

    def unanswered(self, req):
        """Give the request up: the link is lost, or its second of link
        time has passed as of the reader's last read (a host that was not
        run meanwhile has its answer waiting unread), or the reader no
        longer reads at all, or it was waited for WALL_GIVE_UP in all (a
        lockstep board's time may stand still: no wait runs for ever)."""
        return not self.session.asking or self.live.at > req.give_up \
            or not self.reader.is_alive() or req.waited > WALL_GIVE_UP

    def lose(self, loss, stop=True):
        """The link is gone: say so once, stop the running word."""
        m = self.machine

        def stop_first():
            # Before the state says LOST: the running word, finding the link
            # lost (a tick wait, a request), must find its stop already asked
            # for. Else, the reader thread losing, the word could run on 100
            # HALTs with no board (Control loop stalled) before it is.
            self.loss, self.lost_at = loss, time.monotonic()
            if stop and m is not None and (m.in_forth or m.masked):
                m.request_stop(link_lost(loss))
        if self.session.leave({S.IDENTIFIED, S.RUNNING, S.LEAVING}, S.LOST, first=stop_first):
            self.send(P.frame(self.seq, "SAFE"))       # if the board still hears
        self.due = None

    def usable(self):
        """True when the link is up. A lost link is tried again, at most
        every RECONNECT_AFTER seconds: the abort that follows the loss
        (its safe-state relay writes) finds it quietly unusable; any other
        request finds it reconnected, or is stopped with Link lost (a read
        on a lost link has no true answer to give)."""
        if self.session.asking:
            return True
        if self.replay.active or self.machine.in_safe_state:
            return False
        if time.monotonic() - self.lost_at < RECONNECT_AFTER:
            self.machine.request_stop(link_lost(self.loss))
            return False
        self.lost_at = time.monotonic()
        try:
            self.reopen()
        except (P.LinkError, serial.SerialException, OSError) as e:
            self.not_reconnected(e)
            self.machine.request_stop(link_lost(self.loss))   # taken at the next primitive boundary
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
            self.lose(e.loss)
            return None

    def tell_time(self):
        """The lockstep extension (simulated boards only): a board whose
        timer does not tick keeps the host's time; before a port or memory
        access, tell it how far the host has come (CLOCK), so the access
        lands where the simulation has it."""
        if self.lockstep is None or self.replay.active or self.machine is None:
            return
        us = self.lockstep.clock_us(self.machine.clock)
        if us is not None:
            self.post("CLOCK", us=us)

    def tick_reads(self, ops):
        """What the software's tick handler reads first (RCL's counter
        words say it): the board does it at every tick and sends the bytes
        with the TICK, so a tick costs no round trip. Kept for the next
        connect."""
        ops = [tuple(op) for op in ops]
        if ops == self.replay.script:         # this session has it already
            return
        self.replay.script = ops
        if not self.usable():
            return
        try:                                  # not a port access: no CLOCK before it, so
            self.request("SNAPSHOT", ops=ops)   # a lockstep board's time moves as before
        except LinkLost as e:
            self.lose(e.loss)

    # ------------------------------------------------------------ port I/O
    def out8(self, port, byte):
        if self.replay.active:
            return self.replay.out8(port, byte)
        if self.io("OUT8", port=port, value=byte) is not None:
            self.sent_writes.append((port, byte))

    def in8(self, port):
        if self.replay.active:
            value = self.replay.in8(port)
            if value is not None:
                return value
            self.flush_tick_writes()          # off the script: the board is asked
        reply = self.io("IN8", port=port)
        return 0xFF if reply is None else reply["value"] & 0xFF

    def out16(self, port, word):
        if port < PCB_BASE:
            return super().out16(port, word)
        self.flush_tick_writes()
        reply = self.io("OUT16", port=port, value=word)
        self.silent_for = 0.0                 # a stop from here on is our own
        self.timer_was_written(reply)
        if not self.replay.active and not self.lost:
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
        if self.replay.active:
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
        following = self.lockstep is not None and self.lockstep.follows
        if following:
            try:
                self.tell_time()
                self.settle()
            except LinkLost as e:
                self.lose(e.loss)
                return
        while True:
            event = self.next_event(block=self.ticking and not following)
            if event is None:
                if self.session.asking:
                    self.due = m.clock + self.period
                return
            if event.name == "TICK":
                self.ticking = True
                self.ticked = self.ticked or event.order > self.timer_written
                return self.run_tick(m, event)
            if event.order < self.timer_written:
                continue      # sent before the board took our last timer write: old news
            if self.ticking and not event["ticking"] and self.silent_now():
                return self.watchdog_tripped(m)
            if self.ticked and not event["ticking"]:
                return self.tick_stopped_unasked(m)
            self.ticking = bool(event["ticking"])
            if not self.ticking and self.lockstep is not None:
                self.lockstep.follows = following = True   # the board keeps our time again
            elif not self.ticking:
                m.catch_up(self.replay.heartbeat_time(event["time_us"], m.clock, US))

    def watchdog_tripped(self, m):
        """The board stopped its tick unasked after we were silent past
        its watchdog (docs/protocol.md section 6): it has gone quiet, motors
        off. Say so, with the figure, rather than wait for ticks that will
        not come (the running word would end Control loop stalled)."""
        self.ticking, self.due = False, None
        m.request_stop(self.silence_error())

    def silent_now(self):
        """Our silence past the board's watchdog: one a write has ended
        (silent_for), or one not yet ended, nothing sent since (this
        process was stopped, and the board's news is read first)."""
        self.kept_silence(time.monotonic() - self.last_tx)
        return self.silent_for

    def timer_was_written(self, reply):
        """We wrote the timer (reply: the board's answer, if any): a stop
        from here on may be our own, and the TICKs the board sent before
        its answer (still queued) are no sign that it ticks since."""
        self.ticked = False
        self.timer_written = getattr(reply, "order", self.taken)

    def tick_stopped_unasked(self, m):
        """The board stopped a running tick that we neither stopped nor left
        silent past its watchdog: what we sent did not reach it for 250 ms
        (a line that drops or holds our frames; docs/protocol.md section
        6). Say so now, rather than wait out 100 HALTs (Control loop
        stalled): the link failed, our way."""
        self.ticking = self.ticked = False
        self.due = None
        m.request_stop(ForthError(-292, UNHEARD))

    def silence_error(self):
        """The board's watchdog tripped by our silence (silent_for): the
        error to report, with the figure; the silence is then told."""
        silent, self.silent_for = self.silent_for, 0.0
        return ForthError(
            -293, "Host too slow: silent %d ms, past the board's %d ms watchdog; the board "
            "stopped the motors and its tick (INSTALL starts it)"
            % (round(silent * 1000), P.WATCHDOG_MS))

    def next_event(self, block):
        """The next TICK or HEARTBEAT (None: none waiting, when not to
        block); a backlog beyond BACKLOG ticks (the host was away, at the
        prompt) is counted, not run. Only TICKs count: a board that waits
        for our answer sends HEARTBEATs meanwhile (the native board one
        every 10 ms), and a host slow on one tick is not 25 ticks behind."""
        if self.events.qsize() <= BACKLOG:   # (no more frames than that: no more ticks; each tick)
            ticks = 0
        else:
            with self.events.mutex:
                ticks = sum(f.name == "TICK" for f in self.events.queue)
        while ticks > BACKLOG:
            f = self.events.get()
            if f.name == "TICK":
                ticks -= 1
                self.skipped += 1
                self.sent_writes.extend(self.replay.script_writes())
        waited = 0.0
        # a lockstep board waits for our WAIT: look often; a free-running
        # one ticks on its own: wake only to resend a lost TICK_DONE
        poll = 0.002 if self.lockstep is not None or not block else P.RETRY_MS / 2000
        try:
            while True:
                try:
                    return self.events.get(timeout=poll)
                except queue.Empty:
                    self.settle(block=False)      # the last TICK_DONE, resent if lost
                    if not block:
                        return None
                    if self.lockstep is not None and time.monotonic() - waited > P.RETRY_MS / 1000:
                        waited = time.monotonic()
                        self.send(P.frame(0, "WAIT", tick=self.replay.next_tick()))
                    # Silence is the reader thread's to judge, after it has
                    # read what waits: a process that was not scheduled for a
                    # while would find the last frame old here with frames unread.
                    if self.lost:
                        raise LinkLost(self.loss or Loss(Cause.NO_ANSWER, "no tick")) from None
        except LinkLost as e:
            self.lose(e.loss)
            return None

    def run_tick(self, m, tick):
        """One TICK: the machine's time to the tick's, then its handler,
        replayed (tickreplay.py), its writes sent as TICK_DONE."""
        replay = self.replay
        if self.silent_for and tick.arrived > self.heard_again + P.WATCHDOG_MS / 1000:
            self.silent_for = 0.0             # the board ticked on past our silence: no trip
        if self.lockstep is not None:
            self.lockstep.follows = False     # from here the ticks are the clock
        m.catch_up(replay.board_time(tick["tick"], m.clock))
        self.sent_writes.extend(replay.script_writes())
        replay.begin(tick)
        try:
            m.run_handler(tick["off"])
        finally:
            self.flush_tick_writes(final=True)
            replay.end(tick, self.lockstep is not None)
        self.due = replay.next_due()          # the next tick's time, queued or not

    def flush_tick_writes(self, final=False):
        """The handler's writes so far, in order, as TICK_DONE frames; the
        last one (final) also tells a lockstep board the handler ended."""
        replay = self.replay
        if not replay.active or not (replay.writes or final):
            return
        us = max(0, min(0xFFFF, (self.machine.clock - replay.board_clock) // US))
        for values in replay.done_frames(final, us):
            if self.io("TICK_DONE", wait=False, **values) is None:
                return
            self.sent_writes.extend(values["writes"])

    def explain(self, error):
        """A following error that comes after the host answered a tick
        late is the host's doing, not the motors': say so, with the figure
        (docs/protocol.md section 5). A lost link stays Link lost: a cut
        line is the truth whatever the host did before it."""
        lost = self.machine.stop_error if self.machine is not None else None
        if lost is not None and lost is not error:
            # the link went while a word failed of it (a read gave 0xFF):
            # the link is the cause to report
            lost.file, lost.line = error.file, error.line
            return lost
        if error.message.startswith("Control loop not running") and (self.silent_for or self.ticked):
            # the board stopped its tick itself, its watchdog tripped: by our
            # silence, or (a tick ran since our last timer write, and we
            # were not silent) by a line that did not carry our frames, as
            # tick_stopped_unasked says when its HEARTBEAT is read first.
            # Say that, not "INSTALL starts it" (nobody stopped it).
            if self.silent_for:
                e = self.silence_error()
            else:
                self.ticking = self.ticked = False
                e = ForthError(-292, UNHEARD)
            e.file, e.line = error.file, error.line
            return e
        late = self.replay.take_late()
        if late is None or error.message != "Following error":
            return error
        e = ForthError(-293, "Host too slow: answered tick %d after %d ms"
                       % (late[1], round(late[0] * 1000)))
        e.file, e.line = error.file, error.line
        return e

    # -------------------------------------------------------------- safety
    def stop_motors(self):
        if self.pending is not None:              # inside a request (a signal came): no wait
            return self.send(P.frame(0, "SAFE"))
        if not self.lost:
            try:
                self.request("SAFE")
            except P.LinkError:
                self.lose(Loss(Cause.NO_ANSWER, "no answer to SAFE"))

    def tick_failed(self):
        self.replay.active = False
        reply = None
        if not self.lost:
            try:
                reply = self.request("TICK_FAILED")
            except P.LinkError:
                self.lose(Loss(Cause.NO_ANSWER, "no answer to TICK_FAILED"))
        self.timer_was_written(reply)
        self.due = None

    def status(self):
        state = self.session.state.value
        if self.lost and self.loss is not None:
            state = "lost (%s)" % self.loss
        return "link %s: %s, %d ticks, %d skipped, %d resent" % (
            state, self.name, self.ticks, self.skipped, self.retries)


def drain(q):
    while not q.empty():
        q.get_nowait()
