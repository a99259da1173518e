"""The tick on a link: what the host runs for each TICK, and the TICK /
TICK_DONE exchange (docs/protocol.md sections 4 and 5).

    board: timer 0 ticks -> the SNAPSHOT script (the handler's first port
           operations) -> TICK(tick, off, results)
    host:  TickReplay.begin(TICK) -> the Forth handler at `off` runs; its
           port operations come here first:
             on the script, in order  -> served from the TICK: no round trip
             off the script            -> writes queued, reads asked of the board
           -> TICK_DONE frames (at most 19 writes each; the last `final`)

The script is what the software registered (Board.tick_reads): this
module knows no port and no RCL word, only that the handler starts with
those operations. It also keeps the tick numbers' time (tick n is n
periods after the first tick seen, the number wrapping at 2**16) and the
host's own delay answering a tick (` Host too slow `, section 5).
"""
import time

from rcl.hw import protocol as P

# TICK_DONE's writes a frame: 3 bytes each after tick, final and us (5
# bytes), within MAX_PAYLOAD: 19 (20 made a 65-byte payload, refused)
WRITES_PER_FRAME = (P.MAX_PAYLOAD - 5) // 3
# A tick answered later than HOST_LATE is noted: 10 ticks in which RCL's
# control did not act, at 2 MPH its whole 100-count following limit
HOST_LATE = 0.100
LATE_WINDOW = 100        # ticks: a late answer this recent explains the error after it


class TickReplay:
    def __init__(self, script=()):
        self.script = [tuple(op) for op in script]
        self.active = False              # inside a tick's handler
        self.number = None               # the tick being run (its TICK's number)
        self.results, self.at, self.taken, self.writes = [], 0, 0, []
        self.board_clock = None          # virtual time of the last tick
        self.last_tick = None
        self.last_us = None              # HEARTBEAT's time_us, while no tick comes
        self.ticks = self.late = 0       # ticks run; run more than 2 ms after they came
        self.late_answer = None          # (delay s, tick, ticks): the worst recent
        self.slowest = 0.0               # s, the slowest answer since the link opened

    def new_session(self):
        """IDENTIFY: tick numbers and times start again (the script stays:
        it is the software's, registered anew with SNAPSHOT)."""
        self.board_clock = self.last_tick = self.last_us = None
        self.active = False

    # ------------------------------------------------------------ time
    def board_time(self, tick, now):
        """The virtual time of tick number `tick`, ticks a period apart
        (`now`: the host's time, where the first tick seen is put)."""
        if self.board_clock is None:
            self.board_clock, self.last_tick = now, tick
        self.board_clock += ((tick - self.last_tick) & 0xFFFF) * self.period
        self.last_tick = tick
        return self.board_clock

    def heartbeat_time(self, time_us, now, us):
        """The virtual time of a HEARTBEAT while no tick comes."""
        if self.last_us is None:
            self.last_us = time_us
        t = now + ((time_us - self.last_us) & 0xFFFFFFFF) * us
        self.last_us = time_us
        return t

    def next_tick(self):
        """The number of the tick waited for (0xFFFF: not known yet)."""
        return 0xFFFF if self.board_clock is None else (self.last_tick + 1) & 0xFFFF

    def next_due(self):
        return self.board_clock + self.period

    # ------------------------------------------------------- one tick
    def begin(self, tick):
        """A TICK frame's handler starts: its script results to serve."""
        self.ticks += 1
        self.late += time.monotonic() - tick.arrived > 0.002
        self.results = [r for (r,) in tick["results"]]
        self.at, self.taken, self.writes = 0, 0, []
        self.number = tick["tick"]
        self.active = True

    def end(self, tick, lockstep):
        self.active = False
        self.note_answer(tick, lockstep)

    def out8(self, port, byte):
        """The handler writes: done by the board at the tick if the script
        has it here, else queued for TICK_DONE."""
        s = self.script
        if self.at < len(s) and s[self.at] == (P.SCRIPT_OUT, port, byte):
            self.at += 1
            return
        self.at = len(s)                 # off the script from here on
        self.writes.append((port, byte))

    def in8(self, port):
        """The handler reads: -> the byte from the TICK, or None when the
        script does not have this read here (the board must be asked)."""
        s = self.script
        if self.at < len(s) and s[self.at][0] == P.SCRIPT_IN and s[self.at][1] == port:
            self.at += 1
            self.taken += 1
            return self.results[self.taken - 1]
        self.at = len(s)
        return None

    def script_writes(self):
        """The writes the board does itself at every tick (the script's OUTs)."""
        return [(port, value) for op, port, value in self.script if op == P.SCRIPT_OUT]

    def done_frames(self, final, us):
        """The handler's writes so far as TICK_DONE values, in order, and
        forgotten here; the last one says `final` (the handler ended)."""
        writes, self.writes = self.writes, []
        frames = []
        for i in range(0, max(1, len(writes)), WRITES_PER_FRAME):
            part = writes[i:i + WRITES_PER_FRAME]
            last = final and i + WRITES_PER_FRAME >= len(writes)
            frames.append(dict(tick=self.number, final=int(last), us=us, writes=part))
        return frames

    # ------------------------------------------------- a host that is late
    def note_answer(self, tick, lockstep):
        """The host's own delay answering a tick (its TICK read to the final
        TICK_DONE sent). A board that does not wait for the host (no
        lockstep flag) runs on meanwhile: a delay over HOST_LATE is noted,
        the worst of the last LATE_WINDOW ticks kept."""
        delay = time.monotonic() - tick.arrived
        self.slowest = max(self.slowest, delay)
        worst = self.late_answer
        if delay > HOST_LATE and not lockstep and (
                worst is None or delay >= worst[0] or self.ticks - worst[2] > LATE_WINDOW):
            self.late_answer = (delay, tick["tick"], self.ticks)

    def take_late(self):
        """-> (delay s, tick) of a late answer recent enough to explain an
        error now, or None; forgotten either way."""
        late, self.late_answer = self.late_answer, None
        if late is None or self.ticks - late[2] > LATE_WINDOW:
            return None
        return late[:2]
