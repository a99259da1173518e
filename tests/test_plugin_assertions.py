"""Robot assertions (rcl.testing): they hold where the robot really is, in
RCL's own numbers (docs/guide.md section 13), and a failure says what was
expected and what the robot did: pose, wheel counts, arm, relays,
following error, the last moves."""
import pathlib

import pytest

import rcl
from inner_pytest import run
from rcl.testing import (assert_arm, assert_motors_off, assert_no_following_error,
                         assert_pose, assert_time_of_day, assert_wheel_counts, robot)

EXAMPLES = pathlib.Path(rcl.SCREENS) / "examples"


@pytest.fixture(scope="module")
def boxed():
    """The article's BOX (Listing 2) driven once: 3.5 ft sides, right turns."""
    m = robot([EXAMPLES / "listing2.fs"])
    m.evaluate("3.5 FIXED BOX")
    return m


def failure(check, *args, **kwargs):
    with pytest.raises(AssertionError) as info:
        check(*args, **kwargs)
    return str(info.value)


def test_box_comes_back_within_a_third_of_an_inch_turned_0_8_degrees_clockwise(boxed):
    # The simulator's pose once the wheels are at rest; the reference's
    # Listing 1 square (left turns) ends within 0.3 in, +0.7 to +0.8 deg.
    assert_pose(boxed, x=0.21, y=0.33, heading=-0.93, inches=0.1, degrees=0.3)
    assert_pose(boxed, x=0, y=0, inches=0.35)


def test_listing_1s_left_square_comes_back_within_0_3_inches_turned_0_7_to_0_8_degrees():
    # The reference's figure, within two counts (0.035 in of travel, 0.14
    # deg each): its simulation and this one land a count or two apart.
    m = robot([EXAMPLES / "listing1.fs"])
    assert_pose(m, x=0, y=0, heading=0.75, inches=0.3 + 0.07, degrees=0.05 + 0.28)


def test_box_drives_four_sides_of_1193_counts_and_four_turns_of_313(boxed):
    assert_wheel_counts(boxed, left=4 * 1193 + 4 * 313, right=4 * 1193 - 4 * 313, counts=16)


def test_box_ends_with_the_motors_off_and_no_following_error(boxed):
    assert_motors_off(boxed)
    assert_no_following_error(boxed)


def test_a_pose_failure_shows_expected_pose_counts_and_the_last_moves(boxed):
    text = failure(assert_pose, boxed, x=0, y=0, heading=0, inches=0.1, degrees=0.3)
    assert text.startswith("expected the robot at x 0.00 in +-0.1, y 0.00 in +-0.1, "
                           "heading 0.00 deg +-0.3, but it is at (0.21, 0.33, -0.93 deg)")
    assert "wheel counts: left 6027, right 3522" in text
    moves = [line.split()[0] for line in text.split("last moves:\n")[1].splitlines()]
    assert moves == ["FORWARD", "RIGHT"] * 4
    assert "counts left +312 right -311" in text


def test_a_heading_is_compared_whichever_way_round(boxed):
    assert_pose(boxed, heading=359.07, degrees=0.3)       # the sim says -0.93


def test_wheel_counts_failure_names_both_counts():
    m = robot()
    m.evaluate("3.5 FEET FORWARD")
    text = failure(assert_wheel_counts, m, left=1000, right=1000)
    assert "wheel counts left 1000, right 1000 (+-2), but they are left 119" in text


def test_the_arm_and_jaw_are_where_the_reference_puts_them():
    m = robot()
    m.evaluate("ARM 3.1 INCHES DOWN 2 INCHES UP 1 INCHES OPEN")    # 8.0 -> 4.9 -> 6.9
    assert_arm(m, height=6.9, jaw=1.0)
    text = failure(assert_arm, m, height=8.0)
    assert "expected arm 8.0 (+-0.05 in), but they are arm %.2f in, jaw 1.00 in" \
        % m.sim.arm in text
    assert [line.split()[0] for line in text.split("last moves:\n")[1].splitlines()] == \
        ["DOWN", "UP", "OPEN"]


def test_a_stalled_wheel_is_a_following_error_the_assertion_names():
    m = robot()
    m.sim.stall("left")
    with pytest.raises(rcl.ForthError, match="Following error"):
        m.evaluate("3.5 FEET FORWARD")
    assert "but motor 1 could not follow" in failure(assert_no_following_error, m)
    assert_motors_off(m)                                  # the abort stopped them


def test_a_driven_motor_fails_motors_off():
    m = robot()
    m.evaluate("HEX 35 88 PC! DECIMAL")                   # M1/M2 ON and GO
    assert "relays MOTOR 35 AUX 00 drive one" in failure(assert_motors_off, m)


def test_the_time_of_day_follows_the_simulated_clock():
    m = robot()
    m.evaluate("8.5 AM WAIT-UNTIL")
    assert_time_of_day(m, "8:30 AM", seconds=0.01)
    assert_time_of_day(m, "08:30:00")
    assert "time of day 20:30:00.00 (+-0.5 s), but it is 08:30:00.00" in \
        failure(assert_time_of_day, m, "8:30 PM")


def test_a_bad_time_of_day_is_a_clear_error():
    with pytest.raises(ValueError, match="like '7:30 AM'"):
        assert_time_of_day(robot(), "half past eight")


def test_a_bare_machine_has_no_following_error_to_check():
    with pytest.raises(AssertionError, match="RCL is not loaded"):
        assert_no_following_error(rcl.open(screens=False))


def test_a_python_test_that_fails_reports_the_robot_in_pytest(pytester):
    pytester.makepyfile("""
        from rcl.testing import assert_pose

        def test_patrol(rcl_robot):
            rcl_robot.evaluate("1 FEET FORWARD")
            assert_pose(rcl_robot, x=10, inches=0.5)
    """)
    result = run(pytester)
    result.assert_outcomes(failed=1)
    result.stdout.fnmatch_lines([
        ">       assert_pose(rcl_robot, x=10, inches=0.5)",
        "E       AssertionError: expected the robot at x 10.00 in +-0.5, but it is at (1?.??, 0.00, *",
        "E         (after 0.* s for the wheels to roll to rest)",
        "E       what the robot did:",
        "E         wheel counts: left 3??, right 3??",
        "E         last moves:",
        "E           FORWARD *"])
