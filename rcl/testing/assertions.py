"""Robot assertions: where the robot is, its wheel counts, arm and jaw,
following error, motors, time of day, in inches, degrees and seconds.

    assert_pose(robot, x=0.18, y=0.26, heading=-0.82, inches=0.1, degrees=0.3)

Each takes a machine from rcl.open() (or rcl.testing.robot()) and raises
AssertionError saying what was expected and what the robot did: its pose,
wheel counts, arm, relays, following error and, for robots made by
rcl.testing, the last moves. Pose and wheel counts are read once the
wheels have rolled to rest (a move returns as its relays open; the wheels
run on a count or so, mostly in the first 0.1 s, which can turn the robot
by tenths of a degree): pass settle=False to look at once.
"""
import re

from rcl.forth.memory import MASK, signed
from rcl import robot as C
from rcl.testing.moves import pose_text, wrap

SETTLE_LIMIT_S = 2.0          # a braked wheel's rate reaches 0 in ~0.9 s
SETTLE_STEP_S = 0.01          # one RCL tick
DRIVING = (C.M1_GO | C.M2_GO, C.ARM_ON | C.GRIP_ON)


# ------------------------------------------------------------ looking
def variable(m, name):
    """The value of a Forth VARIABLE, signed, or None if it is not defined
    (read from memory, so the data stack is left alone)."""
    hit = m.dictionary.find(name)
    if hit is None:
        return None
    return signed(m.memory.fetch((hit[0] + 2) & MASK))


def driving(sim):
    motor, aux = sim.relays
    return bool(motor & DRIVING[0] or aux & DRIVING[1])


def come_to_rest(m, limit=SETTLE_LIMIT_S):
    """Let the wheels roll to rest, tick by tick, unless a motor is still
    driven; -> the simulated seconds that took."""
    sim, waited = m.sim, 0.0
    # The simulator sets a decaying rate to exactly 0 once it is negligible
    # (about 0.9 s after a move at creep speed); until then a count can flip.
    while any(sim.wheel_rates) and not driving(sim) and waited < limit:
        sim.run(SETTLE_STEP_S)
        waited += SETTLE_STEP_S
    return waited


def time_of_day(m):
    """Seconds since midnight by the board's BIOS tick count."""
    ticks, per_day = m.board.time_of_day()
    return ticks * 86400.0 / per_day


def clock_text(seconds):
    h, rest = divmod(seconds, 3600)
    mi, s = divmod(rest, 60)
    return "%02d:%02d:%05.2f" % (h, mi, s)


def report(m):
    """What the robot did, for a failure message."""
    sim = m.sim
    left, right = sim.wheel_counts
    motor, aux = sim.relays
    ferr = variable(m, "FERR")
    lines = ["what the robot did:",
             "  at %.2f s (time of day %s): x %.2f in, y %.2f in, heading %.2f deg"
             % ((sim.seconds, clock_text(time_of_day(m))) + pose_xy_heading(sim.pose)),
             "  wheel counts: left %d, right %d" % (left, right),
             "  arm %.2f in, jaw %.2f in" % (sim.arm, sim.jaw),
             "  relays: MOTOR %02X, AUX %02X; following error: %s"
             % (motor, aux, "none" if not ferr else "motor %d" % ferr)]
    log = getattr(sim.board, "moves", None)
    if log is not None:
        moves = log.describe()
        lines.append("  last moves:" if moves else "  no moves")
        lines.extend("    " + text for text in moves)
    return "\n".join(lines)


def wanted(**values):
    """`left 1000, right 1000` of the values that were asked for."""
    return ", ".join("%s %s" % (k, v) for k, v in values.items() if v is not None)


def off_by(value, want, tolerance):
    """The value is outside want +- tolerance (want None: anything goes)."""
    return want is not None and abs(value - want) > tolerance


def pose_xy_heading(pose):
    x, y, heading = pose
    return x, y, wrap(heading)


def fail(m, expected, settled=0.0):
    __tracebackhide__ = True      # pytest shows the caller's line
    rest = "\n  (after %.2f s for the wheels to roll to rest)" % settled if settled else ""
    raise AssertionError("expected %s%s\n%s" % (expected, rest, report(m)))


# ---------------------------------------------------------- asserting
def assert_pose(m, x=None, y=None, heading=None, *, inches=0.1, degrees=0.5, settle=True):
    """The robot stands at x, y (inches, within `inches` each) facing
    `heading` (degrees, either way round, within `degrees`). Leave out
    what does not matter."""
    __tracebackhide__ = True      # pytest shows the caller's line
    if x is None and y is None and heading is None:
        raise TypeError("assert_pose needs x, y or heading")
    settled = come_to_rest(m) if settle else 0.0
    px, py, ph = m.sim.pose
    bad = off_by(px, x, inches) or off_by(py, y, inches) \
        or (heading is not None and abs(wrap(ph - heading)) > degrees)
    if bad:
        fail(m, "the robot at %s, but it is at %s"
             % (wanted_pose(x, y, heading, inches, degrees), pose_text(m.sim.pose)), settled)


def wanted_pose(x, y, heading, inches, degrees):
    parts = ["%s %.2f in +-%g" % (name, v, inches) for name, v in (("x", x), ("y", y))
             if v is not None]
    if heading is not None:
        parts.append("heading %.2f deg +-%g" % (heading, degrees))
    return ", ".join(parts)


def assert_wheel_counts(m, left=None, right=None, *, counts=2, settle=True):
    """The encoders read left and right (forward minus reverse counts)."""
    __tracebackhide__ = True      # pytest shows the caller's line
    settled = come_to_rest(m) if settle else 0.0
    wl, wr = m.sim.wheel_counts
    if off_by(wl, left, counts) or off_by(wr, right, counts):
        fail(m, "wheel counts %s (+-%d), but they are left %d, right %d"
             % (wanted(left=left, right=right), counts, wl, wr), settled)


def assert_arm(m, height=None, jaw=None, *, inches=0.05):
    """The lift stands at `height` and the jaws are `jaw` apart (inches)."""
    __tracebackhide__ = True      # pytest shows the caller's line
    arm, opening = m.sim.arm, m.sim.jaw
    if off_by(arm, height, inches) or off_by(opening, jaw, inches):
        fail(m, "%s (+-%g in), but they are arm %.2f in, jaw %.2f in"
             % (wanted(arm=height, jaw=jaw), inches, arm, opening))


def assert_no_following_error(m):
    """No wheel fell too far behind its reference (RCL's FERR is 0)."""
    __tracebackhide__ = True      # pytest shows the caller's line
    ferr = variable(m, "FERR")
    if ferr is None:
        raise AssertionError("no FERR: RCL is not loaded on this machine")
    if ferr:
        fail(m, "no following error, but motor %d could not follow" % ferr)


def assert_motors_off(m):
    """No wheel is driven, and the arm and gripper motors are off."""
    __tracebackhide__ = True      # pytest shows the caller's line
    if driving(m.sim):
        fail(m, "every motor off, but relays MOTOR %02X AUX %02X drive one" % m.sim.relays)


def assert_time_of_day(m, when, *, seconds=0.5):
    """The board's clock reads `when`: "7:30 AM", "19:30:15" or seconds
    since midnight."""
    __tracebackhide__ = True      # pytest shows the caller's line
    want = parse_time(when)
    now = time_of_day(m)
    off = (now - want + 43200.0) % 86400.0 - 43200.0
    if abs(off) > seconds:
        fail(m, "time of day %s (+-%g s), but it is %s"
             % (clock_text(want), seconds, clock_text(now)))


TIME = re.compile(r"^\s*(\d{1,2}):(\d{2})(?::(\d{2}(?:\.\d*)?))?\s*([AaPp][Mm])?\s*$")


def parse_time(when):
    """"7:30 AM" / "19:30" / "7:30:15 PM" / seconds -> seconds since midnight."""
    if isinstance(when, (int, float)):
        return float(when)
    match = TIME.match(str(when))
    if not match:
        raise ValueError("a time of day is like '7:30 AM' or '19:30:15', not %r" % (when,))
    h, mi, s, half = match.groups()
    h, mi, s = int(h), int(mi), float(s or 0)
    if half:
        if not 1 <= h <= 12:
            raise ValueError("%r: with AM or PM the hour is 1 to 12" % (when,))
        h = h % 12 + (12 if half.upper() == "PM" else 0)
    if h > 23 or mi > 59 or s >= 60:
        raise ValueError("%r is not a time of day" % (when,))
    return h * 3600.0 + mi * 60.0 + s
