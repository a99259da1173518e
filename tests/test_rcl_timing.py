"""RCL's waiting words take shortcuts only where nothing would differ: the
same program waits the same virtual time, with the same ticks and time of
day, whether the shortcut is taken or every tick is run."""
import pytest

import rcl


def run(program, shortcuts):
    m = rcl.open()
    if not shortcuts:
        m.sim.board.repeat_idle_ticks = lambda clock, n, c, limit: (clock, n)  # MS ticks through
        m.sim.board.skip_to_tick = lambda target: None     # WAIT-UNTIL polls
    m.evaluate(program)
    board = m.sim.board
    return m.clock, board.ticks, board.low_fetch32(0x46C), board.pcb.missed, m.stack


@pytest.mark.parametrize("program", [
    "100 MS", "7 MS 3 MS 250 MS", "1 MINUTES", "BEEP BEEP 1 SECONDS",
    "ARM 1 INCHES DOWN 2 SECONDS",
    "8 AM TICKS!  8.01 AM WAIT-UNTIL",
    "RERB 1 FEET FORWARD  10 SECONDS  TICKS@ 200. D+ WAIT-UNTIL",
])
def test_a_wait_ends_at_the_same_clock_with_or_without_shortcuts(program):
    assert run(program, shortcuts=True) == run(program, shortcuts=False)


def test_ctrl_c_during_a_move_stops_both_motors():
    m = rcl.open()

    def interrupt_once(board, fired=[]):
        if board.machine.clock > 36_000_000_000 and not fired:   # 1 s into the move
            fired.append(True)
            raise KeyboardInterrupt
    m.sim.board.observers.append(interrupt_once)
    with pytest.raises(rcl.ForthError) as e:
        m.evaluate("RERB 2 MPH 10 FEET FORWARD")
    assert e.value.message == "Interrupted"
    m.sim.board.observers.clear()
    assert m.sim.relays[0] & 0x35 == 0                              # ON and GO bits off
    m.sim.run(1.0)
    assert max(abs(r) for r in m.sim.wheel_rates) < 0.01
    assert m.evaluate("RERB 2 MPH 1 FEET FORWARD") == ""            # still usable
