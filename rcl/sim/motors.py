"""Physics of the R-E Robot: drive wheels with their PLL, arm, gripper, pose.

The model below, integrated in 1 ms sub-steps (its numbers are in
constants.py). The classes have no clock and do no I/O: the board latches
the MOTOR and AUX bytes, knows each motor's reference frequency from its
8253 counter 0, calls `Drive.advance` for the sub-steps since it last did
(stepped one at a time while a rate changes, `Drive._stepped`; at once
while the wheels hold their rates, `Drive.cruise`), feeds the returned
pulses to counters 1 and 2, and answers STATUS reads with
`Drive.status_byte`.

    MOTOR byte --+--> Wheel (left,  motor 1) --(fwd, rev)--> 8253 #1 CLK1/CLK2
    f_ref L, R --+--> Wheel (right, motor 2) --(fwd, rev)--> 8253 #2 CLK1/CLK2
                 |         | travel (counts) / COUNTS_PER_INCH
                 |         v
                 |       Robot pose (x, y in inches, heading in degrees)
    AUX byte ----+--> Lift, Gripper, beeper
                 +--> status_byte(): limit switches, PLL locks, charger

Wheel, one sub-step of dt (tau and the torque limit from constants.py):

    ON GO  PLL:   rate += (+-f_ref - rate) * (1 - exp(-dt/tau_pll)),
                  the change clamped to a_max * dt (a_max = 0.5 G =
                  0.5 * 386.4 in/s^2 * 28.409 counts/in = 5,488.6 counts/s^2)
    ON  -  coast: rate *= exp(-dt/tau_coast)   (300 ms)
    -   -  brake: rate *= exp(-dt/tau_brake)   (50 ms, not torque limited)
    stalled:      rate = 0
    then pos_frac += rate * dt; whole counts leave as forward or reverse pulses.

The load fault, exactly: `load` L (0..1) is a dry-friction drag torque of L
times the motor's torque, always opposing the motion. Under the PLL the
motor keeps its full torque, so the net acceleration available to speed the
wheel up (or start it from rest) is a_max * (1 - L), and to slow it down is
a_max * (1 + L); the PLL still reaches and holds f_ref while L < 1 (a speed
loop has torque to spare), but it gets there later, so the wheel falls behind
the expected position during every ramp. At L = 1 a wheel at rest cannot
start. While coasting or braking the drag takes a further a_max * L * dt off
|rate| each sub-step, never reversing the wheel. A wheel at rest stays at
rest (static friction equals the drag).

Not modelled: motor electrical dynamics, PLL phase (only speed is locked),
wheel slip, relay bounce, 8253 reference changes within a sub-step, battery
voltage. A decaying or converging rate within 1e-6 counts/s of its target is
snapped to it, so a wheel at rest or at steady speed takes the fast path:
while both wheels hold their rates (a Stretch), the wheels' counts and the
pose are a closed form of the time since the stretch began, computed at
once for any number of sub-steps (Drive.cruise).
"""
import math

from rcl.errors import RclError
from rcl.sim import constants as C
from rcl.sim.constants import M1_GO, M1_ON, M1_REV, M2_GO, M2_ON, M2_REV

NO_PULSES = (0, 0)
AUX_BUSY = C.ARM_ON | C.GRIP_ON | C.BEEPER      # AUX bits that keep sub-steps stepped
MICRO = 1_000_000           # lift and gripper positions are kept in micro-inches


class MotorsError(RclError, ValueError):
    """A fault setting out of its range (load, object width, position)."""


# ---------------------------------------------------------------------------
# DRIVE WHEEL
# ---------------------------------------------------------------------------

class Wheel:
    """One drive wheel: gearmotor, PLL speed loop and direction-steered encoder.

    State: `rate` (counts/s, + forward), `pos_frac` (counts not yet
    delivered), `go` (the GO bit of the last step), `travel` (counts moved in
    the last step), totals `forward_counts` / `reverse_counts`. Faults:
    `stalled` (blocked wheel, rate 0) and `load` (drag, see the module doc).
    """

    TAU_PLL = C.TAU_PLL_S
    TAU_COAST = C.TAU_COAST_S
    TAU_BRAKE = C.TAU_BRAKE_S
    A_MAX = C.A_MOTOR_COUNTS_S2
    LOCK_TOLERANCE = C.PLL_LOCK_TOLERANCE
    REST = 1e-6             # counts/s: closer than this to the target is the target

    def __init__(self):
        self.rate = 0.0
        self.pos_frac = 0.0
        self.travel = 0.0
        self.go = False
        self.stalled = False
        self.forward_counts = 0
        self.reverse_counts = 0
        self._load = 0.0
        self._set_dt(C.SUB_STEP_S)

    @property
    def load(self):
        """Drag as a fraction of the motor's torque, 0.0 .. 1.0."""
        return self._load

    @load.setter
    def load(self, value):
        if not 0.0 <= value <= 1.0:
            raise MotorsError(f"wheel load {value} not in 0..1")
        self._load = float(value)
        self._set_dt(self._dt)

    def _set_dt(self, dt):
        # Per-dt factors, recomputed only when dt or the load changes.
        self._dt = dt
        self._k_pll = 1.0 - math.exp(-dt / self.TAU_PLL)
        self._keep_coast = math.exp(-dt / self.TAU_COAST)
        self._keep_brake = math.exp(-dt / self.TAU_BRAKE)
        self._up_dt = self.A_MAX * (1.0 - self._load) * dt
        self._down_dt = self.A_MAX * (1.0 + self._load) * dt
        self._drag_dt = self.A_MAX * self._load * dt

    def step(self, on, rev, go, f_ref, dt=C.SUB_STEP_S):
        """Run one sub-step of the wheel model above; return (fwd_pulses, rev_pulses)."""
        if dt != self._dt:
            self._set_dt(dt)
        self.go = go
        rate = self.rate
        if self.stalled:
            rate = 0.0
        elif on and go:
            target = -f_ref if rev else f_ref
            if rate != target:
                # First-order PLL step, clamped to the torque left over by the drag.
                delta = (target - rate) * self._k_pll
                limit = self._up_dt if delta * rate >= 0.0 else self._down_dt
                if delta > limit:
                    delta = limit
                elif delta < -limit:
                    delta = -limit
                rate += delta
                if -self.REST < target - rate < self.REST:
                    rate = target
        elif rate:
            rate = self._decay(rate, self._keep_coast if on else self._keep_brake)
        self.rate = rate
        if not rate:
            self.travel = 0.0
            return NO_PULSES
        # Move by rate * dt counts and deliver the whole counts as pulses.
        self.travel = counts = rate * dt
        frac = self.pos_frac + counts
        if frac >= 1.0:
            n = int(frac)
            self.pos_frac = frac - n
            self.forward_counts += n
            return (n, 0)
        if frac <= -1.0:
            n = int(-frac)
            self.pos_frac = frac + n
            self.reverse_counts += n
            return (0, n)
        self.pos_frac = frac
        return NO_PULSES

    def _decay(self, rate, keep):
        # Coast or brake toward 0; the drag helps but never reverses the wheel.
        rate *= keep
        drag = self._drag_dt
        if rate > drag:
            rate -= drag
        elif rate < -drag:
            rate += drag
        else:
            return 0.0
        if -self.REST < rate < self.REST:
            return 0.0
        return rate

    def target(self, on, rev, go, f_ref):
        """The rate a step would leave as it is: the reference, or rest."""
        if on and go and not self.stalled:
            return -f_ref if rev else f_ref
        return 0.0

    def glide(self, start, k, go):
        """Where a steady stretch (see Stretch) leaves this wheel k sub-steps
        after its `start` (pos_frac, forward and reverse counts, counts per
        sub-step); -> the (fwd, rev) pulses that are new since the last
        call. The whole counts of pos_frac + k * travel are delivered,
        truncated toward zero as `step` truncates them."""
        frac0, fwd0, rev0, per_step = start
        self.go = go
        self.travel = per_step
        frac = frac0 + per_step * k
        whole = int(frac)
        self.pos_frac = frac - whole
        if whole > 0:
            n, self.forward_counts = fwd0 + whole - self.forward_counts, fwd0 + whole
            return (n, 0) if n else NO_PULSES
        if whole < 0:
            n, self.reverse_counts = rev0 - whole - self.reverse_counts, rev0 - whole
            return (0, n) if n else NO_PULSES
        return NO_PULSES

    def locked(self, f_ref):
        """PLL lock: GO set and |rate| within 5 % of f_ref."""
        return bool(self.go) and abs(abs(self.rate) - f_ref) <= self.LOCK_TOLERANCE * f_ref

    @property
    def position(self):
        """Net delivered counts, forward minus reverse."""
        return self.forward_counts - self.reverse_counts


# ---------------------------------------------------------------------------
# ARM LIFT AND GRIPPER: fixed-speed gearmotors between limit switches
# ---------------------------------------------------------------------------

class LeadScrew:
    """A relay-switched gearmotor moving between 0 and TRAVEL at SPEED.

    Position is kept in whole micro-inches so that whole-second moves are
    exact. Subclasses give the AUX bits: ON_BIT runs the motor, LESS_BIT
    turns it toward 0 (arm down, jaws closing).
    """

    ON_BIT = 0
    LESS_BIT = 0
    SPEED_IN_S = 1.0
    TRAVEL_IN = 1.0
    POWER_ON_IN = 0.0

    def __init__(self):
        self._travel = round(self.TRAVEL_IN * MICRO)
        self._pos = round(self.POWER_ON_IN * MICRO)

    @property
    def position(self):
        """Position in inches, 0.0 .. TRAVEL_IN."""
        return self._pos / MICRO

    @position.setter
    def position(self, inches):
        if not 0.0 <= inches <= self.TRAVEL_IN:
            raise MotorsError(f"position {inches} not in 0..{self.TRAVEL_IN}")
        self._pos = round(inches * MICRO)

    def _floor(self):
        # Where moving toward 0 stops; the gripper raises it for an object.
        return 0

    def step(self, aux_byte, dt=C.SUB_STEP_S):
        """Move for dt seconds if ON_BIT is set in the AUX byte."""
        if not aux_byte & self.ON_BIT:
            return
        d = round(self.SPEED_IN_S * MICRO * dt)
        if aux_byte & self.LESS_BIT:
            self._pos = max(self._floor(), self._pos - d)
        else:
            self._pos = min(self._travel, self._pos + d)


class Lift(LeadScrew):
    """The arm's lift: 0.0 (lowest) .. 8.0 in (parked high, power-on), 1 in/s."""

    ON_BIT = C.ARM_ON
    LESS_BIT = C.ARM_DOWN
    SPEED_IN_S = C.ARM_SPEED_IN_S
    TRAVEL_IN = C.ARM_TRAVEL_IN
    POWER_ON_IN = C.ARM_TRAVEL_IN

    @property
    def top(self):
        """ARM-TOP limit switch."""
        return self._pos >= self._travel

    @property
    def bottom(self):
        """ARM-BOTTOM limit switch."""
        return self._pos <= 0


class Gripper(LeadScrew):
    """The jaws: opening 0.0 (closed, power-on) .. 3.0 in, 0.5 in/s.

    Fault `object_width` (inches, None = nothing held): closing jaws that are
    at least that far open stall at that width. `closed` is the GRIP-CLOSED
    bit: fully closed, or stalled on the object by a closing step (a
    current sense on the board; it stays set, motor on or off, until the jaws
    open or the object or position is changed). Passing the width while
    opening does not set it.
    """

    ON_BIT = C.GRIP_ON
    LESS_BIT = C.GRIP_CLOSE
    SPEED_IN_S = C.GRIP_SPEED_IN_S
    TRAVEL_IN = C.GRIP_TRAVEL_IN
    POWER_ON_IN = 0.0

    def __init__(self):
        super().__init__()
        self._object = None
        self._held = False

    @property
    def opening(self):
        """Jaw opening in inches."""
        return self.position

    @property
    def object_width(self):
        """Width of the object between the jaws, or None."""
        return None if self._object is None else self._object / MICRO

    @object_width.setter
    def object_width(self, inches):
        if inches is not None and not 0.0 < inches <= self.TRAVEL_IN:
            raise MotorsError(f"object width {inches} not in (0, {self.TRAVEL_IN}]")
        self._object = None if inches is None else round(inches * MICRO)
        self._held = False

    @LeadScrew.position.setter
    def position(self, inches):
        LeadScrew.position.fset(self, inches)
        self._held = False

    def step(self, aux_byte, dt=C.SUB_STEP_S):
        """Move the jaws; a closing step that ends on the object grips it."""
        super().step(aux_byte, dt)
        if aux_byte & self.ON_BIT:
            self._held = bool(aux_byte & self.LESS_BIT) and self._pos == self._object

    def _floor(self):
        obj = self._object
        return obj if obj is not None and self._pos >= obj else 0

    @property
    def opened(self):
        """GRIP-OPENED limit switch."""
        return self._pos >= self._travel

    @property
    def closed(self):
        """GRIP-CLOSED: fully closed or stalled on the object."""
        return self._pos <= 0 or self._held


# ---------------------------------------------------------------------------
# ROBOT POSE
# ---------------------------------------------------------------------------

class Robot:
    """Differential-drive pose: x, y in inches, heading in degrees.

    Heading 0 points along +x and counter-clockwise is positive. The heading
    is cumulative (a full spin reads 360, not 0), so tests can see turns.
    """

    TRACK_IN = C.TRACK_IN

    def __init__(self, x=0.0, y=0.0, heading=0.0):
        self.x = x
        self.y = y
        self.heading = heading

    @property
    def heading(self):
        """Heading in degrees, counter-clockwise from +x, not wrapped."""
        return math.degrees(self.heading_rad)

    @heading.setter
    def heading(self, degrees):
        self.heading_rad = math.radians(degrees)
        self._cos = math.cos(self.heading_rad)
        self._sin = math.sin(self.heading_rad)

    @property
    def start(self):
        """The pose as `arc` starts from: (x, y, heading_rad, cos, sin)."""
        return (self.x, self.y, self.heading_rad, self._cos, self._sin)

    def arc(self, start, s_left, s_right):
        """Stand where the exact arc (or line) of the wheels' travel, inches,
        ends when it begins at `start` (see `start`)."""
        x, y, heading, cos, sin = start
        ds = (s_left + s_right) * 0.5
        if s_left == s_right:
            self.x, self.y = x + ds * cos, y + ds * sin
            self.heading_rad, self._cos, self._sin = heading, cos, sin
            return
        turn = (s_right - s_left) / self.TRACK_IN
        chord = ds * math.sin(turn / 2) / (turn / 2)
        mid = heading + turn * 0.5
        self.x, self.y = x + chord * math.cos(mid), y + chord * math.sin(mid)
        self.heading_rad = heading = heading + turn
        self._cos, self._sin = math.cos(heading), math.sin(heading)

    def move(self, s_left, s_right):
        """Apply one sub-step of wheel travel in inches (forward positive)."""
        ds = (s_left + s_right) * 0.5
        if s_left == s_right:
            self.x += ds * self._cos
            self.y += ds * self._sin
            return
        turn = (s_right - s_left) / self.TRACK_IN
        mid = self.heading_rad + turn * 0.5
        self.x += ds * math.cos(mid)
        self.y += ds * math.sin(mid)
        self.heading_rad += turn
        self._cos = math.cos(self.heading_rad)
        self._sin = math.sin(self.heading_rad)


# ---------------------------------------------------------------------------
# STEADY STRETCHES: the state a closed form of the time
# ---------------------------------------------------------------------------

class Stretch:
    """A run of sub-steps in which both wheels hold their rates (Drive.cruise).

    The state k sub-steps after the stretch began is a closed form of k,
    from what it began with (pos_frac f0, counts, pose x0 y0 h0):

        wheel w   f = f0_w + v_w * k          v_w = rate_w * dt, counts
                  int(f) more counts delivered (toward zero, as a step
                  does), f - int(f) left in pos_frac
        robot     s_w = v_w * k / COUNTS_PER_INCH, ds = (s_l + s_r) / 2,
                  turn = (s_r - s_l) / TRACK_IN, t = turn / 2
                  x = x0 + ds * sin(t) / t * cos(h0 + t), y likewise with
                  sin(h0 + t), heading h0 + turn (the exact arc, Robot.arc;
                  a straight line when turn = 0)

    One multiplication, not k additions: the state after k sub-steps is
    one value however the k were cut into calls. So the board may bring
    the physics up at whatever moments it likes (every port access, or
    only those the physics must see) and gets the same bits, and cruising
    k sub-steps one at a time equals cruising them at once, by
    construction (tests/test_motors.py and test_board.py cut stretches at
    random). The stepped sub-steps (Wheel.step, Robot.move) sum instead:
    an Euler step of a rate that changes.
    """

    def __init__(self, drive, dt):
        self.dt = dt
        self.steps = 0
        self.wheels = tuple((w.pos_frac, w.forward_counts, w.reverse_counts, w.rate * dt)
                            for w in (drive.left, drive.right))
        self.pose = drive._robot.start
        self.placed = 0                      # the sub-steps the robot stands at
        self.pose_at = self.pose[:3]         # where this stretch last stood it
        self.left_at = None                  # Drive._where after the last cruise


# ---------------------------------------------------------------------------
# THE WHOLE MECHANISM
# ---------------------------------------------------------------------------

class Drive:
    """The robot's mechanism behind the MOTOR, AUX and STATUS ports.

    Parts: `left` (motor 1) and `right` (motor 2) wheels, `lift`, `gripper`,
    `robot` (pose). Beeper: `beeper` (sounding now) and `beeper_s` (seconds
    sounded in total). Fault: `charger` (sitting on the charging contacts).

    During a steady stretch the pose is worked out only when someone looks
    at `robot` (or a step follows): the wheels' counts are needed at every
    port access, the pose seldom.
    """

    COUNTS_PER_INCH = C.COUNTS_PER_INCH

    def __init__(self):
        self.left = Wheel()
        self.right = Wheel()
        self.lift = Lift()
        self.gripper = Gripper()
        self._robot = Robot()
        self.beeper = False
        self.beeper_s = 0.0
        self.charger = False
        self.stretch = None          # the steady stretch under way, if any

    @property
    def robot(self):
        """The Robot (pose), where the wheels have brought it."""
        if self.stretch is not None:
            self._place()
        return self._robot

    def _place(self):
        """Stand the robot where the stretch under way has brought it."""
        s = self.stretch
        k = s.steps
        if s.placed != k:
            (lstart, rstart), cpi = s.wheels, self.COUNTS_PER_INCH
            r = self._robot
            if lstart[3] or rstart[3]:
                r.arc(s.pose, lstart[3] * k / cpi, rstart[3] * k / cpi)
            s.placed, s.pose_at = k, (r.x, r.y, r.heading_rad)

    def step(self, motor_byte, aux_byte, f_ref_left, f_ref_right, dt=C.SUB_STEP_S):
        """One sub-step; return ((fwd, rev) left pulses, (fwd, rev) right pulses)."""
        _, lf, lr, rf, rr = self._stepped(1, motor_byte, aux_byte, f_ref_left, f_ref_right, dt)
        return (lf, lr), (rf, rr)

    def _stepped(self, n, motor_byte, aux_byte, f_ref_left, f_ref_right, dt, until=None):
        """Sub-steps one at a time (the Euler steps of the module doc): n
        of them, or fewer when after one the wheels' rates are `until`
        (their targets) and the arm, gripper and beeper rest; -> (sub-steps
        taken, left fwd, left rev, right fwd, right rev pulses summed).
        The loop of a ramp (10 a tick while a speed changes): what stays
        the same from one sub-step to the next is looked up once."""
        if self.stretch is not None:          # it ends here
            self._place()
            self.stretch = None
        m, left, right, robot = motor_byte, self.left, self.right, self._robot
        l_on, l_rev, l_go = m & M1_ON, m & M1_REV, m & M1_GO
        r_on, r_rev, r_go = m & M2_ON, m & M2_REV, m & M2_GO
        cpi = self.COUNTS_PER_INCH
        lf = lr = rf = rr = taken = 0
        while True:
            a, b = left.step(l_on, l_rev, l_go, f_ref_left, dt)
            c, d = right.step(r_on, r_rev, r_go, f_ref_right, dt)
            tl, tr = left.travel, right.travel
            if tl or tr:
                robot.move(tl / cpi, tr / cpi)
            if aux_byte or self.beeper:
                self._step_aux(aux_byte, dt)
            lf, lr, rf, rr, taken = lf + a, lr + b, rf + c, rr + d, taken + 1
            if taken == n or (until is not None and self.holds(until, aux_byte)):
                return taken, lf, lr, rf, rr

    def advance(self, n, motor_byte, aux_byte, f_ref_left, f_ref_right, dt=C.SUB_STEP_S):
        """n sub-steps: one at a time while a rate changes (or the arm,
        gripper or beeper runs), then at once as a steady stretch (`cruise`)
        as soon as the drive is `steady`; -> ((fwd, rev) left, (fwd, rev)
        right) pulses summed."""
        targets = self.targets(motor_byte, f_ref_left, f_ref_right)
        if self.holds(targets, aux_byte):
            return self.cruise(n, motor_byte, dt)     # steady already (most calls)
        if n <= 0:
            return NO_PULSES, NO_PULSES
        taken, lf, lr, rf, rr = self._stepped(n, motor_byte, aux_byte, f_ref_left, f_ref_right,
                                              dt, targets)
        if taken < n:                             # steady from here
            (a, b), (c, d) = self.cruise(n - taken, motor_byte, dt)
            lf, lr, rf, rr = lf + a, lr + b, rf + c, rr + d
        return (lf, lr), (rf, rr)

    def targets(self, motor_byte, f_ref_left, f_ref_right):
        """The rates the wheels settle at under these relays and references."""
        m = motor_byte
        return (self.left.target(m & M1_ON, m & M1_REV, m & M1_GO, f_ref_left),
                self.right.target(m & M2_ON, m & M2_REV, m & M2_GO, f_ref_right))

    def holds(self, targets, aux_byte):
        """The wheels are at these rates and the arm, gripper and beeper
        rest: nothing changes from one sub-step to the next."""
        return ((self.left.rate, self.right.rate) == targets
                and not aux_byte & AUX_BUSY and not self.beeper)

    def steady(self, motor_byte, aux_byte, f_ref_left, f_ref_right):
        """Nothing but steady wheels: `cruise` may take many steps at once."""
        return self.holds(self.targets(motor_byte, f_ref_left, f_ref_right), aux_byte)

    def cruise(self, n, motor_byte, dt=C.SUB_STEP_S):
        """n sub-steps of steady wheels (see `steady`) at once: the stretch
        they belong to goes on, or a new one begins here (see Stretch)."""
        s, r = self.stretch, self._robot
        if s is None or s.dt != dt or s.left_at != self._where() \
                or s.pose_at != (r.x, r.y, r.heading_rad):
            if s is not None:
                self._place()
            s = self.stretch = Stretch(self, dt)
        s.steps += n
        k = s.steps
        lstart, rstart = s.wheels
        lp = self.left.glide(lstart, k, motor_byte & M1_GO)
        rp = self.right.glide(rstart, k, motor_byte & M2_GO)
        s.left_at = self._where()
        return lp, rp

    def _where(self):
        """The wheels as a stretch carries on from them: if anything else
        changed them since its last cruise (a test), or moved the robot from
        where the stretch last stood it (`Sim.place`), a new one begins."""
        left, right = self.left, self.right
        return (left.rate, left.pos_frac, left.forward_counts, left.reverse_counts,
                right.rate, right.pos_frac, right.forward_counts, right.reverse_counts)

    def _step_aux(self, aux_byte, dt):
        self.lift.step(aux_byte, dt)
        self.gripper.step(aux_byte, dt)
        self.beeper = bool(aux_byte & C.BEEPER)
        if self.beeper:
            self.beeper_s += dt

    def status_byte(self, f_ref_left, f_ref_right):
        """The STATUS port byte (rcl/robot.py: 1 = active, bit 7 reads 0)."""
        lift, grip = self.lift, self.gripper
        return ((C.ARM_TOP if lift.top else 0)
                | (C.ARM_BOTTOM if lift.bottom else 0)
                | (C.GRIP_OPENED if grip.opened else 0)
                | (C.GRIP_CLOSED if grip.closed else 0)
                | (C.M1_LOCK if self.left.locked(f_ref_left) else 0)
                | (C.M2_LOCK if self.right.locked(f_ref_right) else 0)
                | (C.CHARGER if self.charger else 0))
