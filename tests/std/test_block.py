"""Forth 2012 Block word set (chapter 7) over F83 block files: 1024-byte
blocks shown as 16 lines of 64 characters; scratch blocks in memory when
no file is open; a text file opened with USING is read only. On the bare
and full systems."""
import pytest

BLOCK = 1024


def put(system, n, text):
    """Store text at the start of block n (the rest blank) and UPDATE it."""
    system.evaluate("%d BLOCK" % n)
    system.memory.write(system.s.pop(), text.encode().ljust(BLOCK))
    system.evaluate("UPDATE")


@pytest.fixture
def blk_file(system, tmp_path):
    """A new block file of 4 blank screens, opened."""
    f = tmp_path / "test.blk"
    system.evaluate("4 CREATE-BLOCKS %s" % f)
    return f


# --- buffers ---------------------------------------------------------------------------

def test_block_works_without_any_set_up_on_scratch_blocks(sys_run):
    a, c = sys_run("1 BLOCK DUP C@")
    assert c == 32                          # a scratch block starts blank


def test_an_updated_block_is_read_back_after_its_buffer_was_reused(system):
    put(system, 3, "hello")
    system.evaluate("10 BLOCK DROP 11 BLOCK DROP 12 BLOCK DROP")
    assert system.evaluate("3 BLOCK 5 TYPE") == "hello"


def test_a_block_not_updated_loses_its_changes_when_the_buffer_is_reused(system):
    system.evaluate("5 BLOCK 1 BLANK  CHAR Z 5 BLOCK C!  6 BLOCK DROP 7 BLOCK DROP")
    assert system.evaluate("5 BLOCK C@ EMIT") == " "


def test_empty_buffers_discards_updates(system, blk_file):
    put(system, 1, "lost")
    system.evaluate("EMPTY-BUFFERS")
    assert system.evaluate("1 BLOCK 4 TYPE") == "    "
    assert blk_file.read_bytes()[BLOCK:BLOCK + 4] == b"    "


def test_flush_writes_the_block_into_its_place_in_the_file(system, blk_file):
    put(system, 2, "screen two")
    system.evaluate("FLUSH")
    data = blk_file.read_bytes()
    assert len(data) == 4 * BLOCK
    assert data[2 * BLOCK:2 * BLOCK + 10] == b"screen two"
    assert data[:2 * BLOCK] == b" " * (2 * BLOCK)


def test_save_buffers_writes_and_keeps_the_buffer(system, blk_file):
    put(system, 1, "kept")
    a = system.evaluate("SAVE-BUFFERS 1 BLOCK") or system.stack[-1]
    assert blk_file.read_bytes()[BLOCK:BLOCK + 4] == b"kept"
    assert system.evaluate("4 TYPE") == "kept"


def test_buffer_assigns_a_block_without_reading_it(system, blk_file):
    with open(blk_file, "r+b") as f:
        f.seek(BLOCK)
        f.write(b"on disk")
    assert system.evaluate("1 BUFFER 7 TYPE") != "on disk"
    assert system.evaluate("EMPTY-BUFFERS 1 BLOCK 7 TYPE") == "on disk"


def test_a_block_outside_the_file_is_an_error(system, blk_file, forth_error):
    with pytest.raises(forth_error):
        system.evaluate("4 BLOCK")


# --- loading ---------------------------------------------------------------------------

def test_load_interprets_the_block_with_blk_set_and_restores_it(system):
    put(system, 2, ": TWICE 2* ;  21 TWICE  BLK @")
    system.evaluate("2 LOAD BLK @")
    assert system.stack == [42, 2, 0]


def test_loads_nest_and_the_outer_block_goes_on_after_the_inner(system):
    put(system, 3, "1 4 LOAD 3")
    put(system, 4, "2")
    assert system.evaluate("3 LOAD") == "" and system.stack == [1, 2, 3]


def test_thru_loads_each_block_of_the_range(system):
    for n in (1, 2, 3):
        put(system, n, "%d" % (n * 10))
    system.evaluate("1 3 THRU")
    assert system.stack == [10, 20, 30]


def test_arrow_goes_on_with_the_next_block(system):
    put(system, 5, "5 -->")
    put(system, 6, "6")
    system.evaluate("5 LOAD")
    assert system.stack == [5, 6]


def test_refill_in_a_block_goes_on_with_the_next_block(system):
    put(system, 7, "7 REFILL")
    put(system, 8, "8 BLK @")
    system.evaluate("7 LOAD")
    assert system.stack == [7, -1, 8, 8]


def test_backslash_in_a_block_skips_to_the_end_of_its_64_column_line(system):
    line0 = "1 \\ comment 99".ljust(64)
    put(system, 2, line0 + "2")
    system.evaluate("2 LOAD")
    assert system.stack == [1, 2]


def test_evaluate_inside_a_block_reads_from_the_string_with_blk_zero(system):
    put(system, 2, 'S" BLK @" EVALUATE BLK @')
    system.evaluate("2 LOAD")
    assert system.stack == [0, 2]


def test_save_and_restore_input_go_back_within_a_block(system):
    system.evaluate("VARIABLE N 0 N !")
    put(system, 2, "SAVE-INPUT  1 N +!  N @ 2 < [IF] RESTORE-INPUT [THEN] N @")
    system.evaluate("2 LOAD")
    assert system.stack == [0, 2]           # RESTORE-INPUT's flag, then N after two passes


def test_block_zero_cannot_be_loaded(system, forth_error):
    with pytest.raises(forth_error):
        system.evaluate("0 LOAD")


def test_an_error_in_a_screen_names_the_file_the_screen_and_the_line(system, blk_file,
                                                                      forth_error):
    put(system, 2, "1 2 +".ljust(64) + "".ljust(64) + "  NO-SUCH-WORD")
    with pytest.raises(forth_error) as e:
        system.evaluate("2 LOAD")
    assert e.value.file == str(blk_file)
    assert e.value.line == "screen 2 line 2"
    assert "screen 2 line 2" in str(e.value) and "NO-SUCH-WORD" in str(e.value)


# --- LIST and SCR ------------------------------------------------------------------------

def test_list_shows_sixteen_numbered_lines_and_sets_scr(system):
    put(system, 3, "\\ title line".ljust(64) + "second")
    out = system.evaluate("3 LIST SCR @")
    lines = out.strip("\n").split("\n")
    assert lines[0].startswith("Scr # 3")
    assert lines[1] == "  0 \\ title line" and lines[2] == "  1 second"
    assert len(lines) == 17 and lines[16].startswith(" 15")
    assert system.stack == [3]


# --- block files -----------------------------------------------------------------------

def test_create_blocks_makes_a_file_of_blank_screens(blk_file):
    assert blk_file.read_bytes() == b" " * (4 * BLOCK)


def test_create_blocks_never_overwrites_a_file(system, tmp_path, forth_error):
    f = tmp_path / "precious.blk"
    f.write_bytes(b"x" * BLOCK)
    with pytest.raises(forth_error):
        system.evaluate("2 CREATE-BLOCKS %s" % f)
    assert f.read_bytes() == b"x" * BLOCK


def test_using_opens_an_existing_block_file(system, tmp_path):
    f = tmp_path / "old.blk"
    f.write_bytes(b" " * BLOCK + b"40 2 +".ljust(BLOCK))
    system.evaluate("USING %s 1 LOAD" % f)
    assert system.stack == [42]


def test_using_a_missing_file_says_how_to_create_one(system, tmp_path, forth_error):
    with pytest.raises(forth_error) as e:
        system.evaluate("USING %s" % (tmp_path / "none.blk"))
    assert "CREATE-BLOCKS" in str(e.value)


def test_more_adds_blank_screens_to_the_end(system, blk_file):
    system.evaluate("2 MORE")
    assert blk_file.read_bytes() == b" " * (6 * BLOCK)
    system.evaluate("5 BLOCK DROP")


def test_a_text_file_opened_with_using_begins_at_screen_one(system, tmp_path):
    f = tmp_path / "src.fs"
    f.write_text(": SQ DUP * ;\n7 SQ\n")
    system.evaluate("USING %s 1 LOAD" % f)
    assert system.stack == [49]


def test_a_text_file_opened_with_using_refuses_update_and_stays_as_it_was(
        system, tmp_path, forth_error):
    f = tmp_path / "src.fs"
    text = ": SQ DUP * ;\n7 SQ\n"
    f.write_text(text)
    system.evaluate("USING %s" % f)
    with pytest.raises(forth_error) as e:
        system.evaluate("1 BLOCK 5 BLANK UPDATE")
    assert "read only" in str(e.value) and "rcl.blocks" in str(e.value)
    system.evaluate("FLUSH SAVE-BUFFERS")
    assert f.read_text() == text


def test_an_error_in_a_text_screen_names_the_line_of_the_text_too(system, tmp_path,
                                                                   forth_error):
    f = tmp_path / "src.fs"
    f.write_text("\n".join(["1"] * 20 + ["BAD-WORD"]) + "\n")
    with pytest.raises(forth_error) as e:
        system.evaluate("USING %s 1 2 THRU" % f)
    assert e.value.line == "screen 2 line 4 (line 21 of the text)"


def test_using_a_text_file_with_a_long_line_is_refused_with_its_number(system, tmp_path,
                                                                       forth_error):
    f = tmp_path / "wide.fs"
    f.write_text("1\n" + "2 " * 40 + "\n")
    with pytest.raises(forth_error) as e:
        system.evaluate("USING %s" % f)
    assert "line 2 " in str(e.value)


# --- python -m rcl.blocks ------------------------------------------------------------

TEXT = "\\ squares\n: SQ ( n -- n*n ) DUP * ;\n" + "\n" * 20 + "7 SQ\n"


def test_text_becomes_a_block_file_with_a_title_screen_and_text_from_screen_one(tmp_path):
    from rcl.blocks import main

    src, dst = tmp_path / "sq.fs", tmp_path / "sq.blk"
    src.write_text(TEXT)
    assert main([str(src), str(dst)]) == 0
    data = dst.read_bytes()
    assert len(data) == 3 * BLOCK                       # title + 23 lines in two screens
    assert data[:64].rstrip() == b"\\ " + str(src).encode()[-5:] or data[:2] == b"\\ "
    assert data[BLOCK:BLOCK + 64].rstrip() == b"\\ squares"
    assert data[BLOCK + 64:BLOCK + 128].rstrip() == b": SQ ( n -- n*n ) DUP * ;"


def test_a_converted_file_loads_like_the_text(system, tmp_path):
    from rcl.blocks import main

    src, dst = tmp_path / "sq.fs", tmp_path / "sq.blk"
    src.write_text(TEXT)
    main([str(src), str(dst)])
    system.evaluate("USING %s 1 2 THRU" % dst)
    assert system.stack == [49]


def test_text_to_blocks_and_back_gives_the_same_text(tmp_path):
    from rcl.blocks import main

    src, blk, back = tmp_path / "a.fs", tmp_path / "a.blk", tmp_path / "b.fs"
    src.write_text(TEXT)
    main([str(src), str(blk)])
    assert main([str(blk), str(back)]) == 0
    assert back.read_text() == TEXT


def test_lines_over_64_columns_are_refused_with_their_line_numbers(tmp_path, capsys):
    from rcl.blocks import main

    src, dst = tmp_path / "w.fs", tmp_path / "w.blk"
    src.write_text("ok\n" + "x" * 65 + "\n" + "y" * 64 + "\n\t" + "z" * 60 + "\n")
    assert main([str(src), str(dst)]) == 1
    err = capsys.readouterr().err
    assert "lines 2, 4 longer than 64 columns" in err
    assert not dst.exists()


def test_the_converter_never_overwrites_a_file_unless_forced(tmp_path, capsys):
    from rcl.blocks import main

    src, dst = tmp_path / "a.fs", tmp_path / "a.blk"
    src.write_text("1\n")
    dst.write_bytes(b"keep")
    assert main([str(src), str(dst)]) == 1
    assert dst.read_bytes() == b"keep" and "--force" in capsys.readouterr().err
    assert main([str(src), str(dst), "--force"]) == 0
    assert len(dst.read_bytes()) == 2 * BLOCK


def test_the_converter_as_a_module_reports_a_missing_file_without_a_traceback(tmp_path):
    import subprocess
    import sys

    r = subprocess.run([sys.executable, "-m", "rcl.blocks", str(tmp_path / "no.fs"),
                        str(tmp_path / "no.blk")], capture_output=True, text=True)
    assert r.returncode == 1 and "Traceback" not in r.stderr and "no.fs" in r.stderr
