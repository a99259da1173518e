"""Is the board still there? The host's judge of a silent board (250 ms,
docs/protocol.md section 6) and of an unanswered request (1 s, section 3).

Silence is measured in *link time*, and only at the moments the reader
thread has just read everything waiting on the port:

    reader:  read() returns ---- look(now) ---- frames dispatched: heard(at)
                                   |                   |
                                   at = link time      silent(at)?  (the same instant)

- link time is the board's own clock where the port can tell it
  (rclsim://, a board in this process: `port.board_seconds`), else the
  wall clock less this process's own stalls. A read waits 10 ms at most,
  so a read that comes back much later (beyond STALL) means the machine
  kept this process waiting, most likely the board too: a silence of ours
  is not the board's.
- a silence is judged at the instant of a read, never later: a thread
  stalled after its read, while frames wait on the port unread, would
  otherwise take the stall for the board's silence. So every deadline
  (silence, a request's give-up, a board frame held for) is compared with
  `at`, the last read's link time, whatever thread asks.
"""
import time

STALL = 0.030        # s: a longer gap between the reader's reads is this process's stall


class Liveness:
    def __init__(self, board_seconds=None, wall=time.monotonic):
        self.board_seconds, self.wall = board_seconds, wall
        self.away = 0.0              # s of this process's own stalls, not counted
        self.looked_at = wall()      # wall time of the last read
        self.at = self.link_time(self.looked_at)
        self.last_heard = self.at

    def link_time(self, wall_now):
        if self.board_seconds is not None:
            return self.board_seconds()
        return wall_now - self.away

    def look(self, wall_now=None):
        """The reader's read came back (at wall_now): the stall since the
        last one, if any, is not counted; -> `at`, link time now."""
        wall_now = self.wall() if wall_now is None else wall_now
        gap = wall_now - self.looked_at
        if gap > STALL:
            self.away += gap - STALL
        self.looked_at = wall_now
        self.at = self.link_time(wall_now)
        return self.at

    def heard(self):
        """A good frame from the board, read at the last look."""
        self.last_heard = self.at

    def silent(self, limit):
        """Nothing from the board for `limit` seconds of link time, as of
        the last look."""
        return self.at - self.last_heard > limit

    def host_time(self):
        """Wall time less this process's stalls, as of the last look (a
        deadline that must pass even where the board's clock stands still,
        such as a HELLO's wait)."""
        return self.looked_at - self.away
