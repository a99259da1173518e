"""Defining words, the dictionary, names and vocabularies.

Spec: F83's defining words (docs/forth2012.md, "Core: F83's meanings", and
"Programming-Tools" for FORGET).
"""
import pytest


def run(forth, text):
    return forth.evaluate(text)


def error_from(forth, text):
    import rcl
    with pytest.raises(rcl.ForthError) as info:
        forth.evaluate(text)
    return info.value


# ---------------------------------------------------------------------------
# : and ;
# ---------------------------------------------------------------------------

def test_colon_definition_runs_its_body(forth):
    assert run(forth, ": SQ DUP * ;  7 SQ .") == "49 "


def test_semicolon_aborts_with_stack_changed_when_depth_grew(forth):
    assert error_from(forth, ": Z [ 5 ] ;").message == "Stack Changed"


def test_semicolon_accepts_a_definition_started_over_a_non_empty_stack(forth):
    run(forth, "1 : Y ;")
    assert forth.stack == [1]


def test_new_name_is_hidden_until_semicolon(forth):
    run(forth, ": F 1 ;")
    run(forth, ": F F 1+ ;")
    assert run(forth, "F .") == "2 "


def test_word_cannot_call_itself_before_semicolon(forth):
    assert error_from(forth, ": G G ;").word == "G"


def test_recursive_reveals_the_name_early(forth):
    run(forth, ": FACT RECURSIVE DUP 1 > IF DUP 1- FACT * THEN ;")
    assert run(forth, "5 FACT .") == "120 "


# ---------------------------------------------------------------------------
# VARIABLE CONSTANT CREATE DOES>
# ---------------------------------------------------------------------------

def test_variable_is_initialised_to_zero(forth):
    assert run(forth, "VARIABLE V  V @ .") == "0 "


def test_variable_pushes_an_address_to_store_into(forth):
    assert run(forth, "VARIABLE V  5 V !  V @ .") == "5 "


def test_two_variable_is_initialised_to_zero(forth):
    assert run(forth, "2VARIABLE DV  DV 2@ D.") == "0 "


def test_two_variable_holds_a_double(forth):
    assert run(forth, "2VARIABLE DV  100000. DV 2!  DV 2@ D.") == "100000 "


def test_constant_pushes_its_value(forth):
    assert run(forth, "42 CONSTANT K  K .") == "42 "


def test_two_constant_pushes_its_double(forth):
    run(forth, "100000. 2CONSTANT BIG  BIG")
    assert forth.stack == [-31072, 1]


def test_create_pushes_the_address_of_its_data_field(forth):
    assert run(forth, "CREATE T  1 , 2 ,  T @ . T 2+ @ .") == "1 2 "


def test_allot_reserves_bytes_after_create(forth):
    assert run(forth, "CREATE B  10 ALLOT  HERE B - .") == "10 "


def test_does_gives_children_the_run_time_behaviour(forth):
    run(forth, ": CONST CREATE , DOES> @ ;  7 CONST SEVEN")
    assert run(forth, "SEVEN .") == "7 "


def test_does_child_pushes_its_data_field_address(forth):
    run(forth, ": MARKER CREATE DOES> ;  MARKER M1")
    assert run(forth, "' M1 >BODY M1 = .") == "-1 "


def test_to_body_of_a_variable_is_its_address(forth):
    assert run(forth, "VARIABLE V  ' V >BODY V = .") == "-1 "


# ---------------------------------------------------------------------------
# DEFER / IS, ' ['] EXECUTE
# ---------------------------------------------------------------------------

def test_is_sets_a_deferred_word(forth):
    assert run(forth, "DEFER V  : ONE 1 ;  ' ONE IS V  V .") == "1 "


def test_uninitialized_deferred_word_aborts(forth):
    run(forth, "DEFER V")
    assert error_from(forth, "V").message == "Uninitialized execution vector."


def test_tick_of_an_unknown_word_is_the_question_mark_error(forth):
    err = error_from(forth, "' NOSUCHWORD")
    assert (err.message, err.code, err.word) == ("?", -13, "NOSUCHWORD")


def test_execute_runs_a_ticked_word(forth):
    assert run(forth, "3 ' DUP EXECUTE * .") == "9 "


def test_bracket_tick_compiles_the_address_of_a_word(forth):
    run(forth, ": ONE 1 ;  : T ['] ONE ;")
    assert run(forth, "T EXECUTE .") == "1 "


@pytest.mark.parametrize("text", ["ASCII A .", ": T ASCII A ;  T ."])
def test_ascii_gives_the_code_of_the_next_character(forth, text):
    assert run(forth, text) == "65 "


# ---------------------------------------------------------------------------
# FORGET and EMPTY
# ---------------------------------------------------------------------------

def test_forget_removes_the_named_word(forth):
    run(forth, ": AA 1 ;  : BB 2 ;  FORGET AA")
    assert error_from(forth, "AA").word == "AA"


def test_forget_removes_every_later_word(forth):
    run(forth, ": AA 1 ;  : BB 2 ;  FORGET AA")
    assert error_from(forth, "BB").word == "BB"


def test_forget_uncovers_an_older_definition_of_the_same_name(forth):
    run(forth, "WARNING OFF  : AA 1 ;  : AA 2 ;  FORGET AA")
    assert run(forth, "AA .") == "1 "


def test_forget_refuses_a_base_system_word(forth):
    assert error_from(forth, "FORGET DUP").message == "Below fence"


def test_empty_forgets_everything_defined_after_the_base_system(forth):
    run(forth, ": AA 1 ;  EMPTY")
    assert error_from(forth, "AA").word == "AA"


def test_empty_keeps_the_base_system(forth):
    run(forth, ": AA 1 ;  EMPTY")
    assert run(forth, "2 3 + .") == "5 "


# ---------------------------------------------------------------------------
# Names
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("call", ["3 SQ .", "3 sq .", "3 Sq ."])
def test_names_are_case_insensitive(forth, call):
    run(forth, ": sq dup * ;")
    assert run(forth, call) == "9 "


def test_names_are_significant_to_thirty_one_characters(forth):
    run(forth, ": ABCDEFGHIJKLMNOPQRSTUVWXYZ1234A 1 ;")
    run(forth, ": ABCDEFGHIJKLMNOPQRSTUVWXYZ1234B 2 ;")
    assert run(forth, "ABCDEFGHIJKLMNOPQRSTUVWXYZ1234A .") == "1 "


def test_characters_after_the_thirty_first_are_ignored(forth):
    run(forth, ": ABCDEFGHIJKLMNOPQRSTUVWXYZ12345X 7 ;")
    assert run(forth, "ABCDEFGHIJKLMNOPQRSTUVWXYZ12345Y .") == "7 "


def test_redefinition_prints_the_name_and_isnt_unique(forth):
    run(forth, ": A 1 ;")
    assert run(forth, ": A 2 ;") == "A isn't unique "


def test_warning_off_silences_the_isnt_unique_message(forth):
    run(forth, "WARNING OFF  : A 1 ;")
    assert run(forth, ": A 2 ;") == ""


def test_newest_definition_wins_but_old_code_keeps_the_old_one(forth):
    run(forth, "WARNING OFF  : A 1 ;  : B A ;  : A 2 ;")
    assert run(forth, "B . A .") == "1 2 "


# ---------------------------------------------------------------------------
# IMMEDIATE and compiling words
# ---------------------------------------------------------------------------

def test_immediate_word_runs_while_compiling(forth):
    run(forth, ': HELLO ." hi" ; IMMEDIATE')
    assert run(forth, ": T HELLO ;") == "hi"


def test_immediate_word_is_not_compiled_into_the_definition(forth):
    run(forth, ': HELLO ." hi" ; IMMEDIATE  : T HELLO ;')
    assert run(forth, "T") == ""


def test_compile_compiles_the_following_word_later(forth):
    run(forth, ": COMPILE-DUP COMPILE DUP ; IMMEDIATE  : T COMPILE-DUP * ;")
    assert run(forth, "3 T .") == "9 "


def test_bracket_compile_compiles_an_immediate_word(forth):
    run(forth, ": MYIF [COMPILE] IF ; IMMEDIATE  : T MYIF 1 ELSE 2 THEN ;")
    assert run(forth, "0 T .") == "2 "


def test_literal_compiles_a_value_computed_at_compile_time(forth):
    assert run(forth, ": T [ 6 7 * ] LITERAL ;  T .") == "42 "


def test_dliteral_compiles_a_double(forth):
    assert run(forth, ": T [ 100000. ] DLITERAL ;  T D.") == "100000 "


# ---------------------------------------------------------------------------
# Vocabularies and the search order
# ---------------------------------------------------------------------------

TOOLS = "VOCABULARY TOOLS  ONLY FORTH ALSO TOOLS DEFINITIONS  : HAMMER 5 ;"


def test_word_in_a_vocabulary_is_found_while_it_is_in_the_search_order(forth):
    run(forth, TOOLS)
    assert run(forth, "HAMMER .") == "5 "


def test_word_in_a_vocabulary_is_not_found_once_it_leaves_the_search_order(forth):
    run(forth, TOOLS + "  ONLY FORTH DEFINITIONS")
    assert error_from(forth, "HAMMER").word == "HAMMER"


def test_also_puts_a_vocabulary_back_into_the_search_order(forth):
    run(forth, TOOLS + "  ONLY FORTH DEFINITIONS  ALSO TOOLS")
    assert run(forth, "HAMMER .") == "5 "


def test_previous_drops_the_first_vocabulary_of_the_search_order(forth):
    run(forth, TOOLS + "  PREVIOUS")
    assert error_from(forth, "HAMMER").word == "HAMMER"


def test_forth_words_are_still_found_behind_a_new_vocabulary(forth):
    run(forth, TOOLS)
    assert run(forth, "2 3 + .") == "5 "


def test_order_names_the_vocabularies_in_the_search_order(forth):
    out = run(forth, TOOLS + "  ORDER")
    assert "TOOLS" in out and "FORTH" in out
