"""The prompt's status line text (rcl/status.py), read off a running
system: time of day, pose, move progress, arm, jaw, stack depth, beep."""
import re

import pytest

import rcl
from rcl import status


def test_status_of_a_fresh_system_shows_midnight_the_origin_and_the_arm_at_the_top():
    m = rcl.open()
    assert status.text(m) == ("00:00:00  x 0.0 y 0.0 in  heading 0.0  "
                              "arm 8.00 jaw 0.00 in  stack 0")


def test_status_follows_the_time_of_day_and_the_stack_depth():
    m = rcl.open()
    m.evaluate("9 41 SET-CLOCK 1 2 3")
    assert status.text(m).startswith("09:41:00")
    assert status.text(m).endswith("stack 3")


def test_status_shows_a_base_move_as_commanded_progress_over_its_length():
    m = rcl.open()
    # 500 counts commanded (Q-AT) of a 1000-count move
    m.evaluate("MOVING ON  500. Q-AT 2!  1000. END-AT 2!")
    assert "  moving 50%  " in status.text(m)
    m.evaluate("MOVING OFF")
    assert "moving" not in status.text(m)


def test_status_shows_where_the_simulated_robot_is_after_the_articles_first_command():
    m = rcl.open()
    m.evaluate("RERB 2 MPH 3.4 FEET FORWARD")     # 40.8 in, the robot's own pose
    x, y, heading = m.sim.pose
    assert abs(x - 40.8) < 0.2
    assert "x %.1f y 0.0 in  heading 0.0" % x in status.text(m)


def test_status_shows_a_beep_while_the_beeper_sounds():
    m = rcl.open()
    m.evaluate("BEEP-ON 10 MS")
    assert status.text(m).endswith("  BEEP")
    m.evaluate("BEEP-OFF 10 MS")
    assert "BEEP" not in status.text(m)


def test_status_shows_an_arm_move_and_the_heights_after_it():
    m = rcl.open()
    m.evaluate("ARM-BITS ON")
    assert "arm moving" in status.text(m)
    m.evaluate("ARM-BITS OFF ARM 3.1 INCHES DOWN")
    assert m.sim.arm == pytest.approx(4.9, abs=0.02)           # 8.0 - 3.1 (docs/guide.md section 6)
    assert "arm %.2f jaw 0.00 in" % m.sim.arm in status.text(m)


def test_status_on_a_linked_board_shows_the_link_and_rcls_own_pose():
    m = rcl.open(port="rclsim://?rate=4")
    try:
        m.evaluate("RERB 2 MPH 1 FEET FORWARD .POSE")
        line = status.linked_text(m)
        assert line.startswith("link up: rcl-board (simulated R-E Robot), ")
        assert re.search(r"  x 1[12]\.\d y 0\.0 in  heading 0\.0 \(RCL's\)  stack 0$", line)
        # wider than 80 columns: the link's details go first, the pose stays
        assert len(line) > 79
        assert re.fullmatch(r"link up  x 1[12]\.\d y 0\.0 in  heading 0\.0 \(RCL's\)  stack 0",
                            status.linked_text(m, 79))
    finally:
        m.board.close()


def busy_system():
    """Every field of the status line showing, the numbers at their widest."""
    m = rcl.open()
    m.evaluate("23 59 SET-CLOCK 1 2 3 4 5 6 7 8 9 10 11 12"
               "  MOVING ON  500. Q-AT 2!  1000. END-AT 2!  BEEP-ON")
    m.sim.place(-123.456, -456.789, 359.96)
    return m


def test_status_fits_79_columns_dropping_the_arm_first_and_keeping_the_stack_depth():
    line = status.text(busy_system(), 79)     # an 80-column terminal keeps its last column free
    assert len(line) <= 79
    assert line == "23:59:00  x -123.5 y -456.8 in  heading 0.0  moving 50%  stack 12  BEEP"


def test_status_sheds_fields_least_useful_first_as_the_terminal_narrows():
    m = busy_system()
    assert status.text(m).endswith("  arm 8.00 jaw 0.00 in  stack 12  BEEP")   # no width: all
    assert status.text(m, 60) == "23:59:00  x -123.5 y -456.8 in  heading 0.0  stack 12"
    assert status.text(m, 45) == "23:59:00  x -123.5 y -456.8 in  heading 0.0"


def test_status_heading_wraps_to_0_and_a_small_negative_shows_as_0_0():
    m = rcl.open()
    m.sim.place(0.0, -0.04, 359.97)
    assert "x 0.0 y 0.0 in  heading 0.0  " in status.text(m)
    m.sim.place(-0.06, 0.0, -0.04)
    assert "x -0.1 y 0.0 in  heading 0.0  " in status.text(m)


def test_one_decimal_never_shows_minus_zero_nor_a_heading_of_360():
    # rcl-board's status line writes the pose with these too
    assert [status.heading_text(h) for h in (359.96, 359.94, -0.04, 720.25, 90.0)] == \
        ["0.0", "359.9", "0.0", "0.2", "90.0"]
    assert [status.tenths(v) for v in (-0.04, -0.05001, 0.04, 12.34)] == \
        ["0.0", "-0.1", "0.0", "12.3"]
