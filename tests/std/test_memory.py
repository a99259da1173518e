"""Forth 2012 Memory-Allocation word set (chapter 14): ALLOCATE FREE
RESIZE on a heap inside the 64 KiB image, on the bare and full systems."""
import pytest

DICT_LIMIT = 0xCC00


def u(n):
    return n & 0xFFFF


def test_allocate_gives_ior_zero_and_memory_that_keeps_what_is_stored(sys_run):
    stack = sys_run("100 ALLOCATE SWAP VALUE A  12345 A !  -7 A 98 + !  A @ A 98 + @")
    assert stack == [0, 12345, -7]


def test_allocated_blocks_lie_inside_the_image_above_the_dictionary(sys_run):
    a, ior, b, ior2, here = sys_run("200 ALLOCATE 300 ALLOCATE HERE")
    assert ior == ior2 == 0
    for addr, size in ((u(a), 200), (u(b), 300)):
        assert u(here) < addr and addr + size <= DICT_LIMIT


def test_two_live_blocks_never_overlap(sys_run):
    a, _, b, _ = sys_run("10 ALLOCATE 10 ALLOCATE")
    assert abs(u(a) - u(b)) >= 10


def test_free_gives_ior_zero_for_a_block_and_nonzero_for_anything_else(sys_run):
    stack = sys_run("10 ALLOCATE DROP DUP FREE SWAP FREE  HERE FREE  0 FREE")
    assert stack[0] == 0 and all(ior != 0 for ior in stack[1:])


def test_freed_memory_can_be_allocated_again(sys_run):
    sys_run("UNUSED 1 RSHIFT ALLOCATE DROP FREE")
    assert sys_run("UNUSED 1 RSHIFT ALLOCATE NIP")[-1] == 0


def test_resize_keeps_the_contents_when_the_block_grows(sys_run):
    stack = sys_run("4 ALLOCATE DROP  1111 OVER !  2222 OVER 2+ !  1000 RESIZE "
                    "SWAP DUP @ SWAP 2+ @")
    assert stack == [0, 1111, 2222]


def test_resize_keeps_the_contents_when_the_block_shrinks(sys_run):
    assert sys_run("100 ALLOCATE DROP 4321 OVER ! 2 RESIZE SWAP @") == [0, 4321]


def test_allocate_gives_ior_minus_59_when_the_heap_is_exhausted(sys_run):
    assert sys_run("60000 ALLOCATE NIP")[-1] == -59


def test_a_failed_resize_leaves_the_block_where_it_was_with_its_contents(sys_run):
    stack = sys_run("8 ALLOCATE DROP VALUE A  777 A !  A 60000 RESIZE  A @")
    a = sys_run("A")[-1]
    assert stack[-3:] == [a, -61, 777]


def test_resize_of_an_address_that_is_no_block_gives_a_nonzero_ior(sys_run):
    stack = sys_run("HERE 10 RESIZE")
    assert stack[-1] != 0 and stack[-2] == sys_run("HERE")[-1]


def test_the_heap_takes_its_room_from_the_dictionary_and_gives_it_back(sys_run):
    before, after, freed = map(u, sys_run("UNUSED  10000 ALLOCATE DROP UNUSED SWAP FREE DROP "
                                          "UNUSED"))
    assert before - after >= 10000 and freed == before


def test_the_dictionary_stops_below_the_heap_without_touching_it(system, forth_error):
    system.evaluate("20000 ALLOCATE DROP VALUE A  4242 A !")
    with pytest.raises(forth_error) as e:
        system.evaluate("UNUSED 10 + ALLOT")
    assert e.value.code == -8
    assert system.evaluate("A @ .") == "4242 "


def test_an_exhausted_heap_leaves_the_system_working(sys_run):
    sys_run("60000 ALLOCATE 2DROP")
    assert sys_run(": SQ DUP * ; 9 SQ")[-1] == 81
