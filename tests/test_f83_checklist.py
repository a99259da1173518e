"""F83 conformance checklist: eleven one-line checks of where F83 is not
other Forths (docs/forth2012.md, "Core: F83's meanings").

Each test is one item, as the comment above it words it (item 5 is tested
both in strict F83 mode and with RCL literals, docs/guide.md section 3).
"""
import pytest


def run(forth, text):
    return forth.evaluate(text)


# 1. `40000 .` prints `-25536 `; `40000 U.` prints `40000 `.
@pytest.mark.parametrize("text, printed", [
    ("40000 .", "-25536 "),
    ("40000 U.", "40000 "),
])
def test_item_1_forty_thousand_prints_signed_with_dot_and_unsigned_with_u_dot(forth, text, printed):
    assert run(forth, text) == printed


# 2. `1.2 .S` shows 12 and 0 (0 on top); `DPL @ .` then prints `1 `.
def test_item_2_one_point_two_is_the_double_twelve_with_dpl_one(forth):
    assert run(forth, "1.2 .S") == "     12       0 "
    assert run(forth, "DPL @ .") == "1 "


# 3. `-9.999 D.` prints `-9999 `; `DPL @ .` prints `3 `.
def test_item_3_minus_nine_point_nine_nine_nine_prints_as_double_with_dpl_three(forth):
    assert run(forth, "-9.999 D.") == "-9999 "
    assert run(forth, "DPL @ .") == "3 "


# 4. `725 DPL @ .` prints `-1 ` (after the stack is 725).
def test_item_4_a_plain_integer_is_a_single_with_dpl_minus_one(forth):
    assert run(forth, "725 DPL @ .") == "-1 "
    assert forth.stack == [725]


# 5. `: X 1.25 ;  7 X DPL @ .` prints `-1 ` in strict F83 mode.
def test_item_5_strict_f83_compiled_literal_does_not_touch_dpl(forth):
    run(forth, "RCL-LITERALS OFF")
    assert run(forth, ": X 1.25 ;  7 X DPL @ .") == "-1 "


# 5 (RCL literals, the default): the literal restores its compile-time DPL.
def test_item_5_rcl_literal_restores_its_compile_time_dpl_when_run(forth):
    assert run(forth, ": X 1.25 ;  7 X DPL @ .") == "2 "


# 6. `5 NOT .` prints `-6 `; `0 NOT .` prints `-1 `.
@pytest.mark.parametrize("text, printed", [
    ("5 NOT .", "-6 "),
    ("0 NOT .", "-1 "),
])
def test_item_6_not_is_the_bitwise_ones_complement(forth, text, printed):
    assert run(forth, text) == printed


# 7. `-7 2 / .` prints `-4 `; `-7 2 MOD .` prints `1 `.
@pytest.mark.parametrize("text, printed", [
    ("-7 2 / .", "-4 "),
    ("-7 2 MOD .", "1 "),
])
def test_item_7_division_floors_toward_negative_infinity(forth, text, printed):
    assert run(forth, text) == printed


# 8. `0 10 DO I . -1 +LOOP` (inside a definition) prints 11 numbers ending `0 `.
def test_item_8_counting_down_with_minus_one_plus_loop_prints_eleven_numbers(forth):
    run(forth, ": T 0 10 DO I . -1 +LOOP ;")
    assert run(forth, "T") == "10 9 8 7 6 5 4 3 2 1 0 "


# 9. `foo` prints `FOO  ? ` and no `ok`.
def test_item_9_unknown_word_shows_upper_cased_token_and_question_mark_without_ok(forth):
    assert forth.session("foo") == "foo FOO  ? \n"


# 10. `: A 1 ; : A 2 ;` prints `A isn't unique `.
def test_item_10_redefining_a_word_warns_that_it_isnt_unique(forth):
    assert "A isn't unique " in forth.session(": A 1 ; : A 2 ;")


# 11. `7 0 /` leaves 0, `7 0 MOD` leaves 7.
@pytest.mark.parametrize("text, left", [
    ("7 0 /", [0]),
    ("7 0 MOD", [7]),
])
def test_item_11_division_by_zero_does_not_trap(forth, text, left):
    run(forth, text)
    assert forth.stack == left
