"""Forth 2012 number prefixes (# $ % 'c') and loading source files
(INCLUDE, INCLUDED, REQUIRE, Forth.include)."""
import pytest


# --- number prefixes ----------------------------------------------------------------

@pytest.mark.parametrize("src, expected", [
    ("#1289", [1289]),
    ("#-1289", [-1289]),
    ("$12eF", [0x12EF]),
    ("$12EF", [0x12EF]),
    ("$-12", [-0x12]),
    ("$FFFF", [-1]),
    ("%1010", [10]),
    ("%-101", [-5]),
    ("'a'", [97]),
    ("'A'", [65]),
    ("'~'", [126]),
    ("'1'", [49]),
])
def test_a_prefix_picks_the_base_of_a_single_number(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    ("HEX #10 DECIMAL", [10]),
    ("HEX %11 DECIMAL", [3]),
    ("2 BASE ! $10 DECIMAL", [16]),
    ("$10 BASE @", [16, 10]),
    ("HEX 'a' DECIMAL", [97]),
])
def test_a_prefix_overrides_base_for_that_number_only(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("src, expected", [
    (": T $FF ; T", [255]),
    (": T #-7 ; T", [-7]),
    (": T %111 ; T", [7]),
    (": T 'z' ; T", [122]),
])
def test_prefixed_numbers_compile_as_literals(run, src, expected):
    assert run(src) == expected


@pytest.mark.parametrize("token", ["$XYZ", "%102", "#12A", "$"])
def test_a_prefix_followed_by_bad_digits_is_an_undefined_word(forth, forth_error, token):
    with pytest.raises(forth_error) as e:
        forth.evaluate(token)
    assert e.value.code == -13


# --- loading files ----------------------------------------------------------------

@pytest.fixture
def square_file(tmp_path):
    f = tmp_path / "square.fs"
    f.write_text(": SQUARE DUP * ;\n7 SQUARE\n")
    return f


def test_include_interprets_a_file(run, square_file):
    assert run(f"INCLUDE {square_file}") == [49]


def test_words_defined_by_an_included_file_stay_defined(run, square_file):
    run(f"INCLUDE {square_file}")
    assert run("DROP 3 SQUARE") == [9]


def test_the_rest_of_the_line_runs_after_include(run, square_file):
    assert run(f"INCLUDE {square_file} 5") == [49, 5]


def test_included_takes_the_file_name_as_a_string(run, square_file):
    assert run(f'S" {square_file}" INCLUDED') == [49]


def test_included_works_inside_a_definition(run, square_file):
    assert run(f': LOAD-IT S" {square_file}" INCLUDED ; LOAD-IT') == [49]


def test_forth_include_loads_a_file_from_python(forth, square_file):
    forth.include(str(square_file))
    assert list(forth.stack) == [49]


def test_a_definition_may_span_lines_of_a_file(run, tmp_path):
    f = tmp_path / "multi.fs"
    f.write_text(": T\n  1 2\n  + \\ a comment\n;\n( a comment ) T\n")
    assert run(f"INCLUDE {f}") == [3]


def test_include_nests(run, tmp_path):
    inner = tmp_path / "inner.fs"
    inner.write_text("2\n")
    outer = tmp_path / "outer.fs"
    outer.write_text(f"1\nINCLUDE {inner}\n3\n")
    assert run(f"INCLUDE {outer}") == [1, 2, 3]


@pytest.fixture
def counter_file(tmp_path):
    f = tmp_path / "counter.fs"
    f.write_text("1 CNT +!\n")
    return f


def test_include_loads_a_file_every_time(run, counter_file):
    run("VARIABLE CNT 0 CNT !")
    assert run(f"INCLUDE {counter_file} INCLUDE {counter_file} CNT @") == [2]


def test_require_loads_a_file_only_once(run, counter_file):
    run("VARIABLE CNT 0 CNT !")
    run(f"REQUIRE {counter_file}")
    run(f"REQUIRE {counter_file}")
    assert run("CNT @") == [1]


def test_require_skips_a_file_already_included(run, counter_file):
    run("VARIABLE CNT 0 CNT !")
    assert run(f"INCLUDE {counter_file} REQUIRE {counter_file} CNT @") == [1]


def test_a_missing_file_raises_forth_error(forth, forth_error, tmp_path):
    with pytest.raises(forth_error):
        forth.evaluate(f"INCLUDE {tmp_path / 'no-such-file.fs'}")


def test_a_line_longer_than_1000_characters_loads(run, tmp_path):
    f = tmp_path / "long.fs"
    f.write_text("1 DROP " * 200 + "42\n43\n")
    assert run(f"INCLUDE {f}") == [42, 43]


def test_a_long_comment_line_loads(run, tmp_path):
    f = tmp_path / "longcomment.fs"
    f.write_text("\\ " + "x" * 2000 + "\n( " + "y" * 1500 + " ) 7\n")
    assert run(f"INCLUDE {f}") == [7]


# --- errors inside files -------------------------------------------------------------

@pytest.fixture
def bad_file(tmp_path):
    f = tmp_path / "bad.fs"
    f.write_text("1 2\n: X 3 ;\nX NOSUCHWORD\n4\n")
    return f


def test_an_error_in_an_included_file_names_the_file(forth, forth_error, bad_file):
    with pytest.raises(forth_error) as e:
        forth.evaluate(f"INCLUDE {bad_file}")
    assert e.value.file.endswith("bad.fs")


def test_an_error_in_an_included_file_gives_its_line_number(forth, forth_error, bad_file):
    with pytest.raises(forth_error) as e:
        forth.evaluate(f"INCLUDE {bad_file}")
    assert e.value.line == 3
    assert e.value.code == -13
    assert ":3: " in str(e.value)


def test_an_error_in_a_file_loaded_from_python_gives_file_and_line(forth, forth_error, bad_file):
    with pytest.raises(forth_error) as e:
        forth.include(str(bad_file))
    assert e.value.file.endswith("bad.fs")
    assert e.value.line == 3


def test_an_error_in_a_nested_file_names_the_inner_file(forth, forth_error, tmp_path, bad_file):
    outer = tmp_path / "outer.fs"
    outer.write_text(f"\\ comment\nINCLUDE {bad_file}\n")
    with pytest.raises(forth_error) as e:
        forth.evaluate(f"INCLUDE {outer}")
    assert e.value.file.endswith("bad.fs")
    assert e.value.line == 3


def test_an_error_in_a_file_abandons_the_load_and_empties_the_stack(forth, forth_error, bad_file):
    with pytest.raises(forth_error):
        forth.evaluate(f"INCLUDE {bad_file}")
    assert forth.stack == []
    assert forth.evaluate("DEPTH .") == "0 "


def test_an_error_after_a_long_line_reports_the_right_line(forth, forth_error, tmp_path):
    f = tmp_path / "longbad.fs"
    f.write_text("1 DROP " * 300 + "\n\nNOSUCHWORD\n")
    with pytest.raises(forth_error) as e:
        forth.evaluate(f"INCLUDE {f}")
    assert e.value.line == 3
