"""The `rcl` command line with standard input not a terminal: plain Forth
source in, only what the program prints out, F83's error text on stdout,
exit status 0 or 1. Each test runs `python3 -m rcl` as a user would."""
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def rcl(*args, stdin="", cwd=None):
    """Run `python3 -m rcl ARGS` with stdin from a pipe; -> CompletedProcess.
    Fails the test if anything looks like a Python traceback."""
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, "-m", "rcl", *args], input=stdin,
                          capture_output=True, text=True, timeout=60, cwd=cwd, env=env)
    assert "Traceback" not in done.stdout + done.stderr
    return done


@pytest.fixture
def source(tmp_path):
    """Write a Forth source file; -> its path."""
    def write(text, name="prog.fs"):
        path = tmp_path / name
        path.write_text(text)
        return str(path)
    return write


def test_piped_line_prints_only_what_the_program_prints_and_a_final_newline():
    done = rcl(stdin="2 3 + .\n")
    assert (done.stdout, done.returncode) == ("5 \n", 0)


def test_each_piped_line_that_prints_ends_its_output_with_a_newline():
    done = rcl(stdin='1 .\n\n2 3 + .\n: SHOUT ." deg FT" ;\nSHOUT\nNOSUCH\n')
    assert done.stdout == "1 \n5 \ndeg FT\nNOSUCH  ? \n"


def test_page_in_a_pipe_is_a_form_feed_not_a_terminal_sequence():
    assert rcl(stdin="1 . PAGE 2 .\n").stdout == "1 \f2 \n"


def test_piped_input_without_final_newline_still_runs():
    assert rcl(stdin="2 3 + .").stdout == "5 \n"


def test_empty_input_exits_zero_and_prints_nothing():
    done = rcl(stdin="")
    assert (done.stdout, done.stderr, done.returncode) == ("", "", 0)


def test_unknown_word_shows_f83_text_exits_one_and_next_line_runs():
    done = rcl(stdin="foo\n1 2 + .\n")
    assert done.stdout == "FOO  ? \n3 \n"
    assert done.returncode == 1


def test_stack_underflow_shows_f83_text_between_blanks():
    done = rcl(stdin="drop\n")
    assert (done.stdout, done.returncode) == (" Stack Underflow \n", 1)


def test_error_abandons_the_rest_of_its_line_only():
    assert rcl(stdin="1 . foo 2 .\n3 .\n").stdout == "1 FOO  ? \n3 \n"


def test_colon_definition_spans_piped_lines():
    assert rcl(stdin=": SQ\n DUP * ;\n7 SQ .\n").stdout == "49 \n"


def test_bye_exits_zero_and_stops_reading():
    done = rcl(stdin="1 .\nBYE\n2 .\n")
    assert (done.stdout, done.returncode) == ("1 \n", 0)


def test_bye_inside_a_word_exits():
    done = rcl(stdin=": QUIT-NOW 7 . BYE ; QUIT-NOW 8 .\n9 .\n")
    assert (done.stdout, done.returncode) == ("7 \n", 0)


def test_bye_after_an_error_exits_one():
    assert rcl(stdin="foo\nBYE\n").returncode == 1


def test_accept_reads_the_next_piped_line():
    done = rcl(stdin="PAD 80 ACCEPT PAD SWAP TYPE\nhello world\n1 .\n")
    assert done.stdout == "hello world\n1 \n"


def test_key_reads_the_next_piped_characters_enter_as_13():
    assert rcl(stdin="KEY . KEY . KEY .\nAB\n").stdout == "65 66 13 \n"


def test_accept_at_end_of_input_reads_an_empty_line():
    done = rcl(stdin="PAD 80 ACCEPT .\n")
    assert done.stdout.endswith("0 \n") and done.returncode == 0    # after F83's isn't uniques


def test_key_at_end_of_input_is_an_error_not_a_crash():
    done = rcl(stdin="KEY .\n")
    assert (done.stdout, done.returncode) == (" No input \n", 1)


def test_file_loads_before_standard_input(source):
    path = source(": GREET .\" hi\" ;\n")
    assert rcl(path, stdin="GREET\n").stdout == "hi\n"


def test_files_load_in_order(source):
    first = source(": A 1 . ;\n", "a.fs")
    second = source(": B A 2 . ;\n", "b.fs")
    assert rcl(first, second, stdin="B\n").stdout == "1 2 \n"


def test_file_error_prints_file_and_line_on_stderr_and_exits_one(source):
    path = source(": OK1 1 . ;\n\n  foo\n")
    done = rcl(path, stdin="1 .\n")
    assert done.stderr == "%s:3: FOO  ?\n" % path
    assert done.returncode == 1
    assert done.stdout == ""                     # stdin is not read after it


def test_file_error_stops_the_later_files_and_e_and_stdin_as_the_guide_says(source):
    bad, good = source("foo\n", "bad.fs"), source("2 .\n", "good.fs")
    done = rcl(bad, good, "-e", "3 .", stdin="4 .\n")
    assert (done.stdout, done.stderr, done.returncode) == ("", "%s:1: FOO  ?\n" % bad, 1)


def test_file_error_message_keeps_f83_text(source):
    path = source("DROP\n")
    assert rcl(path).stderr == "%s:1: Stack Underflow\n" % path


def test_missing_file_says_so_without_traceback(tmp_path):
    missing = str(tmp_path / "nosuch.fs")
    done = rcl(missing, stdin="1 .\n")
    assert done.stderr == "%s: File not found\n" % missing
    assert done.returncode == 1


def test_directory_as_file_is_an_error_without_traceback(tmp_path):
    done = rcl(str(tmp_path))
    assert done.returncode == 1
    assert done.stderr == "%s: Is a directory\n" % tmp_path


def test_e_words_run_after_files_and_before_stdin(source):
    path = source(": SQ DUP * ;\n")
    done = rcl(path, "-e", "7 SQ .", stdin="1 .\n")
    assert (done.stdout, done.returncode) == ("49 1 \n", 0)


def test_e_may_be_given_more_than_once_and_runs_in_order():
    assert rcl("-e", "1 .", "-e", "2 .").stdout == "1 2 \n"


def test_e_may_come_before_the_files(source):
    path = source(": SQ DUP * ;\n")
    assert rcl("-e", "3 SQ .", path).stdout == "9 \n"


def test_e_error_is_reported_on_stderr_and_exits_one():
    done = rcl("-e", "foo", stdin="1 .\n")
    assert done.stderr == "-e: FOO  ?\n"
    assert (done.stdout, done.returncode) == ("", 1)


def test_e_bye_exits_zero_without_reading_stdin():
    done = rcl("-e", "5 . BYE", stdin="6 .\n")
    assert (done.stdout, done.returncode) == ("5 \n", 0)


def test_bare_is_accepted():
    assert rcl("--bare", stdin="2 3 * .\n").stdout == "6 \n"


def test_version_names_rcl():
    done = rcl("--version")
    assert done.returncode == 0
    assert done.stdout.startswith("rcl ")


def test_unknown_option_is_a_usage_error_without_traceback():
    done = rcl("--no-such-option")
    assert done.returncode == 2
    assert "usage: rcl" in done.stderr


def test_undecodable_input_bytes_do_not_crash():
    env = dict(os.environ, PYTHONPATH=ROOT)
    done = subprocess.run([sys.executable, "-m", "rcl"], input=b"\xff\xfe 1 .\n2 .\n",
                          capture_output=True, timeout=60, env=env)
    assert b"Traceback" not in done.stdout + done.stderr
    assert done.stdout.endswith(b"2 \n")


# ------------------------------------------------ options and start-up
def test_start_sets_the_time_of_day_24_hour():
    assert rcl("--start", "13:45", "-e", ".TIME").stdout == "13:45:00 \n"


def test_start_sets_the_time_of_day_on_a_board_over_a_link_too():
    # (it was left at midnight: --start only reached the simulated board)
    assert rcl("--port", "rclsim://", "--start", "08:00", "-e", ".TIME").stdout == "08:00:00 \n"


def test_start_now_takes_the_hosts_clock():
    import datetime
    before = datetime.datetime.now()
    shown = rcl("--start", "now", "-e", ".TIME").stdout.strip()
    h, m, _ = (int(x) for x in shown.split(":"))
    # the host clock read before and at start-up: same minute, or the next one
    starts = {(before.hour, before.minute),
              ((before + datetime.timedelta(minutes=1)).hour,
               (before + datetime.timedelta(minutes=1)).minute)}
    assert (h, m) in starts


def test_start_rejects_a_12_hour_or_malformed_time():
    for bad in ("25:00", "8 AM", "12:60", "noon"):
        done = rcl("--start", bad)
        assert done.returncode == 2
        assert "HH:MM (24-hour) or now" in done.stderr


def test_set_clock_sets_a_24_hour_time_at_the_prompt():
    assert rcl(stdin="17 5 SET-CLOCK .TIME\n").stdout == "17:05:00 \n"


def test_set_clock_refuses_a_time_past_23_59():
    assert rcl(stdin="24 0 SET-CLOCK\n").stdout == " Bad time \n"


def test_board_only_has_the_board_without_rcl():
    # the BIOS's ticks-a-day count (0:04F0 = 1,573,040: low cell 176) is there
    done = rcl("--board-only", stdin="0 1264 L@ . RERB\n")
    assert done.stdout == "176 RERB  ? \n"


def test_board_only_can_load_rcl_layer_by_layer():
    layers = "".join("INCLUDE %s\n" % n for n in
                     ("10-hardware.fs", "20-interrupts.fs", "30-counters.fs"))
    done = rcl("--board-only", stdin=layers + "INSTALL INSTALLED @ .\n")
    assert done.stdout.endswith("-1 \n")


def test_bare_refuses_board_options():
    done = rcl("--bare", "--board-only")
    assert done.returncode == 2
    assert "--bare has no board" in done.stderr


def test_screens_loads_rcl_from_another_folder(tmp_path):
    import shutil
    copy = tmp_path / "myrcl"
    shutil.copytree(rcl_module().SCREENS, copy)
    with open(copy / "95-status.fs", "a") as f:
        f.write(": MINE  42 . ;\n")
    assert rcl("--screens", str(copy), "-e", "MINE").stdout == "42 \n"


def test_screens_without_a_load_screen_is_a_usage_error(tmp_path):
    done = rcl("--screens", str(tmp_path))
    assert done.returncode == 2 and "no rcl.fs" in done.stderr


def test_include_finds_the_listings_from_any_directory(tmp_path):
    done = rcl("-e", "INCLUDE examples/listing1.fs .POSE", cwd=str(tmp_path))
    assert done.returncode == 0
    assert done.stdout.startswith("x ")


def test_a_file_argument_is_looked_for_in_the_screens_folder(tmp_path):
    done = rcl("examples/listing3.fs", "-e", "DEPTH .", cwd=str(tmp_path))
    assert done.stdout.endswith("0 \n") and done.returncode == 0    # after F83's isn't uniques


def test_an_error_in_a_file_included_from_a_pipe_names_file_and_line(source):
    path = source("1 2 +\nfoo\n")
    done = rcl(stdin="INCLUDE %s\n3 .\n" % path)
    assert done.stdout == " %s:2: FOO  ? \n3 \n" % path


def test_e_output_ends_with_a_newline():
    assert rcl("-e", "1 .").stdout == "1 \n"


def rcl_module():
    import rcl as package
    return package


def test_lines_after_an_error_in_an_open_definition_are_skipped_up_to_its_semicolon():
    done = rcl(stdin=": BAD 1\nfoo\n7 .\n8 . ;\n9 .\n")
    assert done.stdout == ("FOO  ? \nBAD is abandoned: the lines up to its ; are skipped\n"
                           "7 . skipped\n8 . ; skipped, the definition is over\n9 \n")
    assert done.returncode == 1


def test_an_error_in_a_one_line_definition_skips_nothing():
    assert rcl(stdin=": OK 1 foo 2 ;\n3 .\n").stdout == "FOO  ? \n3 \n"


def test_an_error_in_a_definition_of_an_included_file_skips_nothing_after_the_file(source):
    trip = source("\n\n: TRIP 1 TRUN-LEFT 2 ;\n", "trip.fs")
    done = rcl(stdin="INCLUDE %s\n2 3 + .\n" % trip)
    assert done.stdout == " %s:3: TRUN-LEFT  ? \n5 \n" % trip
    assert done.returncode == 1


def test_an_error_in_the_users_screens_is_a_file_error_exit_one(tmp_path):
    import shutil
    screens = tmp_path / "myscreens"
    shutil.copytree(os.path.join(ROOT, "screens"), str(screens))
    with open(str(screens / "95-status.fs"), "a") as f:
        f.write("NOSUCHWORD\n")
    lines = len(open(str(screens / "95-status.fs")).read().split("\n")) - 1
    done = rcl("--screens", str(screens), stdin="1 .\n")
    assert done.stderr == "%s:%d: NOSUCHWORD  ?\n" % (screens / "95-status.fs", lines)
    assert done.returncode == 1 and "internal" not in done.stderr


def test_an_image_given_as_a_file_says_to_use_image(tmp_path):
    img = str(tmp_path / "robot.img")
    assert rcl(stdin='SAVE-SYSTEM %s\n' % img).returncode == 0
    done = rcl(img, stdin="1 .\n")
    assert done.stderr == ("%s: a saved system, not Forth source: start from it with "
                           "rcl --image %s\n" % (img, img))
    assert done.returncode == 1
    assert rcl("--image", img, stdin="1 .\n").stdout == "1 \n"


def test_the_blocks_module_runs_without_a_warning(tmp_path):
    text = tmp_path / "a.fs"
    text.write_text(": X 1 ;\n")
    env = dict(os.environ, PYTHONPATH=ROOT)
    done = subprocess.run([sys.executable, "-W", "error", "-m", "rcl.blocks", str(text),
                           str(tmp_path / "a.blk")], capture_output=True, text=True, env=env)
    assert (done.returncode, done.stderr) == (0, "")
