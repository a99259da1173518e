"""Real-time pace: the virtual clock waits for the wall clock.

By default the simulation runs as fast as the host allows. A Pacer, set
as `board.pacer`, holds each tick back until the wall clock has caught up
with it, and records how late each tick was (wall time past its moment):
the last minute of ticks one by one, the whole run as a count and a worst
case, so a run of any length keeps its memory bounded.
"""
import collections
import time

from rcl.board import CLOCK_HZ

RECENT = 6000                     # ticks kept one by one: a minute of 10 ms ticks
LATE = 0.002                      # seconds: a tick this late counts as late


class Pacer:
    def __init__(self, machine_clock, wall=time.monotonic, sleep=time.sleep):
        self.wall, self.sleep = wall, sleep
        self.start_wall = wall()
        self.start_clock = machine_clock
        self.lateness = collections.deque(maxlen=RECENT)   # seconds, 0 when on time
        self.ticks = 0
        self.late = 0                 # ticks more than LATE behind
        self.worst = 0.0

    def wait(self, clock):
        due = self.start_wall + (clock - self.start_clock) / CLOCK_HZ
        ahead = due - self.wall()
        if ahead > 0:
            self.sleep(ahead)
        behind = max(0.0, -ahead)
        self.lateness.append(behind)
        self.ticks += 1
        self.late += behind > LATE
        self.worst = max(self.worst, behind)
