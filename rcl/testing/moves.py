"""What the robot did, as its relays saw it: the moves a failing test's
report lists (rcl.testing's robots keep them; any SimBoard can).

    MOTOR latch  GO bits on ............................ GO bits off
                 |<- one base move: direction from the REV relays ->|
    AUX latch    ARM-ON / GRIP-ON on ..................... off
                 |<- one arm or gripper move: UP DOWN OPEN CLOSE  ->|

Each move keeps its start and end time, wheel counts, pose, arm height
and jaw opening, read from the simulated board when the latch is written
(the board brings its physics up to that instant first).
"""
import collections
from dataclasses import dataclass

from rcl.forth.primitives import CLOCK_HZ
from rcl.sim import constants as C
from rcl.sim.board import SimBoard

# (left reverse?, right reverse?) -> the command that sets the relays so
# (CW, turning right, runs the left wheel forward and the right in reverse).
BASE_MOVES = {(False, False): "FORWARD", (True, True): "BACKWARD",
              (True, False): "LEFT", (False, True): "RIGHT"}
GO = C.M1_GO | C.M2_GO


@dataclass
class Snapshot:
    """The robot at one instant."""
    seconds: float
    pose: tuple
    counts: tuple
    arm: float
    jaw: float

    @classmethod
    def of(cls, board):
        d, r = board.drive, board.drive.robot
        return cls(board.machine.clock / CLOCK_HZ, (r.x, r.y, r.heading),
                   (d.left.position, d.right.position), d.lift.position,
                   d.gripper.opening)


@dataclass
class Move:
    what: str                 # FORWARD BACKWARD LEFT RIGHT UP DOWN OPEN CLOSE
    start: Snapshot
    end: Snapshot = None      # None while it runs

    def describe(self):
        end = self.end
        span = "%7.2f -%s s" % (self.start.seconds,
                                "%7.2f" % end.seconds if end else " (running)")
        if end is None:
            return "%-8s %s" % (self.what, span)
        if self.what in ("UP", "DOWN"):
            return "%-8s %s  arm %.2f -> %.2f in" % (self.what, span, self.start.arm, end.arm)
        if self.what in ("OPEN", "CLOSE"):
            return "%-8s %s  jaw %.2f -> %.2f in" % (self.what, span, self.start.jaw, end.jaw)
        (l0, r0), (l1, r1) = self.start.counts, end.counts
        return "%-8s %s  counts left %+d right %+d  %s -> %s" % (
            self.what, span, l1 - l0, r1 - r0, pose_text(self.start.pose), pose_text(end.pose))


def pose_text(pose):
    x, y, heading = pose
    return "(%.2f, %.2f, %.2f deg)" % (x, y, wrap(heading))


def wrap(degrees):
    """A heading in -180 (inclusive) to 180 degrees: the simulator counts
    whole turns, a compass does not."""
    return (degrees + 180.0) % 360.0 - 180.0


class MoveLog:
    """The last `keep` moves, oldest first, with those still running."""

    def __init__(self, keep=8):
        self.moves = collections.deque(maxlen=keep)
        self.running = {}             # "base" / "arm" / "grip" -> Move

    def latch(self, board, kind, what):
        """The latch for `kind` now says `what` (None: that motor is off)."""
        move = self.running.get(kind)
        # A wheel that arrives first stops alone: the base move goes on
        # until both GO bits are off, whatever the other REV relay says.
        if move is not None and what is not None and (kind == "base" or move.what == what):
            return
        snap = Snapshot.of(board)
        if move is not None:
            move.end = snap
            del self.running[kind]
        if what is not None:
            self.running[kind] = Move(what, snap)
            self.moves.append(self.running[kind])

    def describe(self):
        return [move.describe() for move in self.moves]


def base_move(latch):
    if not latch & GO:
        return None
    return BASE_MOVES[(bool(latch & C.M1_REV), bool(latch & C.M2_REV))]


def aux_moves(latch):
    arm = ("DOWN" if latch & C.ARM_DOWN else "UP") if latch & C.ARM_ON else None
    grip = ("CLOSE" if latch & C.GRIP_CLOSE else "OPEN") if latch & C.GRIP_ON else None
    return arm, grip


class RecordingBoard(SimBoard):
    """A SimBoard that remembers its last moves in `moves` (a MoveLog)."""

    def __init__(self, keep=8):
        super().__init__()
        self.moves = MoveLog(keep)

    def out8(self, port, byte):
        super().out8(port, byte)
        if port == C.MOTOR_PORT:
            self.moves.latch(self, "base", base_move(byte))
        elif port == C.AUX_PORT:
            arm, grip = aux_moves(byte)
            self.moves.latch(self, "arm", arm)
            self.moves.latch(self, "grip", grip)

    def stop_motors(self):
        super().stop_motors()
        for kind in list(self.moves.running):
            self.moves.latch(self, kind, None)
