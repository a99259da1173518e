"""The link's parts on their own, in the protocol's own numbers: the tick
replay (rcl/hw/tickreplay.py: what the host runs per TICK and the
TICK_DONE frames it sends), board frames taken in order (inorder.py) and
the judge of a silent board (liveness.py), driven by a clock the test sets."""
import time

from rcl.hw import protocol as P
from rcl.hw.inorder import GIVE_UP, InOrder
from rcl.hw.liveness import STALL, Liveness
from rcl.hw.tickreplay import HOST_LATE, LATE_WINDOW, TickReplay

# A tick script as RCL registers one: latch a counter (OUT), read two bytes
SCRIPT = [(P.SCRIPT_OUT, 0x83, 0x40), (P.SCRIPT_IN, 0x80, 0), (P.SCRIPT_IN, 0x81, 0)]
PERIOD = 10_000


def tick(number, results, arrived=None):
    (f,) = P.FrameReader().feed(P.frame(3, "TICK", tick=number, off=0x1234,
                                        results=[(r,) for r in results]))
    f.arrived = time.monotonic() if arrived is None else arrived
    return f


def replay():
    r = TickReplay(SCRIPT)
    r.period = PERIOD
    return r


# ------------------------------------------------------------ the replay
def test_the_handlers_script_is_served_from_the_tick_and_the_rest_goes_to_the_board():
    r = replay()
    r.begin(tick(7, [0x12, 0x34]))
    assert r.active and r.number == 7
    r.out8(0x83, 0x40)                         # the board latched at the tick
    assert r.in8(0x80) == 0x12 and r.in8(0x81) == 0x34
    r.out8(0x88, 0x0F)                         # off the script: queued
    assert r.in8(0x80) is None                 # ... and a read now is the board's
    assert r.done_frames(final=True, us=25) == [
        {"tick": 7, "final": 1, "us": 25, "writes": [(0x88, 0x0F)]}]
    assert r.writes == []


def test_a_write_that_differs_from_the_script_leaves_it_for_the_rest_of_the_tick():
    r = replay()
    r.begin(tick(8, [1, 2]))
    r.out8(0x83, 0x41)                          # not the script's 0x40
    assert r.in8(0x80) is None and r.taken == 0
    assert r.done_frames(final=False, us=0)[0]["writes"] == [(0x83, 0x41)]


def test_tick_done_carries_19_writes_a_frame_the_most_its_payload_holds_and_only_the_last_is_final():
    r = replay()
    r.begin(tick(9, [0, 0]))
    for i in range(45):
        r.out8(0x84, i)
    frames = r.done_frames(final=True, us=3)
    assert [len(f["writes"]) for f in frames] == [19, 19, 7]
    assert [f["final"] for f in frames] == [0, 0, 1]
    assert [w for f in frames for w in f["writes"]] == [(0x84, i) for i in range(45)]
    # payloads of 5 + 19 x 3 = 62 bytes (a 20th write would make 65, over 64) and 5 + 7 x 3
    assert [len(P.frame(1, "TICK_DONE", **f)) for f in frames] == [6 + 62, 6 + 62, 6 + 26]
    assert r.done_frames(final=True, us=3) == [{"tick": 9, "final": 1, "us": 3, "writes": []}]


def test_tick_numbers_are_a_period_apart_and_wrap_at_2_to_the_16():
    r = replay()
    assert r.next_tick() == 0xFFFF                  # not known yet
    assert r.board_time(65534, 1000) == 1000        # the first tick seen: the host's now
    assert r.board_time(65535, 0) == 1000 + PERIOD
    assert r.board_time(2, 0) == 1000 + 4 * PERIOD  # 65535 -> 0 -> 1 -> 2
    assert r.next_tick() == 3 and r.next_due() == 1000 + 5 * PERIOD
    r.new_session()
    assert r.next_tick() == 0xFFFF and r.script == SCRIPT


def test_a_late_answer_to_a_free_running_board_is_kept_for_100_ticks():
    r = replay()
    late = tick(40, [0, 0], arrived=time.monotonic() - HOST_LATE - 0.05)
    r.begin(late)
    r.end(late, lockstep=False)
    assert r.late_answer[1] == 40 and r.late_answer[0] > HOST_LATE
    for n in range(LATE_WINDOW):
        on_time = tick(41 + n, [0, 0])
        r.begin(on_time)
        r.end(on_time, lockstep=False)
    assert r.take_late()[1] == 40                   # 100 ticks on: still the cause
    assert r.take_late() is None                    # told once


def test_a_late_answer_to_a_lockstep_board_is_no_lateness():
    r = replay()
    late = tick(40, [0, 0], arrived=time.monotonic() - 1.0)
    r.begin(late)
    r.end(late, lockstep=True)
    assert r.take_late() is None


# ------------------------------------------------------ frames in order
def ack(seq):
    (f,) = P.FrameReader().feed(P.frame(seq, "ACK", ack=seq))
    return f


def test_until_identify_no_frame_is_taken():
    frames = InOrder()
    assert frames.take(ack(1), 0.0, 0.0) == ([], None)
    frames.restart()
    ready, nak = frames.take(ack(1), 0.0, 0.0)
    assert [f.seq for f in ready] == [1] and nak is None and frames.expected == 2


def test_a_frame_ahead_is_held_the_missing_one_asked_for_once_per_10_ms_then_all_taken_in_order():
    frames = InOrder()
    frames.restart()
    assert frames.take(ack(3), 0.0, 5.000) == ([], 1)           # 1 and 2 missing: NAK 1
    assert frames.take(ack(4), 0.0, 5.005) == ([], None)        # not again within 10 ms
    assert frames.take(ack(5), 0.0, 5.020) == ([], 1)
    ready, _ = frames.take(ack(1), 0.0, 5.030)
    assert [f.seq for f in ready] == [1]
    ready, _ = frames.take(ack(2), 0.0, 5.031)
    assert [f.seq for f in ready] == [2, 3, 4, 5] and frames.expected == 6 and not frames.held
    assert frames.take(ack(4), 0.0, 5.032) == ([], None)        # behind: already done


def test_board_sequence_numbers_wrap_from_255_to_0():
    frames = InOrder()
    frames.restart()
    frames.expected = 255
    ready, _ = frames.take(ack(255), 0.0, 0.0)
    ready2, _ = frames.take(ack(0), 0.0, 0.0)
    assert [f.seq for f in ready + ready2] == [255, 0] and frames.expected == 1


def test_a_gap_held_for_a_second_of_link_time_is_a_frame_gone():
    frames = InOrder()
    frames.restart()
    frames.take(ack(2), 10.0, 0.0)
    assert not frames.gone(10.0 + GIVE_UP)
    assert frames.gone(10.0 + GIVE_UP + 0.01)
    frames.take(ack(1), 11.5, 0.0)                              # it came after all
    assert not frames.gone(20.0)


# ------------------------------------------------------------- liveness
class Wall:
    """The wall clock, set by the test."""

    def __init__(self):
        self.now = 100.0

    def __call__(self):
        return self.now


def reads(live, wall, until, every=0.010, heard=False):
    """The reader's reads, every `every` s of wall time up to `until`."""
    while wall.now + every <= until + 1e-9:
        wall.now += every
        live.look()
        if heard:
            live.heard()


def test_250_ms_without_a_frame_at_the_reads_is_a_silent_board():
    wall = Wall()
    live = Liveness(wall=wall)
    reads(live, wall, 100.5, heard=True)
    assert not live.silent(P.LOST_MS / 1000)
    reads(live, wall, 100.74)
    assert not live.silent(P.LOST_MS / 1000)         # 240 ms
    reads(live, wall, 100.77)
    assert live.silent(P.LOST_MS / 1000)             # 270 ms


def test_a_read_that_came_back_late_is_this_process_stalled_not_the_board_silent():
    wall = Wall()
    live = Liveness(wall=wall)
    reads(live, wall, 100.1, heard=True)
    wall.now += 0.400                                # the process was not run
    live.look()                                      # ... the board's frames wait
    assert not live.silent(P.LOST_MS / 1000)
    assert abs(live.away - (0.400 - STALL)) < 1e-9   # all but STALL of it not counted
    live.heard()                                     # they are read
    reads(live, wall, wall.now + 0.24)
    assert not live.silent(P.LOST_MS / 1000)
    reads(live, wall, wall.now + 0.02)
    assert live.silent(P.LOST_MS / 1000)             # the board's own silence still counts


def test_a_board_in_this_process_is_judged_by_its_own_time():
    wall, board = Wall(), [0.0]
    live = Liveness(board_seconds=lambda: board[0], wall=wall)
    live.heard()
    wall.now += 5.0                                  # a busy machine: the board did not run
    live.look()
    assert not live.silent(P.LOST_MS / 1000)
    board[0] = 0.3                                   # its time went on, no frame came
    live.look()
    assert live.silent(P.LOST_MS / 1000)


def test_nothing_is_judged_between_reads():
    # whoever asks, the answer is as of the last read: a stall after it
    # (before its frames are read) changes nothing
    wall = Wall()
    live = Liveness(wall=wall)
    live.look()
    live.heard()
    wall.now += 10.0
    assert not live.silent(P.LOST_MS / 1000) and live.at == live.last_heard
