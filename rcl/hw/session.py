"""The host's side of one link as a state machine (docs/link.md, "The
session"): the state a LinkBoard is in, the moves between states that the
protocol allows, why a link was lost, and the one request in flight.

    CLOSED --open_port()--> OPENING --HELLO sent--> HELLO_SENT --IDENTIFY--> IDENTIFIED
      ^ ^                      |                     |    ^                    |
      | '----(open failed)-----'     no IDENTIFY,    |    |       SNAPSHOT     |
      |                              refused, other  |    |       answered     v
      |                              version, port   |    '---RECONNECT---- RUNNING
      |                              failed          v       (port kept)       |  |
      |<--------------------------------close()--- LOST <----------------------'  |
      |                                             ^ |  silent 250 ms, no answer |
      |                                             | |  1 s, port failed, board  |
      |                                             | |  frame not sent again     |
      |                                             | '--RECONNECT (port kept)--> HELLO_SENT
      |<---- LEAVING <---close(): SAFE, timer 0 stopped----------------------------'
               '--(the port fails meanwhile)--> LOST

(IDENTIFIED -> LOST too: the script's SNAPSHOT unanswered.) Every other
move is a bug and raises IllegalTransition. The reader thread and the
Forth machine's thread both move the state, so a move is made under a
lock, and `leave(from_states, to)` tests and moves in one step.
"""
import collections
import enum
import threading
from dataclasses import dataclass
from typing import Optional


class State(enum.Enum):
    CLOSED = "closed"            # no port open
    OPENING = "opening"          # the port being opened
    HELLO_SENT = "hello sent"    # HELLO repeated until IDENTIFY; frames of a last session ignored
    IDENTIFIED = "identified"    # IDENTIFY of our version came; the tick script being registered
    RUNNING = "up"               # requests, ticks, TICK_DONE
    LOST = "lost"                # the board cannot be asked; RECONNECT or the next command
    LEAVING = "leaving"          # rcl leaves: SAFE, timer 0 stopped, then the port closed


S = State
TRANSITIONS = {
    S.CLOSED: {S.OPENING},
    S.OPENING: {S.HELLO_SENT, S.CLOSED},
    S.HELLO_SENT: {S.IDENTIFIED, S.LOST},
    S.IDENTIFIED: {S.RUNNING, S.LOST},
    S.RUNNING: {S.LOST, S.LEAVING, S.HELLO_SENT},
    S.LOST: {S.HELLO_SENT, S.CLOSED},
    S.LEAVING: {S.CLOSED, S.LOST},
}
# States in which the board hears requests (a frame may be sent and waited for)
ASKING = frozenset({S.IDENTIFIED, S.RUNNING, S.LEAVING})


class IllegalTransition(RuntimeError):
    """A move the state machine does not have: a bug in rcl, not the user's."""


class Session:
    """The state of one LinkBoard's link, moved only along TRANSITIONS."""

    def __init__(self):
        self.state = S.CLOSED
        self.lock = threading.Lock()
        self.history = collections.deque(maxlen=64)   # (from, to) of the last moves

    def go(self, to):
        with self.lock:
            self._move(to)

    def leave(self, from_states, to, first=None):
        """Move to `to` if the state is one of from_states; -> whether it
        moved. first(), if given, runs just before the move, under the lock:
        what another thread must find done once it sees the new state."""
        with self.lock:
            if self.state not in from_states:
                return False
            if first is not None:
                first()
            self._move(to)
            return True

    def _move(self, to):
        if to not in TRANSITIONS[self.state]:
            raise IllegalTransition("link session: %s -> %s" % (self.state.name, to.name))
        self.history.append((self.state, to))
        self.state = to

    @property
    def asking(self):
        return self.state in ASKING


class Cause(enum.Enum):
    """Why a link was lost (Loss.cause)."""
    PORT = "port"                    # the port failed: a closed connection, a pty hung up
    SILENT = "silent"                # nothing valid from the board for LOST_MS
    NO_ANSWER = "no answer"          # a request unanswered for REQUEST_GIVE_UP
    FRAME_GONE = "frame gone"        # a board frame held back for, never sent again
    NO_SESSION = "no session"        # HELLO unanswered or refused when connecting again


@dataclass(frozen=True)
class Loss:
    """A lost link: its cause and what to tell the user."""
    cause: Cause
    detail: str

    def __str__(self):
        return self.detail


@dataclass
class Request:
    """The one sequenced host frame in flight (stop and wait, section 3)."""
    seq: int
    name: str
    data: bytes                  # the frame, as resent
    posted: float                # wall time it was first sent
    sent_at: float               # wall time of the last send: resent RETRY_MS after it
    give_up: float               # link time (liveness.py) after which the link is lost
    retries: int = 0
    waited: float = 0.0          # wall time spent waiting for it (at the prompt, none)
    reply: Optional[object] = None   # the answer frame, once it came
