"""The board seam (rcl/board.py): one interface that every board
implements, a machine that owns its clock, and CODE words that find RCL's
variables through what the screens hand them, not by name."""
import ast
import pathlib

import rcl
from rcl.board import Board, NullBoard
from rcl.sim.board import SimBoard
from rcl.words.rclcode import idle_rule

ROOT = pathlib.Path(rcl.__file__).parent
HOOKS = ("out8", "in8", "out16", "in16", "far_fetch8", "far_store8", "port_script",
         "attach", "service", "tick_reads", "stop_motors", "tick_failed", "reconnect",
         "close",                    # safety: leaving a board safe and quiet
         "time_of_day", "set_time_of_day", "trace", "status",
         "explain",                  # observation: a cause the board knows (Host too slow)
         "pose",                     # observation: where the robot is, if the board sees it
         "inject_fault")             # an optional capability: the simulated board's faults


def imports_of(path):
    names = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module:
            names.append(node.module)
        elif isinstance(node, ast.Import):
            names.extend(a.name for a in node.names)
    return names


def test_the_board_packages_import_nothing_of_the_forth_machine():
    for package in ("sim", "hw"):
        for path in (ROOT / package).glob("*.py"):
            for name in imports_of(path):
                assert not name.startswith(("rcl.forth", "rcl.words")), (path, name)


def test_every_hook_has_a_documented_default_on_the_interface():
    for name in HOOKS:
        assert name in Board.__dict__, name
        assert name in Board.__doc__, name
    assert Board.ticks == 0 and Board.due is None


def test_the_interface_names_what_a_board_is_and_nothing_else():
    # ports, memory, interrupts, safety, time of day, observation: no speed hooks
    public = {n for n, v in vars(Board).items() if callable(v) and not n.startswith("_")}
    assert public == set(HOOKS) | {"far_fetch32"}


def test_no_board_assigns_the_machine_clock():
    for package in ("sim", "hw"):
        for path in (ROOT / package).glob("*.py"):
            text = path.read_text()
            assert "m.clock =" not in text and "machine.clock =" not in text, path


def test_a_machine_without_the_simulated_boards_fast_forward_waits_the_same():
    plain = rcl.open()
    plain.evaluate("250 MS")
    declining = rcl.open()
    declining.fast_forward = None
    declining.evaluate("250 MS")
    assert declining.clock == plain.clock
    assert (declining.sim.board.ticks, declining.sim.bios_ticks) \
        == (plain.sim.board.ticks, plain.sim.bios_ticks)


def test_ms_asks_the_screens_idle_rule_at_no_cost_and_it_follows_rcls_moving():
    m = rcl.open()
    idle = idle_rule(m)
    assert m.dictionary.name_of(idle) == "IDLE?"   # the rule is the screens' word
    now = m.clock
    assert m.ask(idle) and m.clock == now
    m.evaluate("-1 MOVING !")
    assert not m.ask(idle)
    m.evaluate("0 MOVING !  -1 ARM-BITS !")
    assert not m.ask(idle)
    m.evaluate("0 ARM-BITS !  : IDLE?  0 ;")       # a user's IDLE? is not RCL's
    assert idle_rule(m) == idle and m.ask(idle)


def test_a_question_asked_outside_time_services_no_tick_however_long_it_runs():
    m = rcl.open()
    m.evaluate(": LONG  0  10000 0 DO 1+ LOOP ;")   # some 30 ticks' worth of primitives
    xt = m.dictionary.find("LONG")[0]
    now, ticks = m.clock, m.sim.board.ticks
    assert m.ask(xt) == 10000
    assert (m.clock, m.sim.board.ticks, m.stack) == (now, ticks, [])
    m.evaluate("LONG DROP")                          # in time, it lets ticks in
    assert m.sim.board.ticks > ticks


def test_the_counter_words_find_their_state_when_the_name_means_something_else():
    m = rcl.open()
    m.evaluate("RERB 1 FEET FORWARD")
    before = m.evaluate("?CNT1 D.")
    m.evaluate("VARIABLE CNT-STATE  12345 CNT-STATE !  VARIABLE MOVING  -1 MOVING !")
    assert m.evaluate("?CNT1 D.") == before
    assert m.ask(idle_rule(m))    # (MS)'s IDLE? still reads RCL's own MOVING


def test_the_null_board_floats_and_declines_everything():
    m = rcl.Forth()
    assert isinstance(m.board, NullBoard)
    assert m.evaluate("HEX 80 PC@ .") == "FF "
    assert m.fast_forward is None                 # waits tick by tick
    assert m.board.reconnect() == "No link to reconnect"


def test_catch_up_moves_the_clock_forward_only():
    m = rcl.open()
    now = m.clock
    m.catch_up(now - 5)
    assert m.clock == now
    m.catch_up(now + 5)
    assert m.clock == now + 5


def test_the_sim_board_is_an_implementation_of_the_interface():
    assert issubclass(SimBoard, Board)


def test_the_time_of_day_is_read_and_set_through_the_interface_on_a_link():
    # LinkBoard has no time of day of its own: the interface reads the BIOS
    # data area through far memory, as the 80188 would, over the link.
    m = rcl.open(port="rclsim://")
    try:
        assert m.board.time_of_day() == m.sim.board.time_of_day()
        _, per_day = m.board.time_of_day()
        assert per_day == 8_640_000                   # INSTALL's 10 ms ticks a day
        m.board.set_time_of_day(8 * 360_000)
        assert m.evaluate(".TIME") == "08:00:00 "
    finally:
        m.board.close()
