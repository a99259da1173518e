"""Forth 2012 Double-Number word set with 32-bit doubles on a 16-bit machine.

A double is two cells on the stack: low cell, then high cell (on top).
MAX-D = 2147483647 is the pair (-1, 32767); MIN-D is (0, -32768).
"""
import pytest

MAX_N, MIN_N = 32767, -32768
MAXD = "-1 32767"       # 2147483647 as low/high cells
MIND = "0 -32768"       # -2147483648
MAX_D = [-1, MAX_N]
MIN_D = [0, MIN_N]


# --- number input -----------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("12.", [12, 0]),
    ("-12.", [-12, -1]),
    ("0.", [0, 0]),
    ("65536.", [0, 1]),
    ("70000.", [4464, 1]),
    ("1234567.", [-10617, 18]),
    ("2147483647.", MAX_D),
    ("-2147483648.", MIN_D),
    ("HEX FFFF. DECIMAL", [-1, 0]),
    ("1.2", [12, 0]),
    ("-1.000", [-1000, -1]),
])
def test_a_number_with_a_point_is_read_as_a_double(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, digits", [
    ("1234.", 0),
    ("12.34", 2),
    ("1.2.345", 3),
])
def test_dpl_counts_the_digits_after_the_last_punctuation(run, src, digits):
    assert run(f"{src} 2DROP DPL @") == [digits]


# --- defining words ---------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("1 2 2CONSTANT DC DC", [1, 2]),
    (f"{MIND} 2CONSTANT DC DC", MIN_D),
    (": T [ 1 2 ] 2LITERAL ; T", [1, 2]),
    (f": T [ {MAXD} ] 2LITERAL ; T", MAX_D),
    ("2VARIABLE DV 3 4 DV 2! DV 2@", [3, 4]),
    ("2VARIABLE A 2VARIABLE B 1 2 A 2! 3 4 B 2! A 2@", [1, 2]),
    ("1 2 2VALUE DV DV", [1, 2]),
    ("1 2 2VALUE DV 3 4 TO DV DV", [3, 4]),
    ("1 2 2VALUE DV : SETDV TO DV ; 5 6 SETDV DV", [5, 6]),
])
def test_double_defining_words_hold_two_cell_values(run, src, expected):
    assert run(src) == expected


# --- arithmetic -------------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("1. 2. D+", [3, 0]),
    ("-1 0 1 0 D+", [0, 1]),                 # carry out of the low cell
    ("-1. 1. D+", [0, 0]),
    (f"{MAXD} 1. D+", MIN_D),                # wraps
    ("0 1 1. D-", [-1, 0]),                  # borrow from the high cell
    ("1. 2. D-", [-1, -1]),
    (f"{MIND} 1. D-", MAX_D),
    ("1. DNEGATE", [-1, -1]),
    ("0 1 DNEGATE", [0, -1]),
    ("0. DNEGATE", [0, 0]),
    (f"{MAXD} DNEGATE", [1, MIN_N]),
    ("-5. DABS", [5, 0]),
    ("5. DABS", [5, 0]),
    ("0 -1 DABS", [0, 1]),
    ("-1 0 D2*", [-2, 1]),
    ("0 16384 D2*", MIN_D),
    ("-1. D2*", [-2, -1]),
    ("0 1 D2/", [MIN_N, 0]),
    ("-1. D2/", [-1, -1]),
    ("-3. D2/", [-2, -1]),
    (f"{MIND} D2/", [0, -16384]),
    ("-1 0 1 M+", [0, 1]),
    ("1. -1 M+", [0, 0]),
    ("0 1 -1 M+", [-1, 0]),
    ("-5. D>S", [-5]),
    ("1234. D>S", [1234]),
])
def test_double_arithmetic_carries_between_the_cells(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("1000000. 3 4 M*/", [29104, 11]),       # 750000
    ("-1000000. 3 4 M*/", [-29104, -12]),    # -750000
    (f"{MAXD} 32767 32767 M*/", MAX_D),      # needs a triple-cell intermediate
    (f"{MAXD} -1 1 M*/", [1, MIN_N]),
    ("70000. -2 1 M*/", [-8928, -3]),        # -140000
    ("-7. 1 2 M*/", [-4, -1]),               # floored, like the system's /
])
def test_m_star_slash_scales_a_double_by_a_ratio(run, src, expected):
    assert run(src) == expected


# --- comparisons --------------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("-1. D0<", [-1]),
    ("0 -1 D0<", [-1]),
    ("-1 0 D0<", [0]),
    ("0. D0<", [0]),
    ("0. D0=", [-1]),
    ("0 1 D0=", [0]),
    ("1 0 D0=", [0]),
    ("1. 1. D=", [-1]),
    ("1 0 1 1 D=", [0]),
    ("-1. -1. D=", [-1]),
    ("-1. 1. D<", [-1]),
    ("1. -1. D<", [0]),
    ("0 1 -1 0 D<", [0]),
    ("-1 0 0 1 D<", [-1]),
    (f"{MIND} {MAXD} D<", [-1]),
    (f"{MAXD} {MIND} D<", [0]),
    ("1. 1. D<", [0]),
    ("-1. 1. DU<", [0]),
    ("1. -1. DU<", [-1]),
    ("0 1 -1 0 DU<", [0]),
    (f"{MAXD} {MIND} DU<", [-1]),
])
def test_double_comparisons_return_well_formed_flags(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("1. -1. DMAX", [1, 0]),
    ("0 1 -1 0 DMAX", [0, 1]),
    (f"{MIND} {MAXD} DMAX", MAX_D),
    ("1. -1. DMIN", [-1, -1]),
    ("0 1 -1 0 DMIN", [-1, 0]),
    (f"{MIND} {MAXD} DMIN", MIN_D),
])
def test_dmax_and_dmin_compare_signed_doubles(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("1 2 3 4 5 6 2ROT", [3, 4, 5, 6, 1, 2]),
])
def test_two_rot_rotates_the_third_pair_to_the_top(run, src, expected):
    assert run(src) == expected


# --- output ---------------------------------------------------------------------------

@pytest.mark.parametrize("src, shown", [
    ("1234567. D.", "1234567 "),
    ("-1. D.", "-1 "),
    ("0. D.", "0 "),
    (f"{MAXD} D.", "2147483647 "),
    (f"{MIND} D.", "-2147483648 "),
    ("0 1 D.", "65536 "),
    ("123. 6 D.R", "   123"),
    ("-123. 6 D.R", "  -123"),
    ("1234567. 3 D.R", "1234567"),
    ("HEX -1 0 D. DECIMAL", "FFFF "),
])
def test_double_output_prints_the_signed_32_bit_value(out, src, shown):
    assert out(src) == shown
