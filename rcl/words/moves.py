"""Which word moved the robot: the move log and .MOVES.

Every move is recorded from the moment it is commanded, the latch write
that turns its motor on, to the write that turns it off: a base move the
MOTOR latch's GO bits (the same bits rcl.track finds a move by in a
trace), an arm or gripper move the AUX latch's ARM-ON and GRIP-ON.

    PC! to the latch, a motor bit rises         PC!, the bits clear
      |  chain: the words running (return         |  end: time, pose, how
      |  stack and compiled frames, wordloc)      |  (done, following error,
      |  RCL's own numbers: END-AT ACC-AT         |   at its limit, stopped
      |  DEC-AT TOP-SPEED SPEED-V4 PENDING        |   by an error or Ctrl-C)
      v  ARM-BUDGET; the board's pose and time    v
    MoveLog: the last LOG_SIZE moves (a deque), numbered from the start

Nothing here computes a distance or a speed: the numbers are RCL's
variables as (MOVE) and (ARM-MOVE) left them for the control loop, read
when the move starts; the pose is the board's observation (Board.pose;
None on a board that cannot see the robot, and then the record has no
pose). The chain is cut where RCL's command word hands the move to its
runner, so it reads `TRIP > TURN-LEFT > LEFT`, not `... > (MOVE) > GO >
ENABLE > LATCH`.

While a trace is recorded (TRACE-ON, --trace) each base move's start and
label also go to `MoveLog.marks`, which the trace's `word` column and the
plot's labels are made from (rcl.words.tracing).
"""
import collections
import os
import sys

from rcl.board import CLOCK_HZ
from rcl.forth import state, wordloc
from rcl.forth.memory import MASK, dsigned, signed
from rcl.forth.primitives import CALL, prim
from rcl.robot import (ARM_DOWN, ARM_ON, AUX_PORT, GRIP_CLOSE, GRIP_ON, M1_GO, M1_REV,
                       M2_GO, M2_REV, MOTOR_PORT)

LOG_SIZE = 1000              # moves kept (MAILBOT's day makes thousands)
SHOWN = 20                   # moves .MOVES lists
MOTOR_BITS = {MOTOR_PORT: M1_GO | M2_GO, AUX_PORT: ARM_ON | GRIP_ON}
RUNNERS = ("(MOVE)", "(ARM-MOVE)")          # RCL's words that run a command's move
RELAY_WORDS = ("GO", "ENABLE", "LATCH")     # layer 1: a move made by hand ends here
DISTANCE_UNITS = {1: "INCHES", 2: "FEET", 3: "MILES", 4: "DEGREES"}
SPEED_UNITS = {1: "MPH", 2: "IPS", 3: "FPS", 4: "FPM"}
# RCL's command numbers (LAST-DISTANCE's), by the relay bits that run them
COMMANDS = ("forward", "backward", "left", "right", "up", "down", "open", "close")
BASE_WAYS = {0: "forward", M1_REV | M2_REV: "backward", M1_REV: "left", M2_REV: "right"}
ARM_WAYS = {ARM_ON: "up", ARM_ON | ARM_DOWN: "down", GRIP_ON: "open",
            GRIP_ON | GRIP_CLOSE: "close"}


class Move:
    """One move, as plain data: what commanded it, RCL's numbers, the ends."""

    def __init__(self, number, chain, where):
        self.number = number
        self.chain = chain            # names, outermost first
        self.where = where            # (file, line) in the outermost word, or None
        self.direction = None         # forward backward left right up down open close
        self.counts = self.acc_at = self.dec_at = self.top_crpm = None   # a base move
        self.ticks = None                      # an arm move: ticks it may run
        self.speed = self.distance = None      # (V4, unit name) as RCL keeps them
        self.start = self.end = None           # (clock s, BIOS ticks, per day, pose or None)
        self.how = None                        # None while it runs

    @property
    def label(self):
        return " > ".join(self.chain) or "?"

    @property
    def base(self):
        return self.direction in BASE_WAYS.values()

    def __repr__(self):
        return "Move(%d, %r)" % (self.number, self.label)


class MoveLog:
    def __init__(self, size=LOG_SIZE):
        self.moves = collections.deque(maxlen=size)
        self.count = 0
        self.open = {}                # latch port -> the move it runs
        self.marks = None             # [(clock s, label)] of base moves while a trace records

    def latched(self, m, port, byte):
        """A latch was written with byte: a move starts or ends."""
        going = byte & MOTOR_BITS[port]
        if going and port not in self.open:
            self.started(m, port, byte)
        elif not going and port in self.open:
            self.ended(m, port)

    def started(self, m, port, byte):
        self.count += 1
        chain, where = commanding_chain(m)
        mv = Move(self.count, chain, where)
        if port == MOTOR_PORT:
            mv.direction = BASE_WAYS.get(byte & (M1_REV | M2_REV))
            read_base_numbers(m, mv)
        else:
            mv.direction = ARM_WAYS.get(byte & (ARM_ON | ARM_DOWN | GRIP_ON | GRIP_CLOSE))
            mv.ticks = variable(m, "ARM-BUDGET")
        mv.distance = given_distance(m, mv)
        mv.start = observe(m)
        self.open[port] = mv
        self.moves.append(mv)
        if self.marks is not None and port == MOTOR_PORT:
            self.marks.append((mv.start[0], mv.label))

    def ended(self, m, port):
        mv = self.open.pop(port)
        mv.end = observe(m)
        if m.in_safe_state:
            mv.how = "stopped"
        elif port == MOTOR_PORT:
            mv.how = {1: "following error, left", 2: "following error, right"}.get(
                variable(m, "FERR"), "done")
        else:                           # ARM-TICK: the ticks ran out, or the limit
            mv.how = "at its limit" if variable(m, "ARM-BUDGET") else "done"


state.session("moves", lambda m: MoveLog())


# ------------------------------------------------------------ reading
def body(m, name):
    hit = m.dictionary.find(name)
    return None if hit is None else (hit[0] + 2) & MASK


def variable(m, name, double=False):
    """A Forth variable's value (signed), or None if there is no such word."""
    a = body(m, name)
    if a is None:
        return None
    if double:                                  # 2! keeps the high cell first
        return dsigned((m.memory.fetch(a) << 16) | m.memory.fetch((a + 2) & MASK))
    return signed(m.memory.fetch(a))


def read_base_numbers(m, mv):
    """What RCL computed for a base move, from its variables."""
    mv.counts = variable(m, "END-AT", True)
    mv.acc_at = variable(m, "ACC-AT", True)
    mv.dec_at = variable(m, "DEC-AT", True)
    mv.top_crpm = variable(m, "TOP-SPEED")
    v4, unit = variable(m, "SPEED-V4", True), variable(m, "SPEED-UNIT")
    if v4 is not None:
        mv.speed = (v4, SPEED_UNITS.get(unit, "?"))


def given_distance(m, mv):
    """(V4, unit) of the distance the command took: PENDING holds its V4
    (its unit is cleared once taken), and the command's LAST-DISTANCE entry
    (V4 then unit, 6 bytes a command) the same V4 with its unit."""
    pending, lasts = variable(m, "PENDING", True), body(m, "LASTS")
    if pending is None or lasts is None or mv.direction is None:
        return None
    cmd = COMMANDS.index(mv.direction)
    for c in (cmd, cmd ^ 1):                    # a negative distance goes the other way
        a = (lasts + 6 * c) & MASK
        v4 = dsigned((m.memory.fetch(a) << 16) | m.memory.fetch((a + 2) & MASK))
        if abs(v4) == abs(pending):             # shown as the way it went
            return abs(v4), DISTANCE_UNITS.get(m.memory.fetch((a + 4) & MASK), "?")
    return None


def observe(m):
    """(virtual seconds, BIOS ticks, ticks a day, pose) now; on a board
    that cannot see the robot (pose None: a board over a link, where the
    time of day is eight round trips away, too slow inside a tick) the
    ticks are None too."""
    pose = m.board.pose()
    ticks, per_day = m.board.time_of_day() if pose is not None else (None, None)
    return m.clock / CLOCK_HZ, ticks, per_day, pose


# --------------------------------------------------------------- chain
class Frame:
    """A Python frame as wordloc.activations reads a traceback entry."""
    __slots__ = ("tb_frame", "tb_lineno", "tb_next")

    def __init__(self, frame, nxt):
        self.tb_frame, self.tb_lineno, self.tb_next = frame, frame.f_lineno, nxt


def python_stack():
    """The running Python frames as a traceback chain, outermost first."""
    tb, f = None, sys._getframe(1)
    while f is not None:
        tb, f = Frame(f, tb), f.f_back
    return tb


def commanding_chain(m):
    """(names outermost first, (file, line) of the outermost word's call
    of the next) of the words running now, cut where a command hands its
    move on."""
    try:
        frames = wordloc.backtrace(m, m.rs, python_stack())[::-1]
    except Exception:                           # a broken dictionary: no chain
        return (), None
    names = [f[0] for f in frames]
    cut = next((i for i, n in enumerate(names) if n in RUNNERS), None)
    if cut is None:
        cut = next((i for i, n in enumerate(names) if n in RELAY_WORDS), len(names))
    kept = frames[:cut]
    # the outermost word's line that led to the move (TRIP's, not AHEAD's)
    where = kept[0][1:] if len(kept) > 1 and kept[0][1] else None
    return tuple(f[0] for f in kept), where


# --------------------------------------------------------------- .MOVES
def clock_text(seconds, ticks, per_day):
    """The time of day, or without it the seconds since the machine started."""
    if ticks is None:
        return "t %.2f s" % seconds
    s = ticks * 86400 / per_day
    return "%02d:%02d:%05.2f" % (s // 3600 % 24, s // 60 % 60, s % 60)


def pose_text(pose):
    return "x %.2f y %.2f in heading %.1f" % (pose[0], pose[1], round(pose[2], 1) % 360 + 0.0)


def v4_text(v4):
    sign, v4 = ("-" if v4 < 0 else ""), abs(v4)
    text = ("%d.%04d" % divmod(v4, 10000)).rstrip("0").rstrip(".")
    return sign + text


def describe(mv):
    """Two lines (three with a pose) about a move, as .MOVES shows it."""
    head = "%4d %s" % (mv.number, mv.label)
    if mv.where:
        head += "  (%s:%s)" % (os.path.basename(mv.where[0]), mv.where[1])
    parts = []
    if mv.distance:
        parts.append("%s %s %s" % (v4_text(mv.distance[0]), mv.distance[1], mv.direction))
    elif mv.direction:
        parts.append(mv.direction)
    if mv.counts is not None:
        parts.append("%d counts a wheel" % mv.counts)
    if mv.ticks is not None:
        parts.append("%d ticks at most" % mv.ticks)
    if mv.speed:
        parts.append("at %s %s (%s crpm)" % (v4_text(mv.speed[0]), mv.speed[1], mv.top_crpm))
    if mv.acc_at is not None:
        parts.append("breakpoints %d %d" % (mv.acc_at, mv.dec_at))
    lines = [head, "       " + ", ".join(parts)]
    t0, pose0 = mv.start[0], mv.start[3]
    when = "       " + clock_text(*mv.start[:3])
    if mv.end is not None:
        when += " to %s (%.2f s), %s" % (clock_text(*mv.end[:3]), mv.end[0] - t0, mv.how)
    else:
        when += ", under way"
    lines.append(when)
    if pose0 is not None:
        to = mv.end[3] if mv.end is not None else None
        lines.append("       %s%s" % (pose_text(pose0), " -> " + pose_text(to) if to else ""))
    return "\n".join(lines)


@prim(".MOVES", "( -- ) the last 20 moves (1000 are kept): the words that commanded "
      "each, its distance, speed, breakpoints, times and poses", kind=CALL)
def dot_moves(m):
    log = m.moves
    shown = list(log.moves)[-SHOWN:]
    if not shown:
        m.type("\nNo moves yet\n")
        return
    earlier = log.count - len(shown)
    text = "\n".join(describe(mv) for mv in shown)
    note = "\n(%d earlier moves not shown)" % earlier if earlier else ""
    m.type("\n" + text + note + "\n")
