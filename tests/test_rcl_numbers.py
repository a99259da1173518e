"""RCL's number words: FIXED and its parts, the unit words, SPEED and >REF,
G, DISTANCE and COUNTS, BREAKPOINTS, AM and PM.

Every expected number is a worked example of docs/guide.md (sections 3
and 13), or follows from the rules there and in docs/words.md (layers 5
to 7, and 9 for AM and PM). Nothing here moves the robot.
"""
import pytest

import rcl


@pytest.fixture
def robot():
    m = rcl.open()
    return m


def stack_after(m, text):
    m.evaluate(text)
    return m.stack


# ---------------------------------------------------------------- FIXED
@pytest.mark.parametrize("typed, frac_int", [
    ("725", [0, 725]),
    ("3.5", [5000, 3]),
    ("-9.999", [-9990, -9]),
    ("38.04", [400, 38]),
    (".1", [1000, 0]),
    ("1.", [0, 1]),
    ("932.015", [150, 932]),
    ("-.5", [-5000, 0]),
])
def test_fixed_turns_the_typed_number_into_ten_thousandths_and_an_integer_part(
        robot, typed, frac_int):
    assert stack_after(robot, typed + " FIXED") == frac_int


def test_fixed_refuses_more_than_four_decimals(robot):
    with pytest.raises(rcl.ForthError) as e:
        robot.evaluate("1.23456 FIXED")
    assert e.value.message == "Too many decimals"


def test_paren_fixed_takes_the_decimals_from_the_stack_not_from_dpl(robot):
    # 1234567 with 3 decimals is 1234.567, whatever DPL says.
    assert stack_after(robot, "1234567. 3 (FIXED)") == [5670, 1234]


def test_paren_fixed_treats_a_negative_decimal_count_as_none(robot):
    assert stack_after(robot, "5. -1 (FIXED)") == [0, 5]


def test_paren_fixed_refuses_an_integer_part_above_32767(robot):
    with pytest.raises(rcl.ForthError) as e:
        robot.evaluate("40000. 0 (FIXED)")
    assert e.value.message == "Out of range"


def test_extract_leaves_the_decimal_digits_least_significant_deepest_and_the_integer_on_top(
        robot):
    # 932.015: digits 5 (third decimal), 1, 0 (first decimal), then 932.
    assert stack_after(robot, "932015. 3 EXTRACT") == [5, 1, 0, 932]


def test_build_puts_the_first_decimal_digit_most_significant(robot):
    assert robot.evaluate("5 1 0 3 BUILD .") == "15 "


@pytest.mark.parametrize("k, m", [(0, 10000), (1, 1000), (3, 10), (4, 1)])
def test_scalar_is_the_factor_that_makes_k_digits_ten_thousandths(robot, k, m):
    assert robot.evaluate("%d SCALAR ." % k) == "%d " % m


def test_fraction_scales_a_fixed_pair_by_a_multiplier(robot):
    assert robot.evaluate("932.015 FIXED 1000 FRACTION D.") == "932015 "


def test_fraction_keeps_the_sign_of_a_negative_number(robot):
    assert robot.evaluate("-932.015 FIXED 1000 FRACTION D.") == "-932015 "


def test_fraction_takes_the_sign_from_the_fraction_when_the_integer_part_is_zero(robot):
    assert robot.evaluate("-.5 FIXED 10000 FRACTION D.") == "-5000 "


def test_v4_is_ten_thousand_times_the_value(robot):
    assert robot.evaluate("3.5 FIXED >V4 D.") == "35000 "


# ------------------------------------------------- distances -> counts
# The pending distance, converted by EXPECTED (docs/guide.md section 13).
@pytest.mark.parametrize("typed, counts", [
    ("1 INCHES", 28),
    ("3.1 INCHES", 88),
    ("6 INCHES", 170),
    ("1 FEET", 341),
    ("3.5 FEET", 1193),
    ("3.4 FEET", 1159),
    ("12 FEET", 4091),
    ("1 MILES", 1800000),
    ("90 DEGREES", 313),
    ("180 DEGREES", 625),
])
def test_a_distance_word_gives_the_reference_count_of_encoder_counts(robot, typed, counts):
    assert robot.evaluate(typed + " EXPECTED D.") == "%d " % counts


def test_a_negative_distance_gives_negative_counts(robot):
    assert robot.evaluate("-2 FEET EXPECTED D.") == "-682 "


def test_counts_turns_ten_thousandths_of_an_inch_into_encoder_counts(robot):
    # 16.0 in, the acceleration distance of 2 MPH at 0.1 G: 454.5 -> 455.
    assert robot.evaluate("160000. COUNTS D.") == "455 "


# ------------------------------------------------------------- speeds
@pytest.mark.parametrize("typed, crpm", [
    ("1 MPH", 6000),
    ("2 MPH", 12000),
    ("5 MPH", 30000),
    ("10 IPS", 3409),
    ("20 IPS", 6818),
    ("25.5 IPS", 8693),
    ("36 IPS", 12273),
    ("1 FPS", 4091),
    ("100 FPM", 6818),
])
def test_a_speed_word_gives_the_reference_speed_in_centi_rpm(robot, typed, crpm):
    assert robot.evaluate(typed + " SPEED .") == "%d " % crpm


def test_speed_is_clamped_to_5_mph(robot):
    assert robot.evaluate("10 MPH SPEED .") == "30000 "


def test_the_default_speed_is_1_mph(robot):
    assert robot.evaluate("SPEED .") == "6000 "


@pytest.mark.parametrize("typed, count", [
    ("2 MPH", 125),
    ("25.5 IPS", 173),
    ("36 IPS", 122),
    ("10 IPS", 440),
    ("1 FPS", 367),
    ("5 MPH", 50),
])
def test_a_speed_gives_the_reference_8253_count(robot, typed, count):
    assert robot.evaluate(typed + " SPEED >REF .") == "%d " % count


def test_a_speed_too_slow_for_the_8253_gets_the_slowest_count_written_as_zero(robot):
    # 1,500,000 / 22 = 68,182 > 65,536: clamped, and 65,536 is written as 0.
    assert robot.evaluate("22 >REF .") == "0 "


# ------------------------------------------------------- acceleration
@pytest.mark.parametrize("typed, accel", [
    (".05", 66),
    ("0.1", 132),
    (".1", 132),
    (".5", 659),
    ("1", 1317),
])
def test_g_converts_the_acceleration_to_centi_rpm_per_tick(robot, typed, accel):
    assert robot.evaluate(typed + " G ACCEL @ .") == "%d " % accel


def test_the_default_acceleration_is_0_1_g(robot):
    assert robot.evaluate("ACCEL @ .") == "132 "


def test_distance_to_reach_2_mph_from_rest_at_0_1_g_is_16_inches(robot):
    assert robot.evaluate("0 12000 DISTANCE D.") == "160000 "


def test_distance_to_stop_from_2_mph_is_the_same_as_to_start(robot):
    assert robot.evaluate("12000 0 DISTANCE D.") == "160000 "


def test_distance_to_reach_25_5_ips_at_0_1_g(robot):
    # round(8693^2 x 11 / (75 x 132)) = 83965 (8.4 in, 239 counts).
    assert robot.evaluate(".1 G 0 8693 DISTANCE D.") == "83965 "


# -------------------------------------------------------- breakpoints
def breakpoints(m, total, crpm, motor=1):
    m.evaluate("%d. %d BREAKPOINTS" % (total, crpm))
    return (m.evaluate("%d ACC-END 2@ D." % motor),
            m.evaluate("%d DEC-START 2@ D." % motor),
            m.evaluate("%d MOVE-END 2@ D." % motor),
            m.evaluate("%d PEAK @ ." % motor))


# docs/guide.md section 13, at 0.1 G: total counts, crpm -> accel end,
# decel start, move end, peak.
BREAKPOINT_TABLE = [
    pytest.param(1193, 8693, 239, 954, 8693, id="25.5 IPS, 3.5 FEET: cruise"),
    pytest.param(1159, 12000, 455, 704, 12000, id="2 MPH, 3.4 FEET: cruise"),
    pytest.param(170, 8693, 85, 85, 5189, id="25.5 IPS, 6 INCHES: triangle"),
    pytest.param(313, 8693, 156, 157, 7029, id="25.5 IPS, 90 DEGREES: triangle"),
    pytest.param(625, 3409, 37, 588, 3409, id="10 IPS, 180 DEGREES: cruise"),
    pytest.param(8523, 12273, 475, 8048, 12273, id="36 IPS, 25 FEET: cruise"),
]


@pytest.mark.parametrize("total, crpm, acc_end, dec_start, peak", BREAKPOINT_TABLE)
def test_breakpoints_lay_out_the_reference_trapezoid(robot, total, crpm, acc_end,
                                                    dec_start, peak):
    assert breakpoints(robot, total, crpm) == (
        "%d " % acc_end, "%d " % dec_start, "%d " % total, "%d " % peak)


def test_breakpoints_give_both_motors_the_same_profile(robot):
    assert breakpoints(robot, 1159, 12000, motor=2) == ("455 ", "704 ", "1159 ", "12000 ")


def test_breakpoints_raise_a_tiny_moves_peak_to_the_creep_speed(robot):
    # isqrt(2400 x 132 x 1) = 562 < V-CREEP 600.
    assert breakpoints(robot, 2, 12000)[3] == "600 "


# ------------------------------------------------------------ AM / PM
@pytest.mark.parametrize("typed, ticks", [
    ("8.5 AM", 3060000),
    ("8 AM", 2880000),
    ("12 AM", 0),               # midnight
    ("12.5 AM", 180000),        # 00:30
    ("1.5 PM", 4860000),
    ("12 PM", 4320000),         # noon
    ("12.5 PM", 4500000),       # 12:30
    ("4.5 PM", 5940000),
])
def test_am_and_pm_give_ticks_since_midnight(robot, typed, ticks):
    assert robot.evaluate(typed + " D.") == "%d " % ticks


@pytest.mark.parametrize("typed", ["13 AM", "25 PM", "-1 AM"])
def test_an_hour_outside_the_clock_face_is_a_bad_time(robot, typed):
    with pytest.raises(rcl.ForthError) as e:
        robot.evaluate(typed)
    assert e.value.message == "Bad time"
