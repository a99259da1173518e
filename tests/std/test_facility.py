"""Forth 2012 Facility word set (chapter 10): terminal words, keyboard
events, time, structures; RCL's MS and the board's time of day in the
full system, the host's clock in the bare one."""
import time

import pytest


# --- the terminal ---------------------------------------------------------------------

def test_at_xy_moves_the_cursor_with_an_ansi_sequence_counting_from_zero(system):
    assert system.evaluate("5 2 AT-XY") == "\x1b[3;6H"


def test_page_clears_the_screen(system):
    assert system.evaluate("PAGE") == "\f"


def test_emit_q_says_emit_can_go_on(sys_run):
    assert sys_run("EMIT?") == [-1]


# --- keyboard events ------------------------------------------------------------------

def test_key_q_and_ekey_q_are_false_with_no_key_waiting(sys_run):
    assert sys_run("KEY? EKEY?") == [0, 0]


def test_key_q_and_ekey_q_are_true_with_a_key_typed_ahead(system):
    system.keys = [ord("x")]
    system.evaluate("KEY? EKEY? EKEY")
    assert system.stack == [-1, -1, ord("x")]


def test_ekey_gives_a_character_that_ekey_to_char_recognises(system):
    system.keys = [ord("a")]
    system.evaluate("EKEY EKEY>CHAR")
    assert system.stack == [ord("a"), -1]


@pytest.mark.parametrize("keys, name", [
    ("\x1b[A", "K-UP"), ("\x1b[B", "K-DOWN"), ("\x1b[C", "K-RIGHT"), ("\x1b[D", "K-LEFT"),
    ("\x1b[H", "K-HOME"), ("\x1b[F", "K-END"), ("\x1b[2~", "K-INSERT"),
    ("\x1b[3~", "K-DELETE"), ("\x1b[5~", "K-PRIOR"), ("\x1b[6~", "K-NEXT"),
    ("\x1bOP", "K-F1"), ("\x1bOS", "K-F4"), ("\x1b[15~", "K-F5"), ("\x1b[24~", "K-F12"),
])
def test_ekey_turns_a_terminal_key_sequence_into_its_key_code(system, keys, name):
    system.keys = [ord(c) for c in keys]
    system.evaluate("EKEY DUP EKEY>CHAR NIP SWAP EKEY>FKEY SWAP %s =" % name)
    assert system.stack == [0, -1, -1]


def test_ekey_adds_the_modifier_bits_of_a_key_sequence(system):
    system.keys = [ord(c) for c in "\x1b[1;5C\x1b[1;2A"]
    system.evaluate("EKEY K-RIGHT K-CTRL-MASK OR =  EKEY K-UP K-SHIFT-MASK OR =")
    assert system.stack == [-1, -1]


def test_the_key_codes_are_all_distinct(sys_run):
    names = ("K-LEFT K-RIGHT K-UP K-DOWN K-HOME K-END K-PRIOR K-NEXT K-INSERT K-DELETE "
             + " ".join("K-F%d" % i for i in range(1, 13)))
    codes = sys_run(names)
    assert len(set(codes)) == 22
    masks = sys_run("K-SHIFT-MASK K-ALT-MASK K-CTRL-MASK")[-3:]
    assert all(m & c == 0 for m in masks for c in codes)


def test_a_lone_escape_is_the_escape_character(system):
    system.keys = [27]
    system.evaluate("EKEY EKEY>CHAR")
    assert system.stack == [27, -1]


# --- time -----------------------------------------------------------------------------

def test_ms_waits_exactly_that_many_milliseconds_of_virtual_time():
    import rcl

    m = rcl.Forth()
    before = m.seconds
    m.evaluate("250 MS")                  # and MS itself costs one primitive, 1000/36 us
    assert m.seconds - before == pytest.approx(0.250 + 1 / 36000, abs=1e-9)


def test_in_the_full_system_ms_is_rcls_calibrated_loop():
    import rcl

    bare, full = rcl.Forth(), rcl.open()
    assert "(MS)" in full.evaluate("SEE MS")
    assert "CODE MS" in bare.evaluate("SEE MS")


def test_time_and_date_in_the_bare_system_is_the_hosts_clock(system):
    import rcl

    bare = rcl.Forth()
    t0 = time.time()
    bare.evaluate("TIME&DATE")
    t1 = time.time()
    sec, minute, hour, day, month, year = bare.stack
    got = hour * 3600 + minute * 60 + sec
    lo, hi = time.localtime(t0), time.localtime(t1)
    assert (day, month, year) in ((lo.tm_mday, lo.tm_mon, lo.tm_year),
                                  (hi.tm_mday, hi.tm_mon, hi.tm_year))
    secs = [t.tm_hour * 3600 + t.tm_min * 60 + t.tm_sec for t in (lo, hi)]
    assert secs[0] <= got <= secs[1] or got in secs       # a midnight between: either end


def test_time_and_date_in_the_full_system_is_the_boards_time_of_day():
    import rcl

    full = rcl.open()
    full.evaluate("3.5 PM TICKS!  TIME&DATE")      # RCL's times are decimal hours
    assert full.stack[:3] == [0, 30, 15]
    start = full.seconds                 # the board's clock runs with virtual time
    full.evaluate("2DROP 2DROP 2DROP  90 SECONDS  TIME&DATE")
    sec, minute, hour = full.stack[:3]
    elapsed = full.seconds - start
    assert hour * 3600 + minute * 60 + sec == pytest.approx(15.5 * 3600 + elapsed, abs=1)


def test_time_and_date_agrees_with_rcls_own_clock():
    import rcl

    full = rcl.open()
    full.evaluate("11.59 AM TICKS!  125 SECONDS")
    hms = full.evaluate(".TIME").split()[0]
    full.evaluate("TIME&DATE")
    sec, minute, hour = full.stack[:3]
    assert hms == "%02d:%02d:%02d" % (hour, minute, sec)


def test_time_and_date_gives_the_hosts_date_in_the_full_system():
    import rcl

    full = rcl.open()
    full.evaluate("TIME&DATE")
    today = time.localtime()
    assert full.stack[3:] == [today.tm_mday, today.tm_mon, today.tm_year]


# --- structures -----------------------------------------------------------------------

POINT = ("BEGIN-STRUCTURE POINT  FIELD: P.X  FIELD: P.Y  CFIELD: P.TAG  "
         "4 +FIELD P.NAME  END-STRUCTURE ")


def test_a_structure_gives_its_size_and_each_field_its_offset(sys_run):
    assert sys_run(POINT + "POINT  0 P.X 0 P.Y 0 P.TAG 0 P.NAME") == [9, 0, 2, 4, 5]


def test_fields_add_their_offset_to_an_address(sys_run):
    assert sys_run(POINT + "CREATE PT POINT ALLOT  7 PT P.Y !  PT P.Y @  PT P.Y PT -") == [7, 2]


def test_plus_field_works_outside_a_structure(sys_run):
    assert sys_run("10 5 +FIELD F1 3 +FIELD F2  100 F1 100 F2") == [18, 110, 115]


def test_an_empty_structure_has_size_zero(sys_run):
    assert sys_run("BEGIN-STRUCTURE NOTHING END-STRUCTURE NOTHING") == [0]
