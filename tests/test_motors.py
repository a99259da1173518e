"""Physics of the robot (rcl/sim/motors.py) against its model and constants.

Numbers (rcl/sim/constants.py, docs/guide.md section 13): count 125 ->
1000 Hz = 2 MPH = 35.2 in/s; a spin is 1250 counts per wheel; the torque
limit 0.5 G is 5,488.6 counts/s^2; PLL, coast and brake time constants 20,
300 and 50 ms; lift 1 in/s over 0-8 in, gripper 0.5 in/s over 0-3 in.
"""
import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rcl.sim import constants as C
from rcl.sim.motors import Drive, Gripper, Lift, MotorsError, Robot, Wheel

FORWARD = C.M1_ON | C.M1_GO | C.M2_ON | C.M2_GO
SPIN_CCW = FORWARD | C.M1_REV           # left reverse, right forward


def f_ref(count):
    """Reference frequency of an 8253 speed count (0 = 65536)."""
    return C.F_8253_CLK / (count or C.N_MAX)


def run_wheel(wheel, ms, on=True, rev=False, go=True, ref=1000.0):
    """Step a wheel for `ms` sub-steps; return the (fwd, rev) pulses summed."""
    fwd = back = 0
    for _ in range(ms):
        f, r = wheel.step(on, rev, go, ref)
        fwd += f
        back += r
    return fwd, back


def run_drive(drive, ms, motor=FORWARD, aux=0, left=1000.0, right=1000.0):
    for _ in range(ms):
        drive.step(motor, aux, left, right)


def steady(drive, left, right):
    """Put both wheels at steady speed (signed counts/s) without a ramp."""
    drive.left.rate, drive.right.rate = left, right


# ---------------------------------------------------------------------------
# Constants
# ---------------------------------------------------------------------------

def test_torque_limit_is_half_a_g_or_5488_6_counts_per_s2():
    assert C.A_MOTOR_COUNTS_S2 == pytest.approx(0.5 * 386.4 * 625 / 22)
    assert round(C.A_MOTOR_COUNTS_S2, 1) == 5488.6


def test_count_125_is_1000_hz_and_1000_counts_per_s_is_35_2_in_per_s():
    assert f_ref(125) == 1000.0
    assert 1000.0 / C.COUNTS_PER_INCH == pytest.approx(35.2)


# ---------------------------------------------------------------------------
# Wheel: PLL, coast, brake, stall, load
# ---------------------------------------------------------------------------

def test_wheel_with_on_and_go_at_count_125_settles_to_1000_counts_per_s():
    wheel = Wheel()
    run_wheel(wheel, 1000, ref=f_ref(125))
    assert wheel.rate == pytest.approx(1000.0, abs=1e-6)
    assert wheel.rate / C.COUNTS_PER_INCH == pytest.approx(35.2)


def test_settled_wheel_delivers_1000_counts_in_one_second():
    wheel = Wheel()
    run_wheel(wheel, 1000, ref=f_ref(125))
    fwd, back = run_wheel(wheel, 1000, ref=f_ref(125))
    assert abs(fwd - 1000) <= 1 and back == 0


def test_wheel_with_rev_set_delivers_reverse_pulses_only():
    wheel = Wheel()
    run_wheel(wheel, 1000, rev=True)
    fwd, back = run_wheel(wheel, 1000, rev=True)
    assert wheel.rate == pytest.approx(-1000.0, abs=1e-6)
    assert fwd == 0 and abs(back - 1000) <= 1
    assert wheel.position == -wheel.reverse_counts


def test_stalled_wheel_delivers_no_counts():
    wheel = Wheel()
    wheel.stalled = True
    assert run_wheel(wheel, 1000) == (0, 0)
    assert wheel.rate == 0.0


def test_stalling_a_running_wheel_stops_it_at_once():
    wheel = Wheel()
    wheel.rate = 1000.0
    wheel.stalled = True
    wheel.step(True, False, True, 1000.0)
    assert wheel.rate == 0.0


def test_step_from_0_to_2500_hz_is_torque_limited_after_100_ms():
    wheel = Wheel()
    run_wheel(wheel, 100, ref=f_ref(C.N_MIN))
    # a free first-order step would be at 2500 * (1 - e^-5) = 2483 by now
    assert wheel.rate <= C.A_MOTOR_COUNTS_S2 * 0.1 + 1e-9
    assert wheel.rate == pytest.approx(5488.6 * 0.1, abs=0.01)


def test_small_reference_step_follows_the_20_ms_time_constant():
    wheel = Wheel()
    wheel.rate = 1000.0
    run_wheel(wheel, 20, ref=1050.0)
    assert wheel.rate == pytest.approx(1000.0 + 50.0 * (1 - math.exp(-1)))


def test_dynamic_braking_decays_with_50_ms_time_constant():
    wheel = Wheel()
    wheel.rate = 1000.0
    run_wheel(wheel, 50, on=False)
    assert wheel.rate == pytest.approx(1000.0 / math.e)


def test_coasting_decays_with_300_ms_time_constant():
    wheel = Wheel()
    wheel.rate = 1000.0
    run_wheel(wheel, 300, go=False)
    assert wheel.rate == pytest.approx(1000.0 / math.e)


def test_braking_from_1000_counts_per_s_stops_faster_than_coasting():
    braked, coasted = Wheel(), Wheel()
    braked.rate = coasted.rate = 1000.0
    run_wheel(braked, 100, on=False)
    run_wheel(coasted, 100, go=False)
    assert braked.rate == pytest.approx(1000.0 * math.exp(-2))
    assert coasted.rate == pytest.approx(1000.0 * math.exp(-1 / 3))


def test_relays_off_brake_even_with_go_set():
    wheel = Wheel()
    wheel.rate = 1000.0
    run_wheel(wheel, 50, on=False, go=True)
    assert wheel.rate == pytest.approx(1000.0 / math.e)


def test_braked_wheel_comes_to_rest_and_delivers_nothing_more():
    wheel = Wheel()
    wheel.rate = 1000.0
    run_wheel(wheel, 2000, on=False)
    assert wheel.rate == 0.0
    assert run_wheel(wheel, 100, on=False) == (0, 0)


def test_load_reduces_the_acceleration_to_the_torque_left_over():
    wheel = Wheel()
    wheel.load = 0.5
    run_wheel(wheel, 100, ref=2500.0)
    assert wheel.rate == pytest.approx(C.A_MOTOR_COUNTS_S2 * 0.5 * 0.1)


def test_loaded_wheel_still_reaches_and_holds_the_reference():
    wheel = Wheel()
    wheel.load = 0.5
    run_wheel(wheel, 2000, ref=1000.0)
    assert wheel.rate == pytest.approx(1000.0, abs=1e-6)


def test_full_load_keeps_a_wheel_at_rest():
    wheel = Wheel()
    wheel.load = 1.0
    assert run_wheel(wheel, 100) == (0, 0)


def test_load_makes_a_coasting_wheel_stop_sooner_and_never_reverses_it():
    wheel = Wheel()
    wheel.load = 0.2                      # 1,097.7 counts/s^2 of drag
    wheel.rate = 1000.0
    fwd, back = run_wheel(wheel, 1000, go=False)
    assert wheel.rate == 0.0 and back == 0


def test_load_outside_0_to_1_is_refused():
    with pytest.raises(MotorsError):
        Wheel().load = 1.5


def test_pll_locks_within_5_percent_of_the_reference_with_go_set():
    wheel = Wheel()
    wheel.rate = 960.0
    wheel.go = True
    assert wheel.locked(1000.0)
    wheel.rate = 940.0
    assert not wheel.locked(1000.0)


def test_pll_is_not_locked_with_go_clear():
    wheel = Wheel()
    wheel.rate = 1000.0
    wheel.step(True, False, False, 1000.0)
    assert not wheel.locked(1000.0)


def test_pll_lock_counts_speed_in_reverse_too():
    wheel = Wheel()
    run_wheel(wheel, 1000, rev=True)
    assert wheel.locked(1000.0)


# ---------------------------------------------------------------------------
# Robot pose
# ---------------------------------------------------------------------------

def test_both_wheels_forward_advance_along_heading_0_at_35_2_in_per_s():
    drive = Drive()
    steady(drive, 1000.0, 1000.0)
    run_drive(drive, 1000)
    assert drive.robot.x == pytest.approx(35.2)
    assert drive.robot.y == 0.0 and drive.robot.heading == 0.0


def test_both_wheels_forward_at_heading_90_advance_along_y():
    drive = Drive()
    drive.robot.heading = 90.0
    steady(drive, 1000.0, 1000.0)
    run_drive(drive, 1000)
    assert drive.robot.y == pytest.approx(35.2)
    assert drive.robot.x == pytest.approx(0.0, abs=1e-9)


def test_robot_starting_from_rest_covers_the_encoder_distance():
    drive = Drive()
    run_drive(drive, 2000)
    counts = drive.left.position + drive.left.pos_frac
    assert drive.robot.x == pytest.approx(counts / C.COUNTS_PER_INCH)


def test_opposite_wheels_1250_counts_each_spin_360_degrees_in_place():
    drive = Drive()
    steady(drive, -1250.0, 1250.0)
    run_drive(drive, 1000, motor=SPIN_CCW, left=1250.0, right=1250.0)
    assert drive.left.reverse_counts == 1250 and drive.right.forward_counts == 1250
    assert drive.robot.heading == pytest.approx(360.0)
    assert drive.robot.x == pytest.approx(0.0, abs=1e-9)
    assert drive.robot.y == pytest.approx(0.0, abs=1e-9)


def test_opposite_wheels_312_5_counts_each_turn_90_degrees():
    drive = Drive()
    steady(drive, -1250.0, 1250.0)
    run_drive(drive, 250, motor=SPIN_CCW, left=1250.0, right=1250.0)
    assert drive.robot.heading == pytest.approx(90.0)
    assert (drive.robot.x, drive.robot.y) == pytest.approx((0.0, 0.0), abs=1e-9)


def test_left_forward_right_reverse_turns_clockwise():
    drive = Drive()
    steady(drive, 1250.0, -1250.0)
    run_drive(drive, 250, motor=FORWARD | C.M2_REV, left=1250.0, right=1250.0)
    assert drive.robot.heading == pytest.approx(-90.0)


def test_constant_curvature_drives_a_quarter_circle_of_the_right_radius():
    # sL, sR per sub-step give radius W/2 * (sR+sL)/(sR-sL) and turn (sR-sL)/W
    robot = Robot()
    s_left, s_right = 0.01, 0.03
    turn = (s_right - s_left) / C.TRACK_IN
    radius = (s_left + s_right) / 2 / turn
    steps = round(math.pi / 2 / turn)
    for _ in range(steps):
        robot.move(s_left, s_right)
    angle = steps * turn
    assert robot.x == pytest.approx(radius * math.sin(angle), abs=1e-5)
    assert robot.y == pytest.approx(radius * (1 - math.cos(angle)), abs=1e-5)


# ---------------------------------------------------------------------------
# Arm lift and gripper
# ---------------------------------------------------------------------------

def test_lift_powers_on_at_8_in_on_its_top_switch():
    lift = Lift()
    assert lift.position == 8.0 and lift.top and not lift.bottom


def test_lift_moves_down_1_in_per_s_while_arm_on():
    lift = Lift()
    for _ in range(1000):
        lift.step(C.ARM_ON | C.ARM_DOWN)
    assert lift.position == 7.0 and not lift.top and not lift.bottom


def test_lift_stops_at_0_on_its_bottom_switch():
    lift = Lift()
    for _ in range(9000):
        lift.step(C.ARM_ON | C.ARM_DOWN)
    assert lift.position == 0.0 and lift.bottom


def test_lift_going_up_stops_at_8_on_its_top_switch():
    lift = Lift()
    lift.position = 6.5
    for _ in range(2000):
        lift.step(C.ARM_ON)
    assert lift.position == 8.0 and lift.top


def test_lift_stays_put_with_arm_on_clear():
    lift = Lift()
    lift.step(C.ARM_DOWN)
    assert lift.position == 8.0


def test_gripper_powers_on_closed():
    grip = Gripper()
    assert grip.opening == 0.0 and grip.closed and not grip.opened


def test_gripper_opens_half_an_inch_per_s_and_stops_at_3_on_its_switch():
    grip = Gripper()
    for _ in range(1000):
        grip.step(C.GRIP_ON)
    assert grip.opening == 0.5 and not grip.closed
    for _ in range(6000):
        grip.step(C.GRIP_ON)
    assert grip.opening == 3.0 and grip.opened


def test_gripper_stalls_on_an_object_and_reports_closed():
    grip = Gripper()
    grip.position = 3.0
    grip.object_width = 1.5
    for _ in range(2999):
        grip.step(C.GRIP_ON | C.GRIP_CLOSE)
    assert not grip.closed
    for _ in range(2000):
        grip.step(C.GRIP_ON | C.GRIP_CLOSE)
    assert grip.opening == 1.5 and grip.closed


def test_gripper_closes_fully_once_the_object_is_gone():
    grip = Gripper()
    grip.position = 1.5
    grip.object_width = None
    for _ in range(3000):
        grip.step(C.GRIP_ON | C.GRIP_CLOSE)
    assert grip.opening == 0.0 and grip.closed


def test_object_wider_than_the_jaws_is_refused():
    with pytest.raises(MotorsError):
        Gripper().object_width = 3.5


# ---------------------------------------------------------------------------
# Drive: latches in, STATUS out
# ---------------------------------------------------------------------------

def test_status_at_power_on_shows_arm_top_and_grip_closed():
    assert Drive().status_byte(1000.0, 1000.0) == C.ARM_TOP | C.GRIP_CLOSED


def test_status_shows_both_pll_locks_once_the_wheels_settle():
    drive = Drive()
    run_drive(drive, 1000)
    status = drive.status_byte(1000.0, 1000.0)
    assert status & C.M1_LOCK and status & C.M2_LOCK


def test_status_shows_no_lock_while_the_wheel_is_still_ramping():
    drive = Drive()
    run_drive(drive, 100)
    assert not drive.status_byte(1000.0, 1000.0) & (C.M1_LOCK | C.M2_LOCK)


def test_status_shows_the_charger_contact():
    drive = Drive()
    drive.charger = True
    assert drive.status_byte(1000.0, 1000.0) & C.CHARGER


def test_drive_returns_left_and_right_pulses_as_fwd_rev_pairs():
    drive = Drive()
    steady(drive, 1000.0, -1000.0)
    pulses = drive.step(FORWARD | C.M2_REV, 0, 1000.0, 1000.0)
    assert pulses == ((1, 0), (0, 1))


def test_drive_moves_the_arm_from_the_aux_byte():
    drive = Drive()
    run_drive(drive, 500, motor=0, aux=C.ARM_ON | C.ARM_DOWN)
    assert drive.lift.position == 7.5
    assert not drive.status_byte(1.0, 1.0) & C.ARM_TOP


def test_beeper_sounds_while_its_aux_bit_is_set():
    drive = Drive()
    run_drive(drive, 250, motor=0, aux=C.BEEPER)
    assert drive.beeper
    run_drive(drive, 10, motor=0, aux=0)
    assert not drive.beeper and drive.beeper_s == pytest.approx(0.25)


def test_gripper_opening_past_the_object_width_does_not_report_closed():
    grip = Gripper()
    grip.object_width = 1.5
    for _ in range(3000):
        grip.step(C.GRIP_ON)
        assert not grip.closed
    assert grip.opening == 1.5


def test_gripper_holding_an_object_stays_closed_with_the_motor_off():
    grip = Gripper()
    grip.position = 2.0
    grip.object_width = 1.5
    for _ in range(1001):
        grip.step(C.GRIP_ON | C.GRIP_CLOSE)
    grip.step(0)
    assert grip.opening == 1.5 and grip.closed


def test_cruising_at_steady_speed_gives_the_same_counts_and_pose_as_stepping():
    stepped, cruised = Drive(), Drive()
    relays = 0x3D                              # spin: left forward, right reverse
    for d in (stepped, cruised):
        for _ in range(1000):                  # reach the steady rate
            d.step(relays, 0, 1000.0, 400.0)
        assert d.steady(relays, 0, 1000.0, 400.0)
    for _ in range(3000):
        stepped.step(relays, 0, 1000.0, 400.0)
    cruised.cruise(3000, relays)
    assert abs(stepped.left.position - cruised.left.position) <= 1
    assert abs(stepped.right.position - cruised.right.position) <= 1
    assert cruised.robot.heading == pytest.approx(stepped.robot.heading, abs=1e-6)
    assert cruised.robot.x == pytest.approx(stepped.robot.x, abs=1e-3)
    assert cruised.robot.y == pytest.approx(stepped.robot.y, abs=1e-3)


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(rates=st.sampled_from([(1000.0, 400.0), (-1250.0, 1250.0), (1000.0, 1000.0), (0.0, -625.0)]),
       pieces=st.lists(st.integers(1, 700), min_size=1, max_size=12))
def test_a_steady_stretch_cruised_in_any_pieces_ends_on_the_same_bits_as_at_once(rates, pieces):
    # the stretch's state is a closed form of its length (Stretch), not a sum of its pieces
    relays = FORWARD | (C.M1_REV if rates[0] < 0 else 0) | (C.M2_REV if rates[1] < 0 else 0)
    whole, cut = Drive(), Drive()
    for d in (whole, cut):
        d.robot.heading = 30.0
        d.left.pos_frac, d.right.pos_frac = 0.75, -0.5      # left over from a ramp
        steady(d, *rates)
    whole.cruise(sum(pieces), relays)
    for n in pieces:
        cut.cruise(n, relays)
        assert cut.robot.heading_rad is not None            # looking at it changes nothing

    def state(d):
        return ([(w.pos_frac, w.forward_counts, w.reverse_counts) for w in (d.left, d.right)],
                (d.robot.x, d.robot.y, d.robot.heading_rad))
    assert state(cut) == state(whole)


def test_a_robot_placed_during_a_stretch_cruises_on_from_where_it_was_placed():
    d = Drive()
    steady(d, 1000.0, 1000.0)
    d.cruise(500, FORWARD)
    d.robot.x, d.robot.y, d.robot.heading = 0.0, 0.0, 90.0     # as Sim.place does
    d.cruise(1000, FORWARD)
    assert (d.robot.x, d.robot.y) == (pytest.approx(0.0, abs=1e-9), pytest.approx(35.2))
    assert d.left.position == 1500
