"""Arithmetic: flags, NOT, mixed multiply/divide, doubles, RCL-support words.

Spec: F83's flags and arithmetic (docs/forth2012.md, "Core: F83's meanings").
Results are read back signed through
`Forth.stack`; a double shows as [low, high].
"""
import pytest


def run(forth, text):
    return forth.evaluate(text)


def stack_after(forth, text):
    run(forth, text)
    return forth.stack


# ---------------------------------------------------------------------------
# Truth values and NOT
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("text, result", [
    ("5 NOT", [-6]),
    ("0 NOT", [-1]),
    ("-1 NOT", [0]),
])
def test_not_is_a_bitwise_complement(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, flag", [
    ("3 3 =", -1), ("3 4 =", 0),
    ("3 4 <>", -1), ("3 3 <>", 0),
    ("-1 1 <", -1), ("1 -1 <", 0),
    ("1 -1 >", -1), ("-1 1 >", 0),
    ("1 -1 U<", -1), ("-1 1 U<", 0),
    ("-1 1 U>", -1), ("1 -1 U>", 0),
    ("0 0=", -1), ("5 0=", 0),
    ("-5 0<", -1), ("5 0<", 0),
    ("5 0>", -1), ("-5 0>", 0),
    ("5 0<>", -1), ("0 0<>", 0),
])
def test_comparisons_return_minus_one_for_true_and_zero_for_false(forth, text, flag):
    assert stack_after(forth, text) == [flag]


@pytest.mark.parametrize("word, value", [("TRUE", -1), ("FALSE", 0)])
def test_true_and_false_constants(forth, word, value):
    assert stack_after(forth, word) == [value]


@pytest.mark.parametrize("word, value", [("ON", -1), ("OFF", 0)])
def test_on_and_off_store_a_flag_at_an_address(forth, word, value):
    assert stack_after(forth, f"VARIABLE V 5 V ! V {word} V @") == [value]


# ---------------------------------------------------------------------------
# Mixed and multiply/divide words
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("text, result", [
    ("65535 65535 UM*", [1, -2]),          # 0xFFFE0001
    ("300 300 UM*", [24464, 1]),           # 90000
])
def test_um_star_is_an_unsigned_sixteen_by_sixteen_multiply(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("-2 3 *D", [-6, -1]),
    ("300 300 *D", [24464, 1]),
    ("-300 300 *D", [-24464, -2]),         # -90000
])
def test_star_d_is_a_signed_sixteen_by_sixteen_multiply(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("100000. 7 UM/MOD", [5, 14285]),
    ("-1 0 2 UM/MOD", [1, 32767]),         # ud = 65535
])
def test_um_slash_mod_divides_unsigned(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text", [
    "10. 0 UM/MOD",                        # divisor 0
    "0 5 5 UM/MOD",                        # high cell >= divisor
    "-1. 1 UM/MOD",                        # quotient does not fit
])
def test_um_slash_mod_does_not_trap_and_returns_all_ones(forth, text):
    assert stack_after(forth, text) == [-1, -1]


@pytest.mark.parametrize("text, result", [
    ("100000. 7 M/MOD", [5, 14285]),
    ("-7. 2 M/MOD", [1, -4]),
    ("7. -2 M/MOD", [-1, -4]),
    ("-7. -2 M/MOD", [-1, 3]),
])
def test_m_slash_mod_is_signed_and_floored(forth, text, result):
    assert stack_after(forth, text) == result


def test_m_slash_mod_by_zero_leaves_the_two_cells_of_the_dividend(forth):
    assert stack_after(forth, "100000. 0 M/MOD") == [-31072, 1]


@pytest.mark.parametrize("text, result", [
    ("100000. 7 MU/MOD", [5, 14285, 0]),
    ("-1. 2 MU/MOD", [1, -1, 32767]),      # 0xFFFFFFFF / 2
])
def test_mu_slash_mod_gives_a_double_quotient(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("300 300 *", [24464]),
    ("-3 4 *", [-12]),
])
def test_star_keeps_the_low_sixteen_bits_of_the_product(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("-7 2 /", [-4]),
    ("-7 2 MOD", [1]),
    ("7 -2 /", [-4]),
    ("7 -2 MOD", [-1]),
    ("-7 -2 /", [3]),
    ("-7 -2 MOD", [-1]),
    ("7 2 /MOD", [1, 3]),
    ("-7 2 /MOD", [1, -4]),
])
def test_signed_division_floors_toward_negative_infinity(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("7 0 /", [0]),
    ("7 0 MOD", [7]),
    ("7 0 /MOD", [7, 0]),
])
def test_division_by_zero_follows_m_slash_mod_doing_nothing(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("1000 1000 100 */", [10000]),
    ("20000 3 4 */", [15000]),
    ("-7 1 2 */", [-4]),
    ("1000 1000 300 */MOD", [100, 3333]),
    ("-7 1 2 */MOD", [1, -4]),
])
def test_star_slash_uses_a_thirty_two_bit_intermediate_and_floors(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("-5 ABS", [5]),
    ("-32768 ABS", [-32768]),
    ("5 NEGATE", [-5]),
    ("3 -5 MIN", [-5]),
    ("3 -5 MAX", [3]),
    ("7 1+", [8]), ("7 1-", [6]), ("7 2+", [9]), ("7 2-", [5]),
    ("-7 2*", [-14]),
])
def test_simple_single_cell_arithmetic(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("-3 2/", [-2]),
    ("7 2/", [3]),
    ("-1 2/", [-1]),
])
def test_two_slash_is_an_arithmetic_shift_that_floors(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("-2 U2/", [32767]),
    ("-1 U2/", [32767]),
    ("8 U2/", [4]),
])
def test_u_two_slash_is_a_logical_shift_right(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, flag", [
    ("1 1 5 BETWEEN", -1),
    ("5 1 5 BETWEEN", -1),
    ("0 1 5 BETWEEN", 0),
    ("6 1 5 BETWEEN", 0),
    ("-3 -5 -1 BETWEEN", -1),
])
def test_between_is_inclusive_at_both_ends(forth, text, flag):
    assert stack_after(forth, text) == [flag]


@pytest.mark.parametrize("text, flag", [
    ("1 1 5 WITHIN", -1),
    ("4 1 5 WITHIN", -1),
    ("5 1 5 WITHIN", 0),
    ("0 1 5 WITHIN", 0),
    ("-3 -5 -1 WITHIN", -1),
])
def test_within_excludes_the_upper_limit(forth, text, flag):
    assert stack_after(forth, text) == [flag]


# ---------------------------------------------------------------------------
# Double numbers
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("text, result", [
    ("1 2 2DUP", [1, 2, 1, 2]),
    ("1 2 3 2DROP", [1]),
    ("1 2 3 4 2SWAP", [3, 4, 1, 2]),
    ("1 2 3 4 2OVER", [1, 2, 3, 4, 1, 2]),
    ("1 2 3 4 5 6 2ROT", [3, 4, 5, 6, 1, 2]),
    ("1 2 3 3DUP", [1, 2, 3, 1, 2, 3]),
    ("1 2 3 4 4DUP", [1, 2, 3, 4, 1, 2, 3, 4]),
])
def test_cell_pair_stack_words(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("1. 1. D+", [2, 0]),
    ("65535. 1. D+", [0, 1]),
    ("-1. -1. D+", [-2, -1]),
    ("2147483647. 1. D+", [0, -32768]),    # wraps modulo 2^32
    ("1. 2. D-", [-1, -1]),
    ("65536. 1. D-", [-1, 0]),
])
def test_double_add_and_subtract_carry_between_cells(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("1. DNEGATE", [-1, -1]),
    ("100000. DNEGATE", [31072, -2]),
    ("-100000. DABS", [-31072, 1]),
    ("100000. DABS", [-31072, 1]),
])
def test_dnegate_and_dabs(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("100000. -1 ?DNEGATE", [31072, -2]),
    ("100000. 1 ?DNEGATE", [-31072, 1]),
    ("100000. 0 ?DNEGATE", [-31072, 1]),
])
def test_question_dnegate_negates_only_for_a_negative_sign(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("5 S>D", [5, 0]),
    ("-5 S>D", [-5, -1]),
    ("-32768 S>D", [-32768, -1]),
])
def test_s_to_d_sign_extends(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, flag", [
    ("-1. 1. D<", -1),
    ("1. -1. D<", 0),
    ("65535. 65536. D<", -1),
    ("1. 65535. D<", -1),                  # equal high cells: low compared unsigned
    ("65535. 1. D<", 0),
    ("1. -1. D>", -1),
    ("-1. 1. D>", 0),
])
def test_d_less_compares_high_cells_signed_then_low_cells_unsigned(forth, text, flag):
    assert stack_after(forth, text) == [flag]


@pytest.mark.parametrize("text, flag", [
    ("1. -1. DU<", -1),
    ("-1. 1. DU<", 0),
])
def test_du_less_is_an_unsigned_double_compare(forth, text, flag):
    assert stack_after(forth, text) == [flag]


@pytest.mark.parametrize("text, flag", [
    ("100000. 100000. D=", -1),
    ("100000. 100001. D=", 0),
    ("0. D0=", -1),
    ("65536. D0=", 0),
])
def test_double_equality_flags(forth, text, flag):
    assert stack_after(forth, text) == [flag]


@pytest.mark.parametrize("text, result", [
    ("-1. 1. DMIN", [-1, -1]),
    ("-1. 1. DMAX", [1, 0]),
    ("100000. 70000. DMIN", [4464, 1]),
    ("100000. 70000. DMAX", [-31072, 1]),
])
def test_dmin_and_dmax_are_signed(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("100000. D2*", [3392, 3]),            # 200000
    ("32768. D2*", [0, 1]),
    ("-3. D2/", [-2, -1]),
    ("65536. D2/", [-32768, 0]),
])
def test_d_two_star_and_d_two_slash_shift_across_cells(forth, text, result):
    assert stack_after(forth, text) == result


# ---------------------------------------------------------------------------
# RCL-support extensions (not in F83)
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("text, result", [
    ("-2 3 M*", [-6, -1]),
    ("300 300 M*", [24464, 1]),
])
def test_m_star_is_an_alias_of_star_d(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("100000. 7 M/", [14285]),
    ("-7. 2 M/", [-4]),
])
def test_m_slash_is_the_floored_quotient_of_m_slash_mod(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("100000. 3 2 M*/", [18928, 2]),        # 150000
    ("2000000000. 3 4 M*/", [12032, 22888]),  # 1,500,000,000 via a 48-bit product
    ("-7. 1 2 M*/", [-4, -1]),
])
def test_m_star_slash_scales_a_double_with_a_wide_intermediate_and_floors(forth, text, result):
    assert stack_after(forth, text) == result


@pytest.mark.parametrize("text, result", [
    ("100000. 1 M+", [-31071, 1]),
    ("0. -1 M+", [-1, -1]),
    ("65535. 1 M+", [0, 1]),
])
def test_m_plus_adds_a_sign_extended_single_to_a_double(forth, text, result):
    assert stack_after(forth, text) == result
