"""Forth 2012 String word set (chapter 17), on the bare and full systems."""
import pytest

BUF = "CREATE BUF 100 ALLOT "


@pytest.mark.parametrize("src, expected", [
    ('S" abc   " -TRAILING NIP', [3]),
    ('S"    " -TRAILING NIP', [0]),
    ('S" " -TRAILING NIP', [0]),
    ('S"  a b" -TRAILING NIP', [4]),
])
def test_minus_trailing_drops_only_trailing_blanks(sys_run, src, expected):
    assert sys_run(src) == expected


def test_slash_string_moves_the_start_and_shortens(sys_run):
    a, n, a2, n2 = sys_run('S" abcdef" 2DUP 2 /STRING')
    assert (a2 - a, n2) == (2, 4)


def test_slash_string_with_a_negative_count_moves_back(sys_run):
    a, n, a2, n2 = sys_run('S" abcdef" 2DUP 3 /STRING -1 /STRING')
    assert (a2 - a, n2) == (2, 4)


def test_blank_fills_with_spaces(sys_run):
    assert sys_run(BUF + 'BUF 3 BLANK BUF 4 + 1 BLANK BUF C@ BUF 2+ C@') == [32, 32]


def test_cmove_copies_low_addresses_first(sys_run):
    # an overlapping move up smears the first character (the classic propagation)
    assert sys_run(BUF + 'S" abcd" BUF SWAP CMOVE BUF BUF 1+ 3 CMOVE '
                   'BUF 4 S" aaaa" COMPARE') == [0]


def test_cmove_up_copies_high_addresses_first(sys_run):
    assert sys_run(BUF + 'S" abcd" BUF SWAP CMOVE BUF BUF 1+ 3 CMOVE> '
                   'BUF 4 S" aabc" COMPARE') == [0]


@pytest.mark.parametrize("src, expected", [
    ('S" abc" S" abc" COMPARE', 0),
    ('S" abc" S" abd" COMPARE', -1),
    ('S" abd" S" abc" COMPARE', 1),
    ('S" ab" S" abc" COMPARE', -1),
    ('S" abc" S" ab" COMPARE', 1),
    ('S" " S" " COMPARE', 0),
    ('S" ABC" S" abc" COMPARE', -1),       # case counts
])
def test_compare_orders_strings_by_character_then_length(sys_run, src, expected):
    assert sys_run(src) == [expected]


def test_search_finds_the_first_match_and_gives_the_rest(sys_run):
    a, n, a2, n2, f = sys_run('S" one two two" 2DUP S" two" SEARCH')
    assert (a2 - a, n2, f) == (4, 7, -1)


def test_search_without_a_match_gives_the_string_back_and_false(sys_run):
    a, n, a2, n2, f = sys_run('S" one two" 2DUP S" six" SEARCH')
    assert (a2, n2, f) == (a, n, 0)


def test_search_for_the_empty_string_matches_at_the_start(sys_run):
    a, n, a2, n2, f = sys_run('S" one" 2DUP S" " SEARCH')
    assert (a2, n2, f) == (a, n, -1)


def test_sliteral_compiles_a_string_that_outlives_its_buffer(sys_run):
    assert sys_run(': T [ S" hello" ] SLITERAL ; S" other" 2DROP T S" hello" COMPARE') == [0]


def test_sliteral_is_compile_only(system, forth_error):
    with pytest.raises(forth_error):
        system.evaluate('S" x" SLITERAL')


# --- substitution ------------------------------------------------------------------

SUBS = BUF + 'S" Fred" S" name" REPLACES  S" 42" S" age" REPLACES '


def substituted(sys_run, text, size=100):
    stack = sys_run(SUBS + 'S" %s" BUF %d SUBSTITUTE ROT ROT TYPE' % (text, size))
    return stack[-1]


@pytest.mark.parametrize("text, shown, n", [
    ("Hi %name%!", "Hi Fred!", 1),
    ("%name% is %age%", "Fred is 42", 2),
    ("100%%", "100%", 0),
    ("%NAME%", "Fred", 1),                     # names as dictionary names: no case
    ("%who% here", "%who% here", 0),           # not a name: passed on whole
    ("50% off", "50% off", 0),                 # a single % is text
    ("%who%name%", "%who%name%", 0),           # resumes after the trailing %
    ("", "", 0),
])
def test_substitute_replaces_names_between_percent_signs(system, text, shown, n):
    system.evaluate(SUBS)
    out = system.evaluate('S" %s" BUF 100 SUBSTITUTE ROT ROT TYPE' % text)
    assert out == shown and system.stack[-1] == n


def test_replaces_again_changes_the_text_of_a_name(system):
    system.evaluate(SUBS + 'S" Ann" S" name" REPLACES')
    assert system.evaluate('S" %name%" BUF 100 SUBSTITUTE DROP TYPE') == "Ann"


def test_substitute_gives_a_negative_n_when_the_result_does_not_fit(sys_run):
    assert sys_run(SUBS + 'S" %name% %name%" BUF 5 SUBSTITUTE')[-1] < 0


def test_unescape_doubles_every_percent_so_substitute_gives_it_back(system):
    system.evaluate(SUBS + "CREATE OUT 100 ALLOT")
    out = system.evaluate('S" 5% of %name%" BUF UNESCAPE 2DUP TYPE SPACE '
                          'OUT 100 SUBSTITUTE DROP TYPE')
    assert out == "5%% of %%name%% 5% of %name%"
