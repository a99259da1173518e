"""Forth 2012 Search-Order word set (chapter 16) beside F83's vocabularies
(ONLY ALSO VOCABULARY keep their F83 meaning), on the bare and full systems."""
import pytest


def test_get_order_gives_the_word_lists_first_searched_on_top(sys_run):
    stack = sys_run("GET-ORDER")
    n = stack[-1]
    assert n >= 1 and len(stack) == n + 1
    assert sys_run("FORTH-WORDLIST")[-1] in stack[:-1]


def test_set_order_then_get_order_gives_the_same_order(sys_run):
    stack = sys_run("WORDLIST CONSTANT W1  W1 FORTH-WORDLIST 2 SET-ORDER GET-ORDER "
                    "W1 FORTH-WORDLIST")
    w1, forth = stack[-2:]
    assert stack[:-2] == [w1, forth, 2]


def test_the_minimum_order_still_finds_forth_wordlist_and_set_order(sys_run):
    assert sys_run("-1 SET-ORDER FORTH-WORDLIST 1 SET-ORDER 1 2 +")[-1] == 3


def test_an_empty_order_finds_nothing(system, forth_error):
    system.evaluate("0 SET-ORDER")
    with pytest.raises(forth_error):
        system.evaluate("DUP")


def test_definitions_go_to_the_current_word_list(sys_run):
    src = ("WORDLIST CONSTANT W1  W1 SET-CURRENT  : HIDDEN-ONE 11 ;  FORTH-WORDLIST SET-CURRENT "
           'S" HIDDEN-ONE" W1 SEARCH-WORDLIST  S" HIDDEN-ONE" FORTH-WORDLIST SEARCH-WORDLIST')
    assert sys_run(src)[-2:] == [-1, 0]


def test_get_current_gives_what_set_current_set(sys_run):
    a, b = sys_run("WORDLIST DUP SET-CURRENT GET-CURRENT  FORTH-WORDLIST SET-CURRENT")
    assert a == b


def test_search_wordlist_gives_1_for_an_immediate_word_and_minus_1_otherwise(sys_run):
    assert sys_run('S" IF" FORTH-WORDLIST SEARCH-WORDLIST NIP '
                   'S" DUP" FORTH-WORDLIST SEARCH-WORDLIST NIP') == [1, -1]


def test_a_word_list_added_to_the_order_is_searched_first(sys_run):
    src = ("WORDLIST CONSTANT W1  W1 SET-CURRENT : DUP 99 ; FORTH-WORDLIST SET-CURRENT "
           "GET-ORDER W1 SWAP 1+ SET-ORDER  5 DUP  PREVIOUS 5 DUP")
    assert sys_run(src)[-4:] == [5, 99, 5, 5]


def test_find_follows_the_search_order(sys_run):
    src = ("WORDLIST CONSTANT W1  W1 SET-CURRENT : ZAP ; FORTH-WORDLIST SET-CURRENT "
           ': ZAP? C" ZAP" FIND NIP ;  ZAP?  GET-ORDER W1 SWAP 1+ SET-ORDER  ZAP?  PREVIOUS')
    assert sys_run(src) == [0, -1]


def test_also_duplicates_and_previous_drops_the_first_word_list(sys_run):
    before = sys_run("GET-ORDER")
    n0 = before[-1]
    stack = sys_run("ALSO GET-ORDER")[n0 + 1:]
    assert stack[-1] == n0 + 1 and stack[-2] == stack[-3]
    assert sys_run("PREVIOUS GET-ORDER")[-(n0 + 1):] == before


def test_only_forth_also_definitions_is_f83s_usual_reset(sys_run):
    stack = sys_run("ONLY FORTH ALSO DEFINITIONS GET-CURRENT FORTH-WORDLIST =")
    assert stack[-1] == -1


def test_a_vocabulary_replaces_the_first_word_list_when_it_runs(system):
    system.evaluate("VOCABULARY TOOLBOX  ALSO TOOLBOX DEFINITIONS : GADGET 7 ; "
                    "PREVIOUS DEFINITIONS")
    with pytest.raises(Exception):
        system.evaluate("GADGET")
    system.evaluate("ALSO TOOLBOX GADGET PREVIOUS")
    assert system.stack == [7]


def test_order_shows_the_search_order_and_current(system):
    out = system.evaluate("ONLY FORTH ALSO DEFINITIONS ORDER")
    assert "FORTH" in out and "Current: FORTH" in out


def test_set_order_refuses_more_than_eight_word_lists(system, forth_error):
    with pytest.raises(forth_error) as e:
        system.evaluate("FORTH-WORDLIST DUP DUP DUP DUP DUP DUP DUP DUP 9 SET-ORDER")
    assert e.value.code == -49


def test_set_order_refuses_a_number_that_is_no_word_list(system, forth_error):
    with pytest.raises(forth_error):
        system.evaluate("1234 1 SET-ORDER")
    assert system.evaluate("1 2 + .") == "3 "
