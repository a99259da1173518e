"""Forth 2012 Programming-Tools word set (chapter 15), F83's tools where
F83 has them, on the bare and full systems."""
import pytest


# --- inspecting ----------------------------------------------------------------------

def test_dot_s_shows_the_stack_and_leaves_it_alone(system):
    assert system.evaluate("1 2 3 .S").split() == ["1", "2", "3"]
    assert system.stack == [1, 2, 3]


def test_question_prints_the_cell_at_an_address(system):
    assert system.evaluate("VARIABLE V 1234 V ! V ?") == "1234 "


def test_dump_shows_each_byte_in_hex_and_as_text(system):
    out = system.evaluate('CREATE D 65 C, 66 C, 7 C,  D 3 DUMP')
    assert "41 42 07" in out and "AB." in out


def test_see_decompiles_a_colon_definition(system):
    out = system.evaluate(": SQ2 ( n -- n' ) DUP * ; SEE SQ2")
    assert out.split() == [":", "SQ2", "DUP", "*", ";"]


def test_words_lists_a_new_definition_first(system):
    assert system.evaluate(": NEWEST-WORD ; WORDS").split()[0] == "NEWEST-WORD"


# --- control-flow stack ---------------------------------------------------------------

def test_ahead_jumps_forward_to_then(sys_run):
    assert sys_run(": T 1 AHEAD 2 THEN 3 ; T") == [1, 3]


def test_cs_pick_copies_a_destination_so_two_untils_loop_to_one_begin(sys_run):
    assert sys_run(": T BEGIN 1+ DUP 5 > [ 0 CS-PICK ] UNTIL DUP 10 > UNTIL ; 0 T") == [11]


def test_cs_roll_reorders_origins_to_build_else(sys_run):
    src = ": T IF 1 AHEAD [ 1 CS-ROLL ] THEN 2 THEN ; TRUE T FALSE T"
    assert sys_run(src) == [1, 2]


# --- conditional compilation ------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("TRUE [IF] 1 [ELSE] 2 [THEN]", [1]),
    ("FALSE [IF] 1 [ELSE] 2 [THEN]", [2]),
    ("FALSE [IF] 1 [THEN] 3", [3]),
    ("FALSE [IF] TRUE [IF] 1 [ELSE] 2 [THEN] [ELSE] 3 [THEN]", [3]),
    ("TRUE [IF] FALSE [IF] 1 [ELSE] 2 [THEN] [ELSE] 3 [THEN]", [2]),
    ("FALSE [if] 1 [else] 2 [then]", [2]),
    (": T [ TRUE ] [IF] 5 [ELSE] 6 [THEN] ; T", [5]),
    ("FALSE [IF] UNDEFINED-WORD [ELSE] 7 [THEN]", [7]),
])
def test_bracket_if_interprets_one_branch_and_skips_the_other(sys_run, src, expected):
    assert sys_run(src) == expected


def test_bracket_if_skips_across_lines(sys_run):
    assert sys_run("FALSE [IF]\n 1\n 2\n[ELSE]\n 3\n[THEN] 4") == [3, 4]


def test_bracket_if_skips_across_lines_of_a_file(sys_run, tmp_path):
    f = tmp_path / "cond.fs"
    f.write_text("FALSE [IF]\nJUNK\n[ELSE]\n5\n[THEN]\n6\n")
    assert sys_run("INCLUDE %s" % f) == [5, 6]


@pytest.mark.parametrize("src, expected", [
    ("[DEFINED] DUP", [-1]),
    ("[DEFINED] NO-SUCH-WORD", [0]),
    ("[UNDEFINED] DUP", [0]),
    ("[UNDEFINED] NO-SUCH-WORD", [-1]),
    (": T [DEFINED] SWAP LITERAL ; T", [-1]),
])
def test_defined_and_undefined_look_the_next_name_up(sys_run, src, expected):
    assert sys_run(src) == expected


# --- return stack, synonyms ----------------------------------------------------------

def test_n_to_r_and_n_r_from_move_a_counted_group_both_ways(sys_run):
    assert sys_run(": T N>R 99 NR> ; 10 20 30 3 T") == [99, 10, 20, 30, 3]


def test_n_to_r_of_nothing_moves_only_the_count(sys_run):
    assert sys_run(": T 0 N>R NR> ; 7 T") == [7, 0]


def test_a_synonym_does_what_its_word_does(sys_run):
    assert sys_run(": TWICE 2* ; SYNONYM DOUBLE TWICE  SYNONYM ADD +  21 DOUBLE 1 ADD") == [43]


def test_a_synonym_of_an_immediate_word_is_immediate(sys_run):
    assert sys_run("SYNONYM WHEN IF  SYNONYM END THEN : T WHEN 1 END 2 ; 0 T 5 T") == [2, 1, 2]


def test_a_synonym_of_a_variable_gives_the_same_address(sys_run):
    a, b = sys_run("VARIABLE V SYNONYM W V  V W")
    assert a == b


def test_a_synonym_of_a_word_that_drops_its_callers_frame_still_does(sys_run):
    # R> DROP leaves the caller early: through a synonym the frames are the same
    assert sys_run(": LEAVE-CALLER R> DROP ; SYNONYM QUIT-CALLER LEAVE-CALLER "
                   ": T 1 QUIT-CALLER 2 ; : U T 3 ; U") == [1, 3]


# --- name tokens --------------------------------------------------------------------

WL = "WORDLIST CONSTANT WL  WL SET-CURRENT : ONE 1 ; : TWO 2 ; : THREE 3 ; IMMEDIATE " \
     "FORTH-WORDLIST SET-CURRENT "


def test_traverse_wordlist_visits_every_word_of_the_list(sys_run):
    assert sys_run(WL + ": COUNTER ( n nt -- n+1 f ) DROP 1+ TRUE ; "
                   "0 ' COUNTER WL TRAVERSE-WORDLIST") == [3]


def test_traverse_wordlist_stops_when_the_word_gives_false(sys_run):
    assert sys_run(WL + ": FIRST-ONLY ( n nt -- n+1 f ) DROP 1+ FALSE ; "
                   "0 ' FIRST-ONLY WL TRAVERSE-WORDLIST") == [1]


def test_name_to_string_gives_each_name(system):
    system.evaluate(WL + ": SHOW ( nt -- f ) NAME>STRING TYPE SPACE TRUE ;")
    assert sorted(system.evaluate("' SHOW WL TRAVERSE-WORDLIST").split()) == ["ONE", "THREE", "TWO"]


def test_name_to_interpret_gives_an_xt_that_runs_the_word(sys_run):
    assert sys_run(WL + ": RUN ( nt -- f ) NAME>INTERPRET EXECUTE FALSE ; "
                   "' RUN WL TRAVERSE-WORDLIST") == [3]


def test_name_to_compile_gives_execute_for_immediate_words_and_compile_for_others(sys_run):
    stack = sys_run(WL + ": BOTH ( nt -- f ) NAME>COMPILE NIP TRUE ; "
                    "' BOTH WL TRAVERSE-WORDLIST ' EXECUTE ' COMPILE,")
    assert stack[:3] == [stack[3], stack[4], stack[4]]


# --- F83's own -----------------------------------------------------------------------

def test_forget_removes_the_word_and_everything_after_it(system, forth_error):
    system.evaluate(": KEEP 1 ; : GONE 2 ; : LATER 3 ; FORGET GONE")
    assert system.evaluate("KEEP .") == "1 "
    with pytest.raises(forth_error):
        system.evaluate("LATER")


def test_state_is_true_only_while_compiling(sys_run):
    assert sys_run(": CSTATE STATE @ ; IMMEDIATE  : T CSTATE LITERAL ; T CSTATE") == [-1, 0]


def test_bye_leaves_the_system():
    import rcl

    with pytest.raises(rcl.Bye):
        rcl.Forth().evaluate("BYE")


def test_code_binds_a_name_to_its_primitive_skipping_the_assembler_text(sys_run):
    assert sys_run("CODE 2DUP  AX POP BX POP BX PUSH AX PUSH BX PUSH AX PUSH NEXT END-CODE "
                   "1 2 2DUP") == [1, 2, 1, 2]


def test_assembler_and_editor_are_vocabularies(system):
    system.evaluate("ASSEMBLER")
    assert "ASSEMBLER" in system.evaluate("ORDER")
    system.evaluate("FORTH EDITOR")       # ASSEMBLER took FORTH's place (F83)
    assert "EDITOR" in system.evaluate("ORDER")
