"""The idle ticks MS counts out in arithmetic (rcl.sim.board.count_out)
are exactly those of the loop that runs primitive by primitive, also when
whole runs of them are taken at once, a step budget cutting in or not."""
import math

from hypothesis import given, settings
from hypothesis import strategies as st

from rcl.sim.board import count_out
from suite_size import scaled

C = 1_000_000                                    # one primitive, clock units


def one_by_one(clock, n, c, d, period, cost, limit):
    """The reference: each tick found primitive by primitive."""
    ticks, last = 0, None
    while n > 0:
        k = max(0, -(-(d - clock) // c))
        if k >= n:
            return clock + n * c, 0, ticks, last
        if clock + k * c + cost >= limit:
            break
        clock += k * c + cost
        n -= k
        ticks, last, d = ticks + 1, d, d + period
    return clock, n, ticks, last


@settings(max_examples=scaled(2000, 500), deadline=None, derandomize=True, database=None)
@given(clock=st.integers(0, 10**12), n=st.integers(1, 5_000), c=st.integers(1, 3 * C),
       ahead=st.integers(-5 * C, 400 * C), period=st.integers(C // 2, 400 * C),
       cost=st.integers(0, 400 * C), budget=st.one_of(st.none(), st.integers(0, 10**11)))
def test_idle_ticks_counted_at_once_are_those_counted_one_by_one(clock, n, c, ahead, period,
                                                                  cost, budget):
    cost = cost % period                         # a handler shorter than the tick
    limit = math.inf if budget is None else clock + budget
    args = (clock, n, c, clock + ahead, period, cost, limit)
    assert count_out(*args) == one_by_one(*args)


def test_an_hour_of_ms_at_rcls_tick_and_cost_counts_360_000_ticks_as_the_loop_does():
    # 10.0005 ms ticks, a 0.3 ms handler, 27.8 us primitives: 3,600 s of MS
    args = (5 * C, 1 + 37 * 3_600_000, 1_000_000, 7 * C, 360_018_000, 10_800_000, math.inf)
    assert count_out(*args) == one_by_one(*args)
    assert count_out(*args)[2] > 300_000
