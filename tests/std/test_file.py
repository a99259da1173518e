"""Forth 2012 File-Access word set (chapter 11) on the host's files, on a
bare machine and on the full system (where RCL's OPEN and CLOSE are
commands and the standard names must still work)."""
import pytest

BUF = "CREATE BUF 300 ALLOT "


def name(path):
    return 'S" %s"' % path


@pytest.fixture
def made(sys_run, tmp_path):
    """A file created R/W holding two lines, its id in FID, position 0."""
    f = tmp_path / "two.txt"
    sys_run(BUF + name(f) + " R/W CREATE-FILE DROP VALUE FID "
            'S" first line" FID WRITE-LINE DROP '
            'S" second" FID WRITE-LINE DROP '
            "0. FID REPOSITION-FILE DROP")
    return f


# --- creating, opening, closing -----------------------------------------------------

def test_create_file_gives_an_id_and_ior_zero_and_makes_an_empty_file(sys_run, tmp_path):
    f = tmp_path / "new.txt"
    fid, ior = sys_run(name(f) + " R/W CREATE-FILE")
    assert ior == 0 and fid != 0
    assert f.exists() and f.read_bytes() == b""


def test_create_file_empties_a_file_that_exists(sys_run, tmp_path):
    f = tmp_path / "old.txt"
    f.write_text("old contents\n")
    assert sys_run(name(f) + " W/O CREATE-FILE NIP")[-1] == 0
    assert f.read_bytes() == b""


def test_open_file_of_a_missing_file_gives_a_nonzero_ior(sys_run, tmp_path):
    ior = sys_run(name(tmp_path / "absent.txt") + " R/O OPEN-FILE NIP")[-1]
    assert ior == -38


def test_open_file_opens_an_existing_file_without_emptying_it(sys_run, tmp_path):
    f = tmp_path / "keep.txt"
    f.write_text("abc\n")
    assert sys_run(name(f) + " R/O OPEN-FILE NIP")[-1] == 0
    assert f.read_text() == "abc\n"


def test_access_methods_are_distinct_and_bin_modifies_them(sys_run):
    ro, wo, rw, bro = sys_run("R/O W/O R/W R/O BIN")
    assert len({ro, wo, rw}) == 3
    assert bro != ro


def test_close_file_gives_ior_zero_once_and_nonzero_after(sys_run, made):
    assert sys_run("FID CLOSE-FILE FID CLOSE-FILE")[-2:] == [0, -37]


def test_open_and_close_name_different_words_from_the_file_words(tmp_path):
    import rcl

    full = rcl.open()                     # RCL's commands OPEN and CLOSE stay
    full.evaluate("' OPEN ' CLOSE ' OPEN-FILE ' CLOSE-FILE")
    assert len(set(full.stack)) == 4
    f = tmp_path / "x.txt"
    assert full.evaluate(name(f) + " R/W CREATE-FILE NIP .") == "0 "


# --- reading and writing ---------------------------------------------------------------

def test_read_line_gives_each_line_without_its_end_then_false_at_the_end(sys_run, made):
    stack = sys_run("BUF 100 FID READ-LINE BUF 3 PICK S\" first line\" COMPARE "
                    "BUF 100 FID READ-LINE BUF 3 PICK S\" second\" COMPARE "
                    "BUF 100 FID READ-LINE")
    assert stack == [10, -1, 0, 0, 6, -1, 0, 0, 0, 0, 0]


def test_read_line_stops_at_the_buffer_and_leaves_the_rest_for_the_next(sys_run, made):
    stack = sys_run("BUF 5 FID READ-LINE BUF 5 S\" first\" COMPARE "
                    "BUF 100 FID READ-LINE BUF 3 PICK S\"  line\" COMPARE")
    assert stack == [5, -1, 0, 0, 5, -1, 0, 0]


def test_read_line_drops_a_carriage_return_before_the_line_feed(sys_run, tmp_path):
    f = tmp_path / "dos.txt"
    f.write_bytes(b"ab\r\ncd")
    stack = sys_run(BUF + name(f) + " R/O OPEN-FILE DROP VALUE F "
                    "BUF 80 F READ-LINE BUF 80 F READ-LINE BUF 80 F READ-LINE")
    assert stack == [2, -1, 0, 2, -1, 0, 0, 0, 0]


def test_read_file_reads_up_to_u1_bytes_and_zero_at_the_end(sys_run, made):
    stack = sys_run("BUF 4 FID READ-FILE BUF 4 S\" firs\" COMPARE "
                    "BUF 300 FID READ-FILE BUF 300 FID READ-FILE")
    assert stack == [4, 0, 0, 14, 0, 0, 0]


def test_write_file_writes_the_bytes_as_they_are(sys_run, tmp_path):
    f = tmp_path / "raw.bin"
    sys_run(name(f) + " W/O BIN CREATE-FILE DROP VALUE F "
            'S\\" a\\x00b\\n" F WRITE-FILE F CLOSE-FILE')
    assert f.read_bytes() == b"a\x00b\n"


def test_write_line_ends_each_line_with_a_line_feed(sys_run, made):
    sys_run("FID CLOSE-FILE DROP")
    assert made.read_bytes() == b"first line\nsecond\n"


def test_a_read_only_file_refuses_writing_and_keeps_its_bytes(sys_run, tmp_path):
    f = tmp_path / "ro.txt"
    f.write_text("keep\n")
    ior = sys_run(name(f) + ' R/O OPEN-FILE DROP VALUE F S" junk" F WRITE-FILE')[-1]
    assert ior != 0 and f.read_text() == "keep\n"


def test_a_write_only_file_refuses_reading(sys_run, tmp_path):
    f = tmp_path / "wo.txt"
    f.write_text("data\n")
    ior = sys_run(BUF + name(f) + " W/O OPEN-FILE DROP VALUE F BUF 10 F READ-FILE")[-1]
    assert ior != 0


# --- position and size -----------------------------------------------------------------

def test_file_position_follows_writes_and_reposition_file_moves_it(sys_run, made):
    stack = sys_run("FID FILE-POSITION 6. FID REPOSITION-FILE FID FILE-POSITION "
                    "BUF 4 FID READ-FILE DROP BUF SWAP S\" line\" COMPARE")
    assert stack == [0, 0, 0, 0, 6, 0, 0, 0]


def test_file_size_counts_the_bytes_written(sys_run, made):
    assert sys_run("FID FILE-SIZE") == [18, 0, 0]


def test_resize_file_cuts_and_extends_the_file(sys_run, made):
    assert sys_run("5. FID RESIZE-FILE FID FILE-SIZE")[-4:] == [0, 5, 0, 0]
    assert sys_run("9. FID RESIZE-FILE FID FILE-SIZE FID CLOSE-FILE")[-5:] == [0, 9, 0, 0, 0]
    assert made.read_bytes() == b"first\0\0\0\0"


def test_flush_file_makes_the_bytes_visible_to_another_reader(sys_run, tmp_path):
    f = tmp_path / "fl.txt"
    assert sys_run(name(f) + ' W/O CREATE-FILE DROP VALUE F S" now" F WRITE-FILE DROP '
                   "F FLUSH-FILE")[-1] == 0
    assert f.read_bytes() == b"now"


# --- names ---------------------------------------------------------------------------

def test_file_status_says_whether_a_file_exists(sys_run, made, tmp_path):
    stack = sys_run(name(made) + " FILE-STATUS NIP " + name(tmp_path / "no") + " FILE-STATUS NIP")
    assert stack[-2] == 0 and stack[-1] != 0


def test_delete_file_removes_it_once(sys_run, tmp_path):
    f = tmp_path / "del.txt"
    f.write_text("x")
    assert sys_run(name(f) + " DELETE-FILE " + name(f) + " DELETE-FILE")[-2:] == [0, -38]
    assert not f.exists()


def test_rename_file_gives_the_file_its_new_name(sys_run, tmp_path):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text("moved\n")
    assert sys_run(name(a) + " " + name(b) + " RENAME-FILE")[-1] == 0
    assert not a.exists() and b.read_text() == "moved\n"


def test_rename_file_never_replaces_a_file_that_exists(sys_run, tmp_path):
    a, b = tmp_path / "a.txt", tmp_path / "b.txt"
    a.write_text("a\n")
    b.write_text("b\n")
    assert sys_run(name(a) + " " + name(b) + " RENAME-FILE")[-1] != 0
    assert b.read_text() == "b\n" and a.read_text() == "a\n"


# --- including -------------------------------------------------------------------------

def test_include_file_interprets_the_rest_of_the_file_with_its_id_as_source_id(
        sys_run, tmp_path):
    f = tmp_path / "inc.fs"
    f.write_text("SKIPPED LINE\n: DOUBLED 2* ; 21 DOUBLED\nSOURCE-ID\n")
    stack = sys_run(BUF + name(f) + " R/O OPEN-FILE DROP VALUE F "
                    "BUF 80 F READ-LINE 2DROP DROP F INCLUDE-FILE F")
    assert stack[0] == 42 and stack[1] == stack[2]


def test_include_file_closes_the_file_at_its_end(sys_run, tmp_path):
    f = tmp_path / "inc.fs"
    f.write_text("1\n")
    assert sys_run(name(f) + " R/O OPEN-FILE DROP VALUE F  F INCLUDE-FILE F CLOSE-FILE") == [1, -37]


def test_a_paren_comment_in_a_file_may_span_lines(sys_run, tmp_path):
    f = tmp_path / "c.fs"
    f.write_text("1 ( a comment\nover two lines ) 2\n")
    assert sys_run(name(f) + " INCLUDED") == [1, 2]


def test_required_loads_a_file_only_once(sys_run, tmp_path):
    f = tmp_path / "once.fs"
    f.write_text("1\n")
    assert sys_run(name(f) + " REQUIRED " + name(f) + " REQUIRED REQUIRE " + str(f)) == [1]


def test_s_quote_interpreted_gives_two_strings_at_once(sys_run):
    assert sys_run('S" abc" S" xyz" 2SWAP S" abc" COMPARE -ROT S" xyz" COMPARE') == [0, 0]


# --- ids cannot be forged; nothing escapes as a Python exception ------------------------

FILE_WORDS = ["CLOSE-FILE", "FLUSH-FILE", "FILE-SIZE NIP NIP", "FILE-POSITION NIP NIP",
              "BUF SWAP 10 SWAP READ-FILE NIP", "BUF SWAP 10 SWAP READ-LINE NIP NIP",
              "BUF SWAP 10 SWAP WRITE-FILE", "BUF SWAP 10 SWAP WRITE-LINE",
              "0. ROT REPOSITION-FILE", "0. ROT RESIZE-FILE"]


@pytest.mark.parametrize("word", FILE_WORDS)
@pytest.mark.parametrize("fid", ["0", "1", "4096", "-1", "HERE", "' DUP"])
def test_a_forged_file_id_gives_an_ior_from_every_file_word(sys_run, word, fid):
    assert sys_run(BUF + fid + " " + word)[-1] != 0


@pytest.mark.parametrize("src", [
    'S" " R/O OPEN-FILE NIP', 'S\\" a\\x00b" R/O OPEN-FILE NIP', "HERE 0 R/W CREATE-FILE NIP",
    'S\\" a\\x00b" DELETE-FILE', 'S" /" R/W OPEN-FILE NIP', 'S" x" 0 OPEN-FILE NIP',
    'S\\" \\x00" FILE-STATUS NIP', 'S" /nonexistent/dir/x" R/W CREATE-FILE NIP'])
def test_names_the_host_refuses_give_an_ior_not_an_exception(sys_run, src):
    assert sys_run(src)[-1] != 0


def test_an_included_file_id_that_is_not_open_is_a_forth_error(system, forth_error):
    with pytest.raises(forth_error):
        system.evaluate("4660 INCLUDE-FILE")
