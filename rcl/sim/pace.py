"""Real-time pace: the virtual clock waits for the wall clock.

By default the simulation runs as fast as the host allows. A Pacer, set
as `board.pacer`, holds each tick back until the wall clock has caught up
with it, and records how late each tick was (wall time past its moment).
"""
import time

from rcl.board import CLOCK_HZ


class Pacer:
    def __init__(self, machine_clock, wall=time.monotonic, sleep=time.sleep):
        self.wall, self.sleep = wall, sleep
        self.start_wall = wall()
        self.start_clock = machine_clock
        self.lateness = []            # seconds, one per tick (0 when on time)

    def wait(self, clock):
        due = self.start_wall + (clock - self.start_clock) / CLOCK_HZ
        ahead = due - self.wall()
        if ahead > 0:
            self.sleep(ahead)
            self.lateness.append(0.0)
        else:
            self.lateness.append(-ahead)

    @property
    def worst(self):
        return max(self.lateness, default=0.0)
