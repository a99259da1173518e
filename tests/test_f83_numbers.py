"""Number input: F83 conversion, DPL, BASE, wrap-around and doubles in memory.

Spec: F83's cells and number input (docs/forth2012.md, "Core: F83's meanings");
RCL literals: docs/guide.md section 3.
Cells are read back signed through `Forth.stack` (low cell, then high cell).
"""
import pytest


def run(forth, text):
    return forth.evaluate(text)


def dpl(forth):
    return run(forth, "DPL @ .")


def error_from(forth, text):
    import rcl
    with pytest.raises(rcl.ForthError) as info:
        forth.evaluate(text)
    return info.value


# ---------------------------------------------------------------------------
# Worked examples (decimal base)
# ---------------------------------------------------------------------------

# typed, cells pushed (signed, low then high), DPL afterwards
TABLE = [
    ("725", [725], -1),
    ("-1.", [-1, -1], 0),
    ("1.", [1, 0], 0),
    ("1.2", [12, 0], 1),
    ("-9.999", [-9999, -1], 3),
    ("38.04", [3804, 0], 2),
    ("932.015", [14511, 14], 3),      # d = 932015 = 14 * 65536 + 14511
    (".1", [1, 0], 1),
    ("-.5", [-5, -1], 1),
    ("25.5", [255, 0], 1),
    ("8.5", [85, 0], 1),
    ("1,000", [1000, 0], 3),
    ("12/25", [1225, 0], 2),
    ("1.2.3", [123, 0], 1),
    ("100000", [-31072], -1),          # 34464 = 0x86A0, wrapped single
]


@pytest.mark.parametrize("typed, cells, _", TABLE)
def test_typed_number_pushes_the_cells_of_the_worked_examples_table(forth, typed, cells, _):
    run(forth, typed)
    assert forth.stack == cells


@pytest.mark.parametrize("typed, _, expected_dpl", TABLE)
def test_typed_number_leaves_dpl_as_in_the_worked_examples_table(forth, typed, _, expected_dpl):
    run(forth, typed)
    assert dpl(forth) == f"{expected_dpl} "


def test_number_with_trailing_garbage_is_an_undefined_word(forth):
    assert error_from(forth, "1.2X").code == -13


def test_failed_conversion_of_one_point_two_x_still_counted_dpl_one(forth):
    error_from(forth, "1.2X")
    assert dpl(forth) == "1 "


def test_token_of_punctuation_without_any_digit_is_not_a_number(forth):
    # No digit at all is no number. A bare `-` is the subtraction word, so
    # the rule is exercised with a punctuation-only non-word.
    assert error_from(forth, "-.").code == -13


def test_token_without_any_digit_leaves_dpl_unchanged(forth):
    run(forth, "38.04 2DROP")
    error_from(forth, "-.")
    assert dpl(forth) == "2 "


def test_leading_plus_sign_is_not_a_number(forth):
    assert error_from(forth, "+5").code == -13


def test_over_long_double_wraps_modulo_two_to_the_thirty_second(forth):
    run(forth, "4294967297.")
    assert forth.stack == [1, 0]


# ---------------------------------------------------------------------------
# Singles wrap to 16 bits
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("typed, cell", [
    ("70000", 4464),
    ("-70000", -4464),
    ("40000", -25536),
    ("65535", -1),
])
def test_single_number_keeps_only_the_low_sixteen_bits(forth, typed, cell):
    run(forth, typed)
    assert forth.stack == [cell]


def test_forty_thousand_prints_unsigned_with_u_dot(forth):
    assert run(forth, "40000 U.") == "40000 "


# ---------------------------------------------------------------------------
# Single-cell arithmetic is modulo 2^16
# ---------------------------------------------------------------------------

def test_largest_positive_cell_plus_one_wraps_to_most_negative(forth):
    run(forth, "32767 1+")
    assert forth.stack == [-32768]


def test_negating_the_most_negative_cell_gives_itself(forth):
    run(forth, "-32768 NEGATE")
    assert forth.stack == [-32768]


def test_cells_are_stored_little_endian(forth):
    assert run(forth, "VARIABLE V  258 V !  V C@ . V 1+ C@ .") == "2 1 "


def test_c_fetch_zero_extends_the_byte(forth):
    assert run(forth, "VARIABLE V  -1 V !  V C@ .") == "255 "


def test_two_store_puts_the_high_cell_at_the_lower_address(forth):
    assert run(forth, "2VARIABLE D  1. D 2!  D @ . D 2+ @ .") == "0 1 "


def test_two_fetch_reads_the_high_cell_from_the_lower_address(forth):
    run(forth, "2VARIABLE D  5 D !  7 D 2+ !  D 2@")
    assert forth.stack == [7, 5]


# ---------------------------------------------------------------------------
# BASE
# ---------------------------------------------------------------------------

def test_machine_starts_in_decimal(forth):
    assert run(forth, "BASE @ .") == "10 "


@pytest.mark.parametrize("word, base", [
    ("DECIMAL", 10),
    ("HEX", 16),
    ("OCTAL", 8),
])
def test_base_words_store_their_radix_in_base(forth, word, base):
    run(forth, f"{word} BASE @ DECIMAL")
    assert forth.stack == [base]


@pytest.mark.parametrize("text, cells", [
    ("HEX FF", [255]),
    ("HEX ff", [255]),
    ("HEX -ff", [-255]),
    ("HEX 1.0", [16, 0]),
    ("OCTAL 17", [15]),
])
def test_input_is_converted_in_the_current_base(forth, text, cells):
    run(forth, text)
    assert forth.stack == cells


def test_output_is_printed_in_the_current_base(forth):
    assert run(forth, "255 HEX .") == "FF "


def test_letters_are_not_digits_in_decimal(forth):
    assert error_from(forth, "FF").code == -13


def test_digit_eight_is_not_a_digit_in_octal(forth):
    assert error_from(forth, "OCTAL 8").code == -13


# ---------------------------------------------------------------------------
# Compiled numbers, and RCL literals (docs/guide.md section 3)
# ---------------------------------------------------------------------------

def test_compiled_single_literal_pushes_one_cell(forth):
    run(forth, ": Y 725 ;  Y")
    assert forth.stack == [725]


def test_compiled_double_literal_pushes_two_cells(forth):
    run(forth, ": X 1.25 ;  X")
    assert forth.stack == [125, 0]


def test_rcl_literals_are_on_by_default(forth):
    assert run(forth, "RCL-LITERALS @ 0= .") == "0 "


def test_rcl_single_literal_sets_dpl_to_minus_one_when_run(forth):
    assert run(forth, ": Y 725 ;  1.2 Y DPL @ .") == "-1 "


def test_strict_f83_single_literal_leaves_dpl_as_the_last_typed_number_set_it(forth):
    run(forth, "RCL-LITERALS OFF")
    assert run(forth, ": Y 725 ;  1.2 Y DPL @ .") == "1 "


def test_interpreted_number_sets_dpl_with_rcl_literals_on(forth):
    assert run(forth, ": X 1.25 ;  X 38.04 DPL @ .") == "2 "


def test_digit_of_a_cell_that_upper_cases_to_two_letters_is_no_digit(forth):
    # 223 is German sharp s (upper case SS), 0xFB06 the ligature st (ST):
    # not digits in any base, never a Python error (found by the fuzz).
    m = forth
    assert m.evaluate("223 36 DIGIT . . 64262 36 DIGIT . U.") == "0 223 0 64262 "
    assert m.evaluate("90 36 DIGIT . .") == "-1 35 "   # Z
