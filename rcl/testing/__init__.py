"""Testing RCL programs: fresh machines, robot assertions, and (through
rcl.testing.plugin, which pytest loads by itself) fixtures and Forth test
files. See docs/testing.md.

    from rcl.testing import robot, assert_pose
    m = robot(["box.fs"])              # rcl.open() on a board that keeps its moves
    m.evaluate("3.5 FIXED BOX")
    assert_pose(m, x=0.18, y=0.26, heading=-0.82, inches=0.1, degrees=0.3)

Nothing here imports pytest: the assertions raise AssertionError.
"""
import rcl
from rcl.testing.assertions import (assert_arm, assert_motors_off,  # noqa: F401
                                    assert_no_following_error, assert_pose,
                                    assert_time_of_day, assert_wheel_counts,
                                    come_to_rest, report, time_of_day, variable)
from rcl.testing.moves import RecordingBoard


def robot(files=()):
    """A fresh running system (rcl.open()) whose board remembers its last
    moves, with `files` loaded in order."""
    m = rcl.open(board=RecordingBoard())
    for path in files:
        m.include(str(path))
    return m


def bare(files=()):
    """A fresh bare machine (rcl.Forth()) with `files` loaded in order."""
    m = rcl.Forth()
    for path in files:
        m.include(str(path))
    return m
