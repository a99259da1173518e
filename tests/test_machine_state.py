"""The machine's state, declared (rcl/forth/state.py): one snapshot serves
a new machine's boot copy and SAVE-SYSTEM, so what a saved system starts
with is what it was, the heap's blocks included."""
import rcl
from rcl.forth import state
from rcl.forth.memory import DICT_LIMIT


def saved_and_started(m, tmp_path):
    path = str(tmp_path / "s.img")
    m.evaluate("SAVE-SYSTEM " + path)
    return rcl.open(image=path)


def test_a_block_allocated_before_save_system_is_still_allocated_after_image(tmp_path):
    # allocate, save, load, free, allocate: no overlap, data intact
    m = rcl.open()
    m.evaluate("VARIABLE P  VARIABLE Q  100 ALLOCATE DROP P !  P @ 100 ERASE  "
               "123 P @ !  4567 P @ 98 + !")
    n = saved_and_started(m, tmp_path)
    assert n.evaluate("P @ @ . P @ 98 + @ .") == "123 4567 "
    n.evaluate("50 ALLOCATE DROP Q !")
    p, q = n.evaluate("P @ U. Q @ U.").split()
    p, q = int(p), int(q)
    assert q + 50 <= p or q >= p + 100                # no overlap with the saved block
    n.evaluate("Q @ 50 255 FILL")
    assert n.evaluate("P @ @ . P @ 98 + @ .") == "123 4567 "   # the saved data intact
    assert n.evaluate("P @ FREE .") == "0 "           # FREE knows the saved block
    assert n.evaluate("Q @ FREE .") == "0 "
    assert n.evaluate("100 ALLOCATE . U.") == "0 %d " % p    # all free again: the top again


def test_the_heap_floor_comes_back_so_the_dictionary_stays_below_a_saved_block(tmp_path):
    m = rcl.open()
    m.evaluate("1000 ALLOCATE 2DROP")
    floor = m.heap_floor
    assert floor < DICT_LIMIT
    assert saved_and_started(m, tmp_path).heap_floor == floor


def test_replaces_text_is_kept_by_save_system(tmp_path):
    m = rcl.Forth()
    m.evaluate(': R  S" rcl" S" who" REPLACES ;  R')
    path = str(tmp_path / "r.img")
    m.evaluate("SAVE-SYSTEM " + path)
    from rcl.forth import image
    n = rcl.Forth()
    image.load(n, path)
    assert n.replacements == {b"WHO": b"rcl"}


def test_every_attribute_a_running_machine_has_is_declared_or_the_machines_own():
    # Word sets add no attribute as they run: what a fresh machine has after
    # RCL's load, a move, HELP, files and the tester is all a new one has.
    fresh = set(vars(rcl.Forth()))
    m = rcl.open()
    m.evaluate(': T  T{ 1 1 + -> 2 }T ;  T  100 ALLOCATE 2DROP  S" x" 2DROP '
               'S" a" S" b" REPLACES  RERB 2 INCHES FORWARD')
    grown = set(vars(m)) - fresh
    assert grown <= {"sim"}, grown                    # the host's view of a simulated board


def test_a_restored_machine_starts_its_session_state_fresh_and_keeps_the_system():
    m = rcl.Forth()
    m.evaluate('100 ALLOCATE 2DROP  S" a" S" b" REPLACES')
    snap = state.snapshot(m)
    m.sbuf, m.abort_message = 3, "old"
    n = rcl.Forth()
    state.restore(n, snap)
    assert (n.sbuf, n.abort_message, n.tracer) == (0, "", None)
    assert n.heap.plain() == m.heap.plain() and n.heap_floor == m.heap_floor
    assert n.replacements == m.replacements and n.xt_of == m.xt_of
    assert bytes(n.mem) == bytes(m.mem)
