"""Board frames taken in sequence order (docs/protocol.md section 3,
"Board to host: selective repeat"): the host's side, apart from any port.

    frame SEQ = expected      -> taken, with every held frame that follows it
    frame ahead of expected   -> held; NAK expected, at most once per RETRY_MS
    frame behind expected     -> already done: dropped
    a gap held for GIVE_UP    -> the board no longer keeps the missing frame

Until IDENTIFY the frames on the line are the last session's (a board
still ticking when HELLO went out), and none is taken.
"""
from rcl.hw import protocol as P

GIVE_UP = 1.0            # s of link time a missing board frame is waited for (section 3)


class InOrder:
    def __init__(self):
        self.restart()
        self.before_identify = True      # a new connection: nothing taken before IDENTIFY

    def restart(self):
        """IDENTIFY: the board numbers its frames from 1 again."""
        self.expected, self.held = 1, {}
        self.gap_since = 0.0         # link time the oldest gap opened
        self.last_nak = 0.0          # wall time of the last NAK
        self.before_identify = False

    def take(self, f, at, now):
        """A sequenced board frame read at link time `at`, wall time `now`;
        -> (the frames now in order, the SEQ to NAK or None)."""
        if self.before_identify:
            return [], None
        d = P.newer(f.seq, self.expected)
        if d > 0:
            if not self.held:
                self.gap_since = at              # a frame is missing from here
            self.held[f.seq] = f
            if now - self.last_nak > P.RETRY_MS / 1000:
                self.last_nak = now
                return [], self.expected
            return [], None
        if d < 0:
            return [], None
        ready = []
        while f is not None:
            self.expected = (self.expected + 1) & 0xFF
            ready.append(f)
            f = self.held.pop(self.expected, None)
        self.last_nak = 0.0
        self.gap_since = at                      # (another gap's time starts now)
        return ready, None

    def gone(self, at):
        """The missing frame has not come GIVE_UP after the gap opened."""
        return bool(self.held) and at - self.gap_since > GIVE_UP
