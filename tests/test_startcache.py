"""rcl.startcache: a system started from the kept copy of loaded RCL is the
system the screens build, exactly; the copy is used only for the code and
screens it was made from, and a bad or unwritable cache is no error."""
import os
import pickle
import shutil

import pytest

import rcl
from rcl import startcache
from rcl.forth import state
from rcl.sim.board import SimBoard

SQUARE = os.path.join(rcl.SCREENS, "examples", "listing1.fs")


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """An empty cache folder, and nothing kept in this process."""
    monkeypatch.setenv("RCL_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(startcache, "_kept", {})
    return tmp_path / "cache"


def files(cache):
    return sorted(p.name for p in cache.iterdir()) if cache.exists() else []


def after_the_square(m):
    out = m.evaluate("RERB 2 MPH 3.4 FEET FORWARD")
    m.include(SQUARE)
    return (out, m.evaluate(".POSE"), m.clock, m.sim.ticks, m.sim.bios_ticks,
            m.sim.wheel_counts, m.sim.pose)


def test_a_system_from_the_kept_copy_drives_the_square_exactly_as_a_loaded_one(cache):
    loaded = rcl.open(board=SimBoard())          # a board of one's own: never a copy
    first = rcl.open()                            # loads, keeps a copy, returns one
    assert len(files(cache)) == 1
    startcache._kept.clear()
    copied = rcl.open()                           # from the file
    assert copied.fn == {}                        # compiled again on first use
    assert loaded.clock == first.clock == copied.clock
    expected = after_the_square(loaded)
    assert after_the_square(first) == expected
    assert after_the_square(copied) == expected


def test_each_open_from_the_copy_is_a_system_of_its_own(cache):
    a = rcl.open()
    a.evaluate(": MINE 42 ;  RERB 2 MPH 3.4 FEET FORWARD")
    b = rcl.open()
    assert b.dictionary.find("MINE") is None
    assert b.sim.wheel_counts == (0, 0) and a.sim.wheel_counts != (0, 0)


def test_output_goes_to_the_callers_writer(cache):
    rcl.open()
    said = []
    m = rcl.open(write=said.append)
    m.evaluate("1 2 + .")
    assert "".join(said) == "3 "


def test_changed_screens_are_loaded_not_taken_from_the_copy(cache, tmp_path):
    screens = tmp_path / "screens"
    shutil.copytree(rcl.SCREENS, screens)
    rcl.open(screens=str(screens))
    with open(screens / "rcl.fs", "a") as f:
        f.write(": ADDED  7 ;\n")
    os.utime(screens / "rcl.fs", ns=(0, 1))        # a different time, whatever the clock
    m = rcl.open(screens=str(screens))
    assert m.evaluate("ADDED .") == "7 "
    assert len(files(cache)) == 2                  # one copy per version of the screens


def test_a_damaged_cache_file_is_ignored_and_written_again(cache):
    rcl.open()
    (name,) = files(cache)
    whole = (cache / name).read_bytes()
    (cache / name).write_bytes(whole[:-100] + b"\0" * 100)
    startcache._kept.clear()
    m = rcl.open()
    assert m.evaluate("1 2 + .") == "3 "
    startcache._kept.clear()
    assert startcache.fetch(startcache.key(rcl.SCREENS)) is not None   # written again


def test_a_cache_folder_that_cannot_be_made_means_loading_every_time(tmp_path, monkeypatch):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("RCL_CACHE_DIR", str(blocker / "rcl"))
    monkeypatch.setattr(startcache, "_kept", {})
    m = rcl.open()
    assert m.evaluate("1 2 + .") == "3 "
    assert blocker.read_text() == "not a folder"


def test_a_kept_copy_this_code_cannot_read_is_forgotten_and_the_screens_loaded(cache):
    rcl.open()
    k = startcache.key(rcl.SCREENS)
    startcache._kept[k] = b"not a pickle"
    m = rcl.open()
    assert m.evaluate("1 2 + .") == "3 " and startcache._kept[k] != b"not a pickle"


def test_copies_not_written_for_a_week_are_removed_when_a_new_one_is_kept(cache):
    cache.mkdir()
    old, recent = cache / "start-x-00000001.pickle", cache / "start-x-00000002.pickle"
    for p in (old, recent):
        p.write_bytes(b"another build's copy")
    os.utime(old, (0, 0))
    rcl.open()
    assert not old.exists() and recent.exists() and len(files(cache)) == 2


def test_a_kept_copy_is_the_one_snapshot_the_machines_time_and_the_board(cache):
    # state.py's snapshot (what SAVE-SYSTEM writes and the boot copy is):
    # no machine or word set object is pickled, only the board.
    m = rcl.open()
    data = startcache._kept[startcache.key(rcl.SCREENS)]
    snap, (clock, *_), board = pickle.loads(data)
    assert set(snap) == set(state.SYSTEM) | {"memory", "headers"}
    assert b"rcl.forth" not in data and b"rcl.words" not in data
    assert isinstance(board, SimBoard) and board.machine is None
    assert clock == m.clock and snap["memory"] == bytes(m.mem)
    assert m.board.machine is m and m.fast_forward is m.board
