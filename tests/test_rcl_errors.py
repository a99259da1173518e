"""RCL's error messages (docs/guide.md section 8): each
aborts with its text, leaves the robot stopped and the system usable (the
stacks empty, words defined before the error still work)."""
import pytest

import rcl

MOTOR_BITS = 0x35               # M1-ON M2-ON M1-GO M2-GO: MOTOR latch bits 0, 2, 4, 5
ARM_GRIP_ON = 0x05              # ARM-ON GRIP-ON: AUX latch bits 0 and 2
BEFORE = ": TWICE ( n -- 2n )  2 * ;"


@pytest.fixture
def robot():
    m = rcl.open()
    m.evaluate(BEFORE)
    return m


def abort_message(m, text):
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate(text)
    return e.value.message


def assert_stopped_and_usable(m):
    motor, aux = m.sim.relays
    assert (motor & MOTOR_BITS) == 0
    assert (aux & ARM_GRIP_ON) == 0
    assert m.stack == []
    assert m.evaluate("2 3 + .") == "5 "
    assert m.evaluate("3 TWICE .") == "6 "


# ------------------------------------------------------------- numbers
def test_too_many_decimals_for_a_distance(robot):
    assert abort_message(robot, "1.23456 FEET") == "Too many decimals"
    assert_stopped_and_usable(robot)


def test_a_number_too_large_for_a_fixed_pair_is_out_of_range(robot):
    assert abort_message(robot, "40000. 0 (FIXED)") == "Out of range"
    assert_stopped_and_usable(robot)


def test_a_distance_of_50000_feet_is_out_of_range(robot):
    assert abort_message(robot, "50000.0 FEET") == "Out of range"
    assert_stopped_and_usable(robot)


def test_a_unit_word_in_hex_is_not_decimal(robot):
    assert abort_message(robot, "HEX 10 FEET") == "Not decimal"
    assert_stopped_and_usable(robot)


# ------------------------------------------------------- arm units
def test_miles_for_the_arm_is_a_bad_unit(robot):
    assert abort_message(robot, "ARM 2 MILES UP") == "Bad unit"
    assert_stopped_and_usable(robot)


def test_degrees_for_the_arm_is_a_bad_unit(robot):
    assert abort_message(robot, "ARM 90 DEGREES DOWN") == "Bad unit"
    assert_stopped_and_usable(robot)


def test_a_bad_unit_leaves_the_arm_where_it_was(robot):
    abort_message(robot, "ARM 90 DEGREES DOWN")
    assert robot.sim.arm == 8.0


# ---------------------------------------------- speed, acceleration, time
def test_zero_speed_is_a_bad_speed(robot):
    assert abort_message(robot, "0 MPH") == "Bad speed"
    assert_stopped_and_usable(robot)


def test_a_negative_speed_is_a_bad_speed(robot):
    assert abort_message(robot, "-5 IPS") == "Bad speed"
    assert_stopped_and_usable(robot)


def test_zero_g_is_a_bad_acceleration(robot):
    assert abort_message(robot, "0 G") == "Bad acceleration"
    assert_stopped_and_usable(robot)


def test_13_am_is_a_bad_time(robot):
    assert abort_message(robot, "13 AM") == "Bad time"
    assert_stopped_and_usable(robot)


def test_25_pm_is_a_bad_time(robot):
    assert abort_message(robot, "25 PM") == "Bad time"
    assert_stopped_and_usable(robot)


# ---------------------------------------------------------------- moves
def test_a_following_error_aborts_the_move(robot):
    assert abort_message(robot, "1 G 4 MPH 5 FEET FORWARD") == "Following error"
    assert_stopped_and_usable(robot)


def test_a_move_without_the_control_loop_installed_aborts(robot):
    robot.evaluate("UNINSTALL")
    assert abort_message(robot, "3 FEET FORWARD") == "Not installed"
    assert_stopped_and_usable(robot)


def test_a_move_that_is_not_installed_does_not_move_the_robot(robot):
    robot.evaluate("UNINSTALL")
    abort_message(robot, "3 FEET FORWARD")
    robot.sim.run(1)
    assert robot.sim.wheel_counts == (0, 0)


def test_the_robot_moves_normally_after_a_following_error(robot):
    abort_message(robot, "1 G 4 MPH 5 FEET FORWARD")
    robot.sim.run(1)                                # let the braked wheels settle
    left, right = robot.sim.wheel_counts
    robot.evaluate(".1 G 2 MPH 3.4 FEET FORWARD")
    robot.sim.run(0.5)                              # and roll to rest
    l2, r2 = robot.sim.wheel_counts
    # 1159 counts and the run-on; a wheel that starts part-way through a
    # count gets it a count early ("within a count or two", docs/testing.md).
    assert 1158 <= l2 - left <= 1163 and 1158 <= r2 - right <= 1163
