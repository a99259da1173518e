"""Forth 2012 Core word set on a 16-bit F83 machine.

Cells are 16 bits: MAX-N = 32767, MIN-N = -32768, MAX-U = 65535 (shown on
the Python-side stack as -1, because `forth.stack` holds signed ints).
Division is floored.  A double is two stack items: low cell, then high cell.
"""
import pytest

MAX_N, MIN_N = 32767, -32768


# --- stack manipulation ---------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("1 DUP", [1, 1]),
    ("1 2 DROP", [1]),
    ("1 2 SWAP", [2, 1]),
    ("1 2 OVER", [1, 2, 1]),
    ("1 2 3 ROT", [2, 3, 1]),
    ("0 ?DUP", [0]),
    ("5 ?DUP", [5, 5]),
    ("DEPTH", [0]),
    ("7 8 9 DEPTH", [7, 8, 9, 3]),
    ("1 2 3 2DROP", [1]),
    ("1 2 2DUP", [1, 2, 1, 2]),
    ("1 2 3 4 2OVER", [1, 2, 3, 4, 1, 2]),
    ("1 2 3 4 2SWAP", [3, 4, 1, 2]),
])
def test_stack_words_rearrange_the_data_stack(run, src, expected):
    assert run(src) == expected


def test_return_stack_words_move_cells_between_the_stacks(run):
    assert run(": T >R 5 R@ R> ; 3 T") == [5, 3, 3]


# --- arithmetic -------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("1 2 +", [3]),
    ("32767 1 +", [MIN_N]),
    ("1 2 -", [-1]),
    ("-32768 1 -", [MAX_N]),
    ("6 7 *", [42]),
    ("-1 -1 *", [1]),
    ("256 256 *", [0]),
    ("32767 1+", [MIN_N]),
    ("-32768 1-", [MAX_N]),
    ("5 NEGATE", [-5]),
    ("-32768 NEGATE", [MIN_N]),
    ("-5 ABS", [5]),
    ("32767 ABS", [MAX_N]),
    ("-1 1 MAX", [1]),
    ("-32768 32767 MIN", [MIN_N]),
    ("16384 2*", [MIN_N]),
    ("-32768 2*", [0]),
    ("-1 2/", [-1]),
    ("-3 2/", [-2]),
    ("-32768 2/", [-16384]),
    ("-5 S>D", [-5, -1]),
    ("5 S>D", [5, 0]),
])
def test_single_cell_arithmetic_wraps_at_sixteen_bits(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("7 2 /", [3]),
    ("-7 2 /", [-4]),
    ("7 -2 /", [-4]),
    ("-7 -2 /", [3]),
    ("7 2 MOD", [1]),
    ("-7 2 MOD", [1]),
    ("7 -2 MOD", [-1]),
    ("-7 -2 MOD", [-1]),
    ("-7 2 /MOD", [1, -4]),
    ("32767 -1 /", [-MAX_N]),
])
def test_division_of_single_cells_is_floored(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("7 S>D 2 FM/MOD", [1, 3]),
    ("-7 S>D 2 FM/MOD", [1, -4]),
    ("7 S>D -2 FM/MOD", [-1, -4]),
    ("-7 S>D -2 FM/MOD", [-1, 3]),
    ("0 1 4 FM/MOD", [0, 16384]),
    ("0 -1 4 FM/MOD", [0, -16384]),
    ("-32768 S>D 1 FM/MOD", [0, MIN_N]),
    ("7 S>D 2 SM/REM", [1, 3]),
    ("-7 S>D 2 SM/REM", [-1, -3]),
    ("7 S>D -2 SM/REM", [1, -3]),
    ("-7 S>D -2 SM/REM", [-1, 3]),
    ("1 0 -2 SM/REM", [1, 0]),
    ("-32768 S>D 1 SM/REM", [0, MIN_N]),
])
def test_fm_mod_floors_and_sm_rem_truncates_a_double_dividend(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("7 0 2 UM/MOD", [1, 3]),
    ("0 1 2 UM/MOD", [0, MIN_N]),           # 65536 / 2 = 32768 (unsigned)
    ("-1 32767 -1 UM/MOD", [MAX_N, MIN_N]),  # 7FFFFFFF / FFFF
    ("3 4 UM*", [12, 0]),
    ("-1 -1 UM*", [1, -2]),                 # FFFF * FFFF = FFFE0001
    ("-1 2 UM*", [-2, 1]),
    ("3 -4 M*", [-12, -1]),
    ("32767 32767 M*", [1, 16383]),
    ("-32768 -32768 M*", [0, 16384]),
    ("-32768 32767 M*", [MIN_N, -16384]),
])
def test_mixed_precision_multiply_and_divide_use_the_full_double(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("20000 3 4 */", [15000]),      # 60000 does not fit a single cell
    ("-20000 3 4 */", [-15000]),
    ("-7 1 2 */", [-4]),
    ("32767 32767 32767 */", [MAX_N]),
    ("20000 3 7 */MOD", [3, 8571]),
    ("-7 1 2 */MOD", [1, -4]),
])
def test_star_slash_keeps_a_double_intermediate_and_floors(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("1 15 LSHIFT", [MIN_N]),
    ("-1 8 LSHIFT", [-256]),
    ("1 0 LSHIFT", [1]),
    ("-1 1 RSHIFT", [MAX_N]),           # logical, not arithmetic
    ("-32768 15 RSHIFT", [1]),
    ("-1 15 RSHIFT", [1]),
    ("12 0 RSHIFT", [12]),
    ("-1 0 AND", [0]),
    ("12 10 AND", [8]),
    ("12 10 OR", [14]),
    ("12 10 XOR", [6]),
    ("0 INVERT", [-1]),
    ("21845 INVERT", [-21846]),
])
def test_bitwise_words_work_on_sixteen_bit_cells(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("0 0=", [-1]),
    ("1 0=", [0]),
    ("-1 0<", [-1]),
    ("0 0<", [0]),
    ("-32768 0<", [-1]),
    ("1 1 =", [-1]),
    ("1 2 =", [0]),
    ("-1 0 <", [-1]),
    ("-32768 32767 <", [-1]),
    ("32767 -32768 <", [0]),
    ("32767 -32768 >", [-1]),
    ("2 2 >", [0]),
    ("0 -1 U<", [-1]),
    ("-1 0 U<", [0]),
    ("-32768 32767 U<", [0]),
    ("32767 -32768 U<", [-1]),
])
def test_comparisons_return_well_formed_flags(run, src, expected):
    assert run(src) == expected


# --- memory -----------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("VARIABLE V 5 V ! V @", [5]),
    ("VARIABLE V 5 V ! 3 V +! V @", [8]),
    ("VARIABLE V -1 V ! V @", [-1]),
    ("CREATE X 4 ALLOT 1 2 X 2! X @ X CELL+ @", [2, 1]),
    ("CREATE X 4 ALLOT 1 2 X 2! X 2@", [1, 2]),
    ("CREATE X 2 ALLOT -1 X C! X C@", [255]),
    ("CREATE X 2 ALLOT 258 X ! X C@ X CHAR+ C@ + X @", [3, 258]),
    ("HERE 1 CELLS ALLOT HERE SWAP -", [2]),
    ("HERE 5 , HERE SWAP - ", [2]),
    ("HERE 7 , @", [7]),
    ("HERE 7 C, HERE SWAP - ", [1]),
    ("HERE 200 C, C@", [200]),
    ("42 CONSTANT K K K +", [84]),
    ("1 CELLS 3 CELLS", [2, 6]),
    ("1 CHARS 3 CHARS", [1, 3]),
    ("100 CELL+ 100 CHAR+", [102, 101]),
])
def test_memory_words_store_fetch_and_allocate(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("addr", [100, 101, 102, 103])
def test_aligned_rounds_up_to_an_aligned_address_by_less_than_a_cell(run, addr):
    (a,) = run(f"{addr} ALIGNED")
    assert addr <= a < addr + 2
    assert run("ALIGNED") == [a]  # already aligned: unchanged


def test_align_leaves_here_aligned(run):
    assert run("HERE 1 ALLOT DROP ALIGN HERE DUP ALIGNED =") == [-1]


def test_fill_sets_every_char_of_a_region(out):
    assert out("CREATE B 8 ALLOT B 8 CHAR * FILL B 8 TYPE") == "********"


def test_fill_with_zero_count_changes_nothing(out):
    assert out("CREATE B 2 ALLOT B 2 CHAR a FILL B 0 CHAR z FILL B 2 TYPE") == "aa"


@pytest.mark.parametrize("move, shown", [
    ("B B 1+ 4 MOVE", "aabcdfgh"),   # overlapping, moving up
    ("B 1+ B 4 MOVE", "bcdeefgh"),   # overlapping, moving down
    ("B 4 + B 4 MOVE", "efghefgh"),
    ("B B 5 + 0 MOVE", "abcdefgh"),
])
def test_move_copies_correctly_even_when_regions_overlap(out, move, shown):
    out('CREATE B 8 ALLOT S" abcdefgh" B SWAP MOVE')
    assert out(move + " B 8 TYPE") == shown


def test_count_turns_a_counted_string_into_address_and_length(run):
    assert run("CREATE CS 3 C, CHAR a C, CS COUNT SWAP CS -") == [3, 1]


# --- characters, strings and output ----------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("BL", [32]),
    ("CHAR A", [65]),
    ("CHAR abc", [97]),
    (": T [CHAR] z ; T", [122]),
    (": T [CHAR] ZED ; T", [90]),
])
def test_char_words_give_the_first_character_of_the_next_word(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, shown", [
    ("5 .", "5 "),
    ("-5 .", "-5 "),
    ("0 .", "0 "),
    ("32767 .", "32767 "),
    ("-32768 .", "-32768 "),
    ("-1 U.", "65535 "),
    ("255 HEX . DECIMAL", "FF "),
    ("65 EMIT", "A"),
    ("SPACE", " "),
    ("3 SPACES", "   "),
    ("0 SPACES", ""),
    ("-2 SPACES", ""),
    ('S" hello" TYPE', "hello"),
    (': T ." hi there" ; T', "hi there"),
    (': T S" abc" TYPE ; T', "abc"),
    ("1 ( 2 ) .", "1 "),
])
def test_output_words_print_exactly_what_is_specified(out, src, shown):
    assert out(src) == shown


def test_cr_starts_a_new_line(out):
    assert out("65 EMIT CR 66 EMIT").replace("\r\n", "\n") == "A\nB"


def test_s_quote_gives_address_and_length_of_the_string(run):
    assert run(': T S" hello" ; T SWAP DROP') == [5]
    assert run('DROP S" abc" DROP C@') == [97]


@pytest.mark.parametrize("src, shown", [
    ("123 0 <# #S #> TYPE", "123"),
    ("0 0 <# #S #> TYPE", "0"),
    ("1234 0 <# # # #> TYPE", "34"),
    ("70000. <# #S #> TYPE", "70000"),
    ("-123 DUP ABS 0 <# #S ROT SIGN #> TYPE", "-123"),
    ("123 DUP ABS 0 <# #S ROT SIGN #> TYPE", "123"),
    ("5 0 <# #S CHAR $ HOLD #> TYPE", "$5"),
    ("5 0 <# CHAR % HOLD #S #> TYPE", "5%"),
    ("255 0 HEX <# #S #> DECIMAL TYPE", "FF"),
    ("5 0 2 BASE ! <# #S #> DECIMAL TYPE", "101"),
])
def test_pictured_numeric_output_builds_the_string_right_to_left(out, src, shown):
    assert out(src) == shown


def test_ending_the_picture_gives_the_length_of_the_converted_string(run):
    assert run("12345 0 <# #S #> SWAP DROP") == [5]


@pytest.mark.parametrize("src, expected", [
    ('0 0 S" 123" >NUMBER SWAP DROP', [123, 0, 0]),
    ('0 0 S" 12X4" >NUMBER SWAP C@', [12, 0, 2, 88]),
    ('1 0 S" 5" >NUMBER 2DROP', [15, 0]),
    ('0 0 S" 70000" >NUMBER 2DROP', [4464, 1]),
    ('0 0 S" FF" HEX >NUMBER DECIMAL 2DROP', [255, 0]),
    ('0 0 S" -5" >NUMBER SWAP DROP', [0, 0, 2]),
    ('0 0 S" " >NUMBER SWAP DROP', [0, 0, 0]),
])
def test_to_number_accumulates_digits_until_a_non_digit(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("DECIMAL BASE @", [10]),
    ("HEX BASE @ DECIMAL", [16]),
    ("HEX FF DECIMAL", [255]),
    ("2 BASE ! 1010 DECIMAL", [10]),
    ("36 BASE ! Z DECIMAL", [35]),
])
def test_base_controls_number_conversion(run, src, expected):
    assert run(src) == expected


# --- defining words -----------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("CREATE X 1 , 2 , X @ X CELL+ @", [1, 2]),
    ("CREATE X HERE X =", [-1]),
    ("CREATE X ' X >BODY X =", [-1]),
    (": CONST CREATE , DOES> @ ; 7 CONST SEVEN SEVEN", [7]),
    (": ADDER CREATE , DOES> @ + ; 10 ADDER ADD10 5 ADD10", [15]),
    (": MK CREATE DOES> ; MK Y ' Y >BODY Y =", [-1]),
    ("VARIABLE V : T 9 V ! ; T V @", [9]),
    (": T 1 EXIT 2 ; T", [1]),
])
def test_defining_words_create_words_with_the_specified_behaviour(run, src, expected):
    assert run(src) == expected


def test_immediate_words_execute_while_compiling(run):
    assert run("VARIABLE V 0 V ! : SET 1 V ! ; IMMEDIATE : T SET ; V @") == [1]


def test_postpone_of_an_immediate_word_compiles_it(run):
    src = ": ENDIF POSTPONE THEN ; IMMEDIATE : T IF 1 ELSE 2 ENDIF ; -1 T 0 T"
    assert run(src) == [1, 2]


def test_postpone_of_a_normal_word_compiles_a_call_to_it(run):
    assert run(": DUP, POSTPONE DUP ; IMMEDIATE : T DUP, * ; 5 T") == [25]


def test_brackets_and_literal_compile_a_value_computed_while_compiling(run):
    assert run(": T [ 3 4 + ] LITERAL ; T") == [7]


def test_state_is_false_when_interpreting_and_true_when_compiling(run):
    src = ": ST STATE @ ; IMMEDIATE ST : T ST LITERAL ; T 0="
    assert run(src) == [0, 0]


@pytest.mark.parametrize("src, expected", [
    ("' DUP 5 SWAP EXECUTE", [5, 5]),
    (": T ['] + ; 2 3 T EXECUTE", [5]),
    (": SQ DUP * ; 4 ' SQ EXECUTE", [16]),
])
def test_tick_and_execute_run_words_by_execution_token(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    (": T-N ; BL WORD T-N FIND SWAP ' T-N =", [-1, -1]),
    (": T-I ; IMMEDIATE BL WORD T-I FIND SWAP ' T-I =", [1, -1]),
    ("BL WORD XYZZY DUP FIND SWAP ROT =", [0, -1]),
])
def test_find_returns_xt_and_1_for_immediate_or_minus_1_otherwise(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, shown", [
    ("BL WORD HELLO COUNT TYPE", "HELLO"),
    ("BL WORD     spaced COUNT TYPE", "spaced"),
    (": PW [CHAR] , WORD COUNT TYPE ; PW ab,", "ab"),
])
def test_word_parses_a_counted_string_skipping_leading_delimiters(out, src, shown):
    assert out(src) == shown


# --- control flow -------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    (": T IF 1 THEN 2 ; -1 T 0 T", [1, 2, 2]),
    (": T IF 1 ELSE 2 THEN ; 5 T 0 T", [1, 2]),
    (": T BEGIN DUP 1- DUP 0= UNTIL ; 3 T", [3, 2, 1, 0]),
    (": T BEGIN DUP WHILE DUP 1- REPEAT ; 3 T", [3, 2, 1, 0]),
    (": FACT DUP 1 > IF DUP 1- RECURSE * THEN ; 7 FACT", [5040]),
])
def test_conditionals_loops_and_recursion_branch_as_specified(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    (": T 5 0 DO I LOOP ; T", [0, 1, 2, 3, 4]),
    (": T 10 0 DO I 3 +LOOP ; T", [0, 3, 6, 9]),
    (": T 0 5 DO I -1 +LOOP ; T", [5, 4, 3, 2, 1, 0]),
    (": T 0 10 DO I -3 +LOOP ; T", [10, 7, 4, 1]),
    (": T -3 -1 DO I -1 +LOOP ; T", [-1, -2, -3]),
    (": T 6 0 DO I 2 +LOOP ; T", [0, 2, 4]),
    (": T 32767 32765 DO I LOOP ; T", [32765, 32766]),
    (": T -32767 32766 DO I LOOP ; T", [32766, MAX_N, MIN_N]),
    (": T 3 0 DO 2 0 DO J I LOOP LOOP ; T", [0, 0, 0, 1, 1, 0, 1, 1, 2, 0, 2, 1]),
])
def test_counted_loops_stop_when_the_index_crosses_the_limit(run, src, expected):
    assert run(src) == expected


def test_leave_exits_the_loop_at_once(run):
    assert run(": T 10 0 DO I 3 = IF LEAVE THEN I LOOP 99 ; T") == [0, 1, 2, 99]


def test_unloop_then_exit_returns_from_inside_a_loop(run):
    src = ": T 10 0 DO I 3 = IF I UNLOOP EXIT THEN LOOP 99 ; T"
    assert run(src) == [3]


def test_unloop_exit_works_from_a_nested_loop(run):
    src = ": T 5 0 DO 5 0 DO J I + 3 = IF J I UNLOOP UNLOOP EXIT THEN LOOP LOOP ; T"
    assert run(src) == [0, 3]


# --- the text interpreter ------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ('S" 1 2 +" EVALUATE', [3]),
    (': T S" 2 3 *" EVALUATE ; T', [6]),
    ('S" : SQ DUP * ;" EVALUATE 5 SQ', [25]),
    ('S" 1" EVALUATE 2', [1, 2]),
    ('S" " EVALUATE', []),
    ('S" >IN @ 123" EVALUATE', [6, 123]),
    ('S" SOURCE" EVALUATE SWAP DROP', [6]),
])
def test_evaluate_interprets_a_string_then_resumes_the_old_input(run, src, expected):
    assert run(src) == expected


def test_setting_to_in_to_zero_reinterprets_the_line(run):
    run("VARIABLE N 0 N ! : AGAIN? N @ 3 < IF 0 >IN ! THEN ;")
    assert run("1 N +! AGAIN?") == []
    assert run("N @") == [3]


def test_setting_to_in_to_zero_reinterprets_an_evaluated_string(run):
    run("VARIABLE N 0 N ! : AGAIN? N @ 3 < IF 0 >IN ! THEN ;")
    assert run('S" 1 N +! AGAIN?" EVALUATE N @') == [3]


def test_advancing_to_in_skips_input(run):
    assert run(": SKIP-WORD BL WORD DROP ; SKIP-WORD 99 7") == [7]


def test_source_gives_the_whole_current_input_line(out):
    assert out("SOURCE TYPE") == "SOURCE TYPE"


@pytest.mark.parametrize("query, expected", [
    ("MAX-N", [MAX_N, -1]),
    ("MAX-U", [-1, -1]),
    ("MAX-D", [-1, MAX_N, -1]),
    ("MAX-UD", [-1, -1, -1]),
    ("MAX-CHAR", [255, -1]),
    ("ADDRESS-UNIT-BITS", [8, -1]),
    ("FLOORED", [-1, -1]),
    ("XYZZY-NO-SUCH-QUERY", [0]),
])
def test_environment_query_answers_for_a_sixteen_bit_floored_system(run, query, expected):
    assert run(f'S" {query}" ENVIRONMENT?') == expected


@pytest.mark.parametrize("query, minimum", [
    ("/COUNTED-STRING", 255),
    ("/HOLD", 34),
    ("/PAD", 84),
    ("STACK-CELLS", 1),
    ("RETURN-STACK-CELLS", 1),
])
def test_environment_query_reports_sizes_at_least_the_standard_minimum(run, query, minimum):
    value, flag = run(f'S" {query}" ENVIRONMENT?')
    assert flag == -1
    assert value & 0xFFFF >= minimum


def test_abort_empties_the_stack_and_raises(forth, forth_error):
    with pytest.raises(forth_error) as e:
        forth.evaluate("1 2 ABORT 3")
    assert e.value.code == -1
    assert forth.stack == []
