"""No wait runs forever with a motor on: a move, an arm move, MS, SECONDS,
MINUTES and WAIT-UNTIL start only when the tick can run; a command gives
up, everything stopped, when the control loop stops making progress; the
settings its checks rely on are refused when they would break them; the
idle shortcuts run only under RCL's own control word."""
import pytest

import rcl
from rcl.forth.primitives import CLOCK_HZ

NOT_RUNNING = "Control loop not running (INSTALL starts it)"
MOTOR_BITS, ARM_BITS = 0x3F, 0x0F


@pytest.fixture
def robot():
    return rcl.open()


def refusal(m, text):
    """The message text gives, the virtual seconds it took, and whether any
    motor relay was left on."""
    start = m.clock
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate(text)
    motor, aux = m.sim.relays
    return e.value.message, (m.clock - start) / CLOCK_HZ, bool(motor & MOTOR_BITS or aux & ARM_BITS)


@pytest.mark.parametrize("setup", ["INT-OFF", "MASK", "0 0 28 SET-INT"])
@pytest.mark.parametrize("wait", ["RERB 1 FEET FORWARD", "ARM 1 INCHES DOWN", "100 MS",
                                  "2 SECONDS", "1 MINUTES", "TICKS@ 100. D+ WAIT-UNTIL"])
def test_no_wait_starts_when_no_tick_can_come(robot, setup, wait):
    message, seconds, motor_on = refusal(robot, setup + "  " + wait)
    assert message == NOT_RUNNING
    assert seconds < 0.01 and not motor_on
    robot.evaluate("INSTALL  " + wait)                      # and INSTALL mends it


def test_a_move_refuses_when_int_1ch_is_not_rcls_control_word(robot):
    robot.evaluate(": OTHER ;  ' OTHER GET-CS 28 SET-INT")
    message, _, motor_on = refusal(robot, "RERB 1 FEET FORWARD")
    assert message == "INT 1Ch is not CONTROL (INSTALL puts it back)"
    assert not motor_on
    robot.evaluate("INSTALL RERB 1 FEET FORWARD")


@pytest.mark.parametrize("text", ["' NOOP IS CONTROL  RERB 1 FEET FORWARD",
                                  "' NOOP IS CONTROL  ARM 1 INCHES DOWN",
                                  ": SILENCE  INT-OFF ;  ' SILENCE IS CONTROL  RERB 1 FEET FORWARD"])
def test_a_command_whose_control_loop_makes_no_progress_gives_up_with_the_motors_off(robot, text):
    # 100 waits without progress: a second of ticks that do nothing, or at
    # once when the ticks stop coming.
    message, seconds, motor_on = refusal(robot, text)
    assert message == "Control loop stalled"
    assert seconds <= 1.1 and not motor_on
    robot.evaluate("INSTALL RERB 1 FEET FORWARD")


@pytest.mark.parametrize("setting, message", [
    ("0 ACCEL !", "Bad acceleration"), ("-5 ACCEL !", "Bad acceleration"),
    ("30001 ACCEL !", "Bad acceleration"),
    ("0 FERR-LIMIT !", "Bad following limit"), ("32767 FERR-LIMIT !", "Bad following limit"),
    ("-1 FERR-LIMIT !", "Bad following limit")])
def test_a_move_refuses_settings_its_checks_cannot_work_with(robot, setting, message):
    assert refusal(robot, setting + "  RERB 1 FEET FORWARD")[0] == message
    assert robot.sim.wheel_counts == (0, 0)


def test_the_largest_following_limit_still_trips_on_a_stalled_wheel(robot):
    # 30000 counts of lag at 5 MPH (25 counts a tick): about 12 s.
    robot.sim.stall("left")
    message, seconds, motor_on = refusal(robot, "30000 FERR-LIMIT !  RERB 5 MPH 500 FEET FORWARD")
    assert message == "Following error"
    assert 12 < seconds < 14 and not motor_on
    assert robot.evaluate("FERR ?") == "1 "


@pytest.mark.parametrize("when", ["-1.", "8640000.", "9999999.", "-8640000."])
def test_wait_until_refuses_a_time_that_never_comes(robot, when):
    assert refusal(robot, when + " WAIT-UNTIL")[0] == "Bad time"


def test_wait_until_takes_the_last_tick_of_the_day(robot):
    robot.evaluate("8639990. TICKS!  8639999. WAIT-UNTIL")
    assert robot.evaluate("TICKS@ D.") == "8639999 "


def test_a_users_own_control_word_runs_on_every_tick_of_ms_and_wait_until(robot):
    # The idle shortcuts skip the handler only when it is RCL's own.
    robot.evaluate("VARIABLE N  : COUNTING  1 N +!  (CONTROL) ;  ' COUNTING IS CONTROL")
    robot.evaluate("0 N !  TICKS@ 100. D+ WAIT-UNTIL")
    assert robot.evaluate("N ?") == "100 "
    ticks = robot.sim.board.ticks
    robot.evaluate("0 N !  1000 MS")
    assert int(robot.evaluate("N ?")) == robot.sim.board.ticks - ticks >= 100


def test_ms_waits_the_same_with_its_shortcut_under_the_stock_control_word():
    def run(shortcut):
        m = rcl.open()
        if not shortcut:
            m.sim.board.repeat_idle_ticks = lambda clock, n, c, limit: (clock, n)
        m.evaluate("1000 MS")
        return m.clock, m.sim.board.ticks
    assert run(True) == run(False)


@pytest.mark.parametrize("wait", ["-1 MINUTES", "-5 SECONDS", "-32768 SECONDS"])
def test_a_negative_wait_is_out_of_range_at_once(robot, wait):
    message, seconds, motor_on = refusal(robot, "37 137 PC!  " + wait)
    assert (message, motor_on) == ("Out of range", False)
    assert seconds < 0.01                                   # (the abort's hooks run)


def test_the_largest_count_still_waits(robot):
    robot.evaluate("0 SECONDS  0 MINUTES")
    start = robot.clock
    robot.evaluate("32767 SECONDS")
    assert (robot.clock - start) / CLOCK_HZ >= 32767
