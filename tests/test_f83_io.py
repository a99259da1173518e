"""Comments, strings, output words, errors and the screen text of the prompt.

Spec: F83 2.1.0's behaviour (docs/forth2012.md, "Core: F83's meanings", and
"Programming-Tools" for DUMP, WORDS, SEE; the prompt: docs/guide.md section 1).
"""
import re

import pytest


def run(forth, text):
    return forth.evaluate(text)


def error_from(forth, text):
    import rcl
    with pytest.raises(rcl.ForthError) as info:
        forth.evaluate(text)
    return info.value


# ---------------------------------------------------------------------------
# Comments and strings
# ---------------------------------------------------------------------------

def test_paren_comment_is_ignored_while_interpreting(forth):
    run(forth, "1 ( 2 3 ) 4")
    assert forth.stack == [1, 4]


def test_paren_comment_is_ignored_while_compiling(forth):
    run(forth, ": T 1 ( 2 ) 3 ;  T")
    assert forth.stack == [1, 3]


def test_paren_comment_without_closing_paren_swallows_the_rest_of_the_line(forth):
    run(forth, "1 ( 2 3\n4")
    assert forth.stack == [1, 4]


def test_backslash_ignores_the_rest_of_the_line(forth):
    run(forth, "1 \\ 2 3\n4")
    assert forth.stack == [1, 4]


def test_dot_paren_types_its_text_at_once(forth):
    assert run(forth, ".( hi)") == "hi"


def test_only_the_first_blank_after_dot_paren_is_the_delimiter(forth):
    assert run(forth, ".(  hi)") == " hi"


def test_dot_quote_types_its_text_when_the_definition_runs(forth):
    run(forth, ': T ." hi" ;')
    assert run(forth, "T") == "hi"


def test_dot_quote_prints_nothing_when_the_definition_is_compiled(forth):
    assert run(forth, ': T ." hi" ;') == ""


def test_dot_quote_outside_a_definition_prints_nothing(forth):
    assert run(forth, '." hi"') == ""


def test_quote_compiles_a_string_that_type_can_print(forth):
    # F83 kernel86.blk: `: (") (S -- addr len ) R> COUNT ...` so the
    # run-time result goes straight to TYPE.
    run(forth, ': T " hello" TYPE ;')
    assert run(forth, "T") == "hello"


def test_abort_quote_with_a_true_flag_raises_its_message(forth):
    run(forth, ': T ABORT" Oops" ;')
    err = error_from(forth, "1 T")
    assert (err.message, err.code) == ("Oops", -2)


def test_abort_quote_with_a_false_flag_does_nothing(forth):
    run(forth, ': T ABORT" Oops" ;')
    assert run(forth, "5 0 T .") == "5 "


def test_abort_quote_empties_the_data_stack(forth):
    run(forth, ': T ABORT" Oops" ;')
    error_from(forth, "5 6 -1 T")
    assert forth.stack == []


def test_abort_raises_code_minus_one(forth):
    assert error_from(forth, "ABORT").code == -1


def test_abort_empties_the_data_stack(forth):
    error_from(forth, "1 2 3 ABORT")
    assert forth.stack == []


# ---------------------------------------------------------------------------
# Output words
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("text, printed", [
    ("-5 .", "-5 "),
    ("1 . 2 .", "1 2 "),
    ("-1 U.", "65535 "),
    ("42 5 .R", "   42"),
    ("-42 5 .R", "  -42"),
    ("-100000. D.", "-100000 "),
    ("-1. UD.", "4294967295 "),
    ("100000. 8 D.R", "  100000"),
    ("-100000. 8 D.R", " -100000"),
    ("-1. 11 UD.R", " 4294967295"),
    ("65 EMIT", "A"),
    ("SPACE", " "),
    ("3 SPACES", "   "),
])
def test_output_word_prints_exactly(forth, text, printed):
    assert run(forth, text) == printed


def test_type_prints_bytes_from_memory(forth):
    assert run(forth, "CREATE S 72 C, 73 C,  S 2 TYPE") == "HI"


def test_cr_starts_a_new_line(forth):
    assert "\n" in run(forth, "CR")


def test_question_mark_prints_the_cell_at_an_address(forth):
    assert run(forth, "VARIABLE V  7 V !  V ?") == "7 "


def test_dot_s_prints_each_cell_in_seven_columns_and_a_space(forth):
    assert run(forth, "1 2 3 .S") == "      1       2       3 "


def test_dot_s_prints_cells_unsigned(forth):
    assert run(forth, "-1 .S") == "  65535 "


def test_dot_s_leaves_the_stack_alone(forth):
    run(forth, "1 2 3 .S")
    assert forth.stack == [1, 2, 3]


def test_dot_s_on_an_empty_stack_prints_empty(forth):
    assert run(forth, ".S") == "Empty "


def test_dump_shows_the_bytes_of_a_buffer(forth):
    out = run(forth, "CREATE BUF 171 C, 205 C, 239 C,  HEX BUF 3 DUMP")
    assert re.search(r"AB\s+CD\s+EF", out.upper())


def test_words_lists_dup(forth):
    assert "DUP" in run(forth, "WORDS")


def test_words_leaves_out_a_definition_an_error_abandoned(forth):
    run(forth, ": KEPT 1 ;")
    error_from(forth, ": ABANDONED 1 NOSUCH ;")
    names = run(forth, "WORDS").split()
    assert "KEPT" in names and "ABANDONED" not in names
    assert error_from(forth, "ABANDONED").word == "ABANDONED"      # as it answers ?


def test_see_decompiles_a_colon_definition(forth):
    out = run(forth, ": SQ DUP * ;  SEE SQ")
    assert "DUP" in out and "*" in out and ";" in out


# ---------------------------------------------------------------------------
# Errors
# ---------------------------------------------------------------------------

def test_drop_on_an_empty_stack_is_stack_underflow(forth):
    err = error_from(forth, "DROP")
    assert (err.message, err.code) == ("Stack Underflow", -4)


def test_unknown_word_error_carries_the_upper_cased_token(forth):
    err = error_from(forth, "foo")
    assert (err.message, err.code, err.word, str(err)) == ("?", -13, "FOO", "FOO  ?")


def test_error_empties_the_data_stack(forth):
    error_from(forth, "1 2 foo")
    assert forth.stack == []


def test_earlier_definitions_survive_an_error(forth):
    run(forth, ": SQ DUP * ;")
    error_from(forth, "foo")
    assert run(forth, "3 SQ .") == "9 "


def test_error_inside_a_definition_returns_to_interpreting(forth):
    error_from(forth, ": T 1 foo")
    assert run(forth, "2 3 + .") == "5 "


# ---------------------------------------------------------------------------
# The exact screen text at the prompt
# ---------------------------------------------------------------------------

@pytest.mark.parametrize("typed, screen", [
    ("2 3 + .", "2 3 + . 5  ok\n"),
    ("1 2", "1 2  ok\n"),
    ("foo", "foo FOO  ? \n"),
    ("DROP", "DROP  Stack Underflow \n"),
    (": Z [ 5 ] ;", ": Z [ 5 ] ;  Stack Changed \n"),
    ("ABORT", "ABORT   \n"),
])
def test_one_line_at_the_prompt_shows_echo_blank_output_and_ok_or_error(forth, typed, screen):
    assert forth.session(typed) == screen


def test_no_ok_is_shown_while_a_definition_is_open_across_lines(forth):
    assert forth.session(": SQ DUP *\n;\n3 SQ .") == ": SQ DUP * \n;  ok\n3 SQ . 9  ok\n"


def test_prompt_continues_with_the_next_line_after_an_error(forth):
    assert forth.session("foo\n1 .") == "foo FOO  ? \n1 . 1  ok\n"


def test_abort_quote_message_appears_between_blanks_on_screen(forth):
    screen = forth.session(': T ABORT" Oops" ;\n1 T')
    assert screen == ': T ABORT" Oops" ;  ok\n1 T  Oops \n'
