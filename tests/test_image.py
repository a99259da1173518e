"""SAVE-SYSTEM and `rcl --image`: the whole system round-trips through a
file (definitions, variables, vocabularies, RCL's settings), starts with
RCL's interrupt handler installed again, and every bad file is refused
with a clear message that leaves the machine as it was."""
import os
import subprocess
import sys

import pytest

import rcl
from rcl.board import FORTH_CS
from rcl.forth import image
from rcl.forth.image import ImageError

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
USER = (": SQ  DUP * ;  VARIABLE V  42 V !  3 4 + CONSTANT SEVEN "
        ": COUNTER  CREATE 0 ,  DOES> 1 OVER +! @ ;  COUNTER CLICKS  CLICKS DROP "
        "DEFER GREET  : HI  .\" hi\" ;  ' HI IS GREET "
        "VOCABULARY TOOLS  ONLY FORTH ALSO TOOLS DEFINITIONS  : HAMMER  5 ;  FORTH DEFINITIONS "
        "RERB 10 IPS  .2 G  HEX")


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """A system with user words and RCL settings, saved; -> its path."""
    path = str(tmp_path_factory.mktemp("img") / "robot.img")
    m = rcl.open()
    m.evaluate(USER)
    m.evaluate("SAVE-SYSTEM " + path)
    return path


@pytest.fixture
def started(saved):
    return rcl.open(image=saved)


# ------------------------------------------------------------ round trip
def test_definitions_and_variables_come_back_as_saved(started):
    m = started
    assert m.evaluate("DECIMAL 7 SQ . V @ . SEVEN . CLICKS . CLICKS .") == "49 42 7 2 3 "


def test_deferred_words_and_vocabularies_come_back(started):
    assert started.evaluate("GREET TOOLS HAMMER . FORTH") == "hi5 "


def test_the_number_base_in_force_when_saved_comes_back(started):
    assert started.evaluate("10 .") == "10 " and started.evaluate("DECIMAL 10 .") == "10 "
    assert started.evaluate("HEX 10 DECIMAL .") == "16 "


def test_rcl_settings_come_back_and_a_move_uses_them(started):
    m = started
    m.evaluate("DECIMAL")
    settings = m.evaluate(".SETTINGS")
    assert "count 440" in settings                    # 10 IPS: 8253 count 440
    t0 = m.sim.seconds
    m.evaluate("RERB 1 FEET FORWARD")
    assert m.sim.pose[0] == pytest.approx(12.0, abs=0.15)
    assert m.sim.seconds - t0 > 1.0                   # 1 ft at 10 IPS, not at 2 MPH


def test_rcl_interrupt_handler_is_installed_again(started):
    board = started.sim.board
    seg, off = board.vector(0x1C)
    assert seg == FORTH_CS and off == started.dictionary.find("CONTROL")[0]
    assert board.tick_period() == 6667 * 54_000       # the 10 ms tick
    ticks = board.ticks
    started.sim.run(0.1)
    assert board.ticks - ticks == 10


def test_the_board_is_not_part_of_the_image(started):
    assert started.sim.pose == (0.0, 0.0, 0.0) and started.sim.relays == (0, 0)
    assert started.sim.seconds < 1


def test_files_loaded_before_the_save_are_not_required_again(tmp_path):
    path = str(tmp_path / "mail.img")
    m = rcl.open()
    m.include(os.path.join(rcl.SCREENS, "examples", "listing5.fs"))
    m.evaluate("SAVE-SYSTEM " + path)
    n = rcl.open(image=path)
    assert n.evaluate("REQUIRE %s" % os.path.join(rcl.SCREENS, "examples", "listing4.fs")) == ""
    assert n.dictionary.find("TRIP") is not None


def test_rcl_image_starts_the_saved_system_from_the_command_line(tmp_path):
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    run = lambda *a, stdin="": subprocess.run(  # noqa: E731
        [sys.executable, "-m", "rcl", *a], input=stdin, capture_output=True, text=True,
        timeout=60, cwd=tmp_path, env=env)
    first = run(stdin=": CUBE  DUP DUP * * ;  RERB 1 FEET FORWARD  SAVE-SYSTEM cube.img\n")
    assert first.returncode == 0 and first.stdout == ""
    again = run("--image", "cube.img", "-e", "3 CUBE . RERB 1 FEET BACKWARD .POSE")
    assert again.returncode == 0, again.stderr
    assert again.stdout.startswith("27 x -")             # the board starts at its origin
    assert float(again.stdout.split()[2]) == pytest.approx(-12.0, abs=0.15)


# -------------------------------------------------------------- refusals
def refused(path, match):
    m = rcl.Forth()
    m.evaluate(": KEPT 99 ;")
    with pytest.raises(ImageError, match=match):
        image.load(m, str(path))
    assert m.evaluate("KEPT .") == "99 "              # the machine is as it was


def test_a_foreign_file_is_refused(tmp_path):
    path = tmp_path / "notes.img"
    path.write_text("Dear robot, ...\n")
    refused(path, "is not an rcl system image")


def test_an_empty_file_is_refused(tmp_path):
    path = tmp_path / "empty.img"
    path.write_bytes(b"")
    refused(path, "is not an rcl system image")


def test_a_truncated_image_is_refused_with_its_length(saved, tmp_path):
    data = open(saved, "rb").read()
    for cut in (60, len(data) // 2, len(data) - 1):
        path = tmp_path / ("cut%d.img" % cut)
        path.write_bytes(data[:cut])
        refused(path, r"is truncated \(%d bytes" % cut)


def test_a_damaged_image_is_refused_by_its_checksum(saved, tmp_path):
    data = bytearray(open(saved, "rb").read())
    for at in (len(data) - 100, 30, 60):              # payload, fingerprint, length
        bad = bytearray(data)
        bad[at] ^= 0x01
        path = tmp_path / ("bad%d.img" % at)
        path.write_bytes(bytes(bad))
        refused(path, "is damaged|is truncated")


def test_an_image_of_another_version_is_refused(tmp_path, monkeypatch):
    m = rcl.Forth()
    path = str(tmp_path / "old.img")
    monkeypatch.setattr(image, "version", lambda: "0.0.9")
    image.save(m, path)
    monkeypatch.undo()
    refused(path, r"saved by another version of rcl \(0.0.9\); this is rcl")


def test_an_image_of_another_build_is_refused(tmp_path, monkeypatch):
    m = rcl.Forth()
    path = str(tmp_path / "build.img")
    monkeypatch.setattr(image, "fingerprint", lambda: bytes(32))
    image.save(m, path)
    monkeypatch.undo()
    refused(path, "another build")


def test_an_image_of_another_format_is_refused(saved, tmp_path):
    data = bytearray(open(saved, "rb").read())
    data[8] = 2
    path = tmp_path / "format2.img"
    path.write_bytes(bytes(data))
    refused(path, "image format 2")


def test_a_missing_image_is_refused_by_name():
    refused("/nonexistent/robot.img", "cannot read /nonexistent/robot.img")


def test_rcl_image_refuses_a_bad_file_with_a_message_not_a_traceback(tmp_path):
    (tmp_path / "bad.img").write_bytes(b"RCLIMAGE\x01\x00garbage")
    env = dict(os.environ, PYTHONPATH=ROOT + os.pathsep + os.environ.get("PYTHONPATH", ""))
    done = subprocess.run([sys.executable, "-m", "rcl", "--image", "bad.img"], input="",
                          capture_output=True, text=True, timeout=60, cwd=tmp_path, env=env)
    assert done.returncode == 2 and "Traceback" not in done.stderr
    assert "rcl: --image: bad.img is truncated" in done.stderr


# --------------------------------------------------------------- writing
def test_a_failed_save_leaves_the_old_image_whole(saved, tmp_path, monkeypatch):
    path = tmp_path / "keep.img"
    path.write_bytes(open(saved, "rb").read())
    before = path.read_bytes()

    def disk_full(fd):
        raise OSError(28, "No space left on device")
    monkeypatch.setattr(os, "fsync", disk_full)
    m = rcl.Forth()
    with pytest.raises(rcl.ForthError, match="No space left on device"):
        m.evaluate("SAVE-SYSTEM %s" % path)
    assert path.read_bytes() == before
    assert os.listdir(tmp_path) == ["keep.img"]        # no temporary file left


def test_save_system_into_a_missing_folder_is_a_forth_error():
    m = rcl.Forth()
    with pytest.raises(rcl.ForthError, match="cannot write /nonexistent/x.img"):
        m.evaluate("SAVE-SYSTEM /nonexistent/x.img")
