"""Forth 2012 Core Extensions word set on a 16-bit F83 machine."""
import pytest

MAX_N, MIN_N = 32767, -32768

# Pushes every char of a string: ( c-addr u -- c1 .. cu )
BYTES = ": BYTES 0 ?DO DUP C@ SWAP CHAR+ LOOP DROP ; "


# --- stack words ----------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("1 2 NIP", [2]),
    ("1 2 TUCK", [2, 1, 2]),
    ("1 2 3 0 PICK", [1, 2, 3, 3]),
    ("1 2 3 1 PICK", [1, 2, 3, 2]),
    ("1 2 3 2 PICK", [1, 2, 3, 1]),
    ("1 2 3 0 ROLL", [1, 2, 3]),
    ("1 2 3 1 ROLL", [1, 3, 2]),
    ("1 2 3 2 ROLL", [2, 3, 1]),
    ("1 2 3 4 3 ROLL", [2, 3, 4, 1]),
])
def test_nip_tuck_pick_and_roll_rearrange_the_stack(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    (": T 2>R 2R@ 2R> ; 1 2 T", [1, 2, 1, 2]),
    (": T 2>R R> R> ; 1 2 T", [2, 1]),
    (": T >R >R 2R> ; 1 2 T", [2, 1]),
])
def test_two_cell_return_stack_words_keep_the_pair_in_order(run, src, expected):
    assert run(src) == expected


# --- comparisons ----------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("0 0<>", [0]),
    ("-5 0<>", [-1]),
    ("1 0>", [-1]),
    ("0 0>", [0]),
    ("-1 0>", [0]),
    ("-32768 0>", [0]),
    ("32767 0>", [-1]),
    ("1 2 <>", [-1]),
    ("2 2 <>", [0]),
    ("-1 0 U>", [-1]),
    ("0 -1 U>", [0]),
    ("32767 -32768 U>", [0]),
    ("FALSE", [0]),
    ("TRUE", [-1]),
])
def test_extension_comparisons_and_flags_are_well_formed(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("2 1 3 WITHIN", [-1]),
    ("1 1 3 WITHIN", [-1]),
    ("3 1 3 WITHIN", [0]),
    ("0 1 3 WITHIN", [0]),
    ("-1 -2 0 WITHIN", [-1]),
    ("0 -1 1 WITHIN", [-1]),              # range wraps through zero
    ("32767 32766 -32768 WITHIN", [-1]),  # range wraps through MAX-N
    ("-32768 32766 -32768 WITHIN", [0]),
    ("5 3 3 WITHIN", [0]),
])
def test_within_tests_the_half_open_circular_range(run, src, expected):
    assert run(src) == expected


# --- output ----------------------------------------------------------------------

@pytest.mark.parametrize("src, shown", [
    (".( hello world)", "hello world"),
    ("5 4 .R", "   5"),
    ("-5 4 .R", "  -5"),
    ("12345 2 .R", "12345"),
    ("-1 7 U.R", "  65535"),
    ("0 3 U.R", "  0"),
    ("7 1 U.R", "7"),
    ('0 0 <# S" abc" HOLDS #> TYPE', "abc"),
    ('12 0 <# S" xy" HOLDS #S #> TYPE', "12xy"),
])
def test_extension_output_words_print_exactly_what_is_specified(out, src, shown):
    assert out(src) == shown


def test_dot_paren_prints_immediately_even_while_compiling(out):
    assert out(": T .( compiling) 1 ;") == "compiling"
    assert out("T .") == "1 "


# --- definitions and control flow ------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    (":NONAME 2 * ; 7 SWAP EXECUTE", [14]),
    (": T 0 0 ?DO I LOOP 99 ; T", [99]),
    (": T 3 0 ?DO I LOOP ; T", [0, 1, 2]),
    (": T 5 5 ?DO I LOOP 7 ; T", [7]),
    (": T 0 BEGIN 1+ DUP 5 = IF EXIT THEN AGAIN ; T", [5]),
    (": T ['] DUP COMPILE, ; IMMEDIATE : U T * ; 4 U", [16]),
    (": MY-IF [COMPILE] IF ; IMMEDIATE : T MY-IF 1 ELSE 2 THEN ; -1 T 0 T", [1, 2]),
])
def test_extension_definition_and_control_words_behave_as_specified(run, src, expected):
    assert run(src) == expected


CASE_DEF = ": T CASE 1 OF 11 ENDOF 2 OF 22 ENDOF 99 SWAP ENDCASE ; "


@pytest.mark.parametrize("selector, expected", [(1, [11]), (2, [22]), (3, [99]), (-1, [99])])
def test_case_runs_the_matching_branch_or_the_default(run, selector, expected):
    assert run(CASE_DEF + f"{selector} T") == expected


def test_an_empty_case_drops_the_selector(run):
    assert run(": T CASE ENDCASE ; 1 5 T") == [1]


@pytest.mark.parametrize("src, expected", [
    ("5 VALUE V V", [5]),
    ("5 VALUE V 7 TO V V", [7]),
    ("5 VALUE V : SETV TO V ; 9 SETV V", [9]),
    ("5 VALUE V : GETV V ; 6 TO V GETV", [6]),
])
def test_value_returns_its_contents_and_to_changes_them(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("DEFER D1 ' 1+ IS D1 5 D1", [6]),
    ("DEFER D1 ' 2* ' D1 DEFER! 5 D1", [10]),
    ("DEFER D1 ' 2* ' D1 DEFER! ' D1 DEFER@ ' 2* =", [-1]),
    ("DEFER D1 ' 1+ IS D1 ACTION-OF D1 ' 1+ =", [-1]),
    ("DEFER D1 : SETD IS D1 ; ' NEGATE SETD 5 D1", [-5]),
    ("DEFER D1 ' 1+ IS D1 : GETD ACTION-OF D1 ; GETD ' 1+ =", [-1]),
    ("DEFER D1 : T D1 ; ' 1+ IS D1 5 T ' 2* IS D1 5 T", [6, 10]),
])
def test_deferred_words_execute_whatever_was_last_stored_in_them(run, src, expected):
    assert run(src) == expected


def test_marker_forgets_everything_defined_after_it(forth, forth_error):
    forth.evaluate("MARKER FORGET-ME : ZZZ 1 ; FORGET-ME")
    with pytest.raises(forth_error) as e:
        forth.evaluate("ZZZ")
    assert e.value.code == -13


def test_marker_restores_the_dictionary_pointer(run):
    assert run("HERE MARKER M1 100 ALLOT M1 HERE =") == [-1]


# --- memory ------------------------------------------------------------------------

def test_buffer_colon_reserves_usable_distinct_regions(out):
    src = ("4 BUFFER: B1 4 BUFFER: B2 B1 4 CHAR a FILL B2 4 CHAR b FILL "
           "B1 4 TYPE B2 4 TYPE")
    assert out(src) == "aaaabbbb"


def test_erase_clears_a_region_to_zero(run):
    src = "CREATE E 4 ALLOT E 4 CHAR x FILL E 4 ERASE E C@ E 3 + C@"
    assert run(src) == [0, 0]


def test_pad_is_a_scratch_area_that_holds_data(out):
    assert out('S" hi" PAD SWAP MOVE PAD 2 TYPE') == "hi"


def test_unused_shrinks_by_what_allot_takes(run):
    assert run("UNUSED 10 ALLOT UNUSED -") == [10]
    assert run("DROP UNUSED 0=") == [0]


def test_hex_sets_base_sixteen(run):
    assert run("HEX 10 DECIMAL 10") == [16, 10]


# --- strings and parsing ----------------------------------------------------------

def test_c_quote_compiles_a_counted_string(out):
    assert out(': T C" abc" ; T COUNT TYPE T C@ .') == "abc3 "


@pytest.mark.parametrize("src, shown", [
    ("CHAR | PARSE abc| TYPE", "abc"),
    (": P [CHAR] ) PARSE TYPE ; P hello world)", "hello world"),
    (": P [CHAR] ) PARSE TYPE ; P no close", "no close"),
    (": PN PARSE-NAME TYPE ; PN    word", "word"),
])
def test_parse_and_parse_name_return_the_text_they_consume(out, src, shown):
    assert out(src) == shown


@pytest.mark.parametrize("src, expected", [
    ("CHAR | PARSE | SWAP DROP", [0]),
    ("PARSE-NAME xyz SWAP DROP", [3]),
    (": PNLEN PARSE-NAME SWAP DROP ; PNLEN", [0]),
])
def test_parse_and_parse_name_return_the_right_length(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("body, expected", [
    (r"\a", [7]),
    (r"\b", [8]),
    (r"\e", [27]),
    (r"\f", [12]),
    (r"\l", [10]),
    (r"\m", [13, 10]),
    (r"\q", [34]),
    (r"\r", [13]),
    (r"\t", [9]),
    (r"\v", [11]),
    (r"\z", [0]),
    (r"\"", [34]),
    (r"\x41", [65]),
    (r"\x7e\x7E", [126, 126]),
    (r"\\", [92]),
    (r"a\tb\x41\\\"", [97, 9, 98, 65, 92, 34]),
    ("plain", [112, 108, 97, 105, 110]),
])
def test_s_backslash_quote_translates_each_escape(run, body, expected):
    assert run(BYTES + 'S\\" ' + body + '" BYTES') == expected


def test_s_backslash_quote_n_gives_a_newline_sequence(run):
    assert run(BYTES + r'S\" \n" BYTES') in ([10], [13, 10], [13])


def test_s_backslash_quote_works_inside_a_definition(out):
    assert out(r': T S\" say \qhi\q" ; T TYPE') == 'say "hi"'


def test_backslash_ignores_the_rest_of_the_line(run):
    assert run("1 \\ 2 3\n4") == [1, 4]


# --- input sources ------------------------------------------------------------------

def test_source_id_is_zero_for_the_user_input_device(run):
    assert run("SOURCE-ID") == [0]


def test_source_id_is_minus_one_while_evaluating_a_string(run):
    assert run('S" SOURCE-ID" EVALUATE') == [-1]


def test_source_id_is_a_file_id_while_including_a_file(run, tmp_path):
    f = tmp_path / "sid.fs"
    f.write_text("SOURCE-ID\n")
    (fid,) = run(f"INCLUDE {f}")
    assert fid not in (0, -1)


def test_refill_fails_while_evaluating_a_string(run):
    assert run('S" REFILL" EVALUATE') == [0]


def test_refill_reads_the_next_line_of_a_file(run, tmp_path):
    f = tmp_path / "refill.fs"
    f.write_text("REFILL 999\n42\n")
    assert run(f"INCLUDE {f}") == [-1, 42]


def test_refill_reads_the_next_line_typed_at_the_keyboard(run):
    assert run("REFILL 999\n42") == [-1, 42]


# Keeps the values from SAVE-INPUT in memory and re-runs the rest of the
# line after MARK until CNT reaches 3.
SAVER = (
    "CREATE SAVED 16 CELLS ALLOT "
    ": SAVE ( i*x n -- ) DUP SAVED ! 0 ?DO SAVED I 1+ CELLS + ! LOOP ; "
    ": RESTORE ( -- flag ) SAVED @ 0 ?DO SAVED SAVED @ I - CELLS + @ LOOP "
    "SAVED @ RESTORE-INPUT ; "
    ": MARK SAVE-INPUT SAVE ; "
    "VARIABLE CNT 0 CNT ! "
    ': THRICE CNT @ 3 < IF RESTORE ABORT" restore failed" THEN ; '
)


def test_restore_input_rewinds_the_keyboard_line_to_save_input(run):
    run(SAVER)
    assert run("MARK 1 CNT +! THRICE CNT @") == [3]


def test_restore_input_rewinds_an_evaluated_string_to_save_input(run):
    run(SAVER)
    assert run('S" MARK 1 CNT +! THRICE CNT @" EVALUATE') == [3]


def test_restore_input_rewinds_a_file_to_save_input(run, tmp_path):
    f = tmp_path / "rewind.fs"
    f.write_text("MARK\n1 CNT +!\nTHRICE\nCNT @\n")
    run(SAVER)
    assert run(f"INCLUDE {f}") == [3]
