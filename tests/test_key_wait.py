"""KEY at a terminal (rcl/terminal.py read_tty_key): a key typed is read
unechoed, Enter as 13; a Ctrl-C ends the wait even when Python swallowed
its KeyboardInterrupt (raised inside a finalizer, "Exception ignored":
seen once as DBG's view waited, which then waited on for a key)."""
import os
import pty
import sys

import pytest

from rcl.terminal import read_tty_key


@pytest.fixture
def a_terminal(monkeypatch):
    master, slave = pty.openpty()
    stdin = os.fdopen(slave, "r")
    monkeypatch.setattr(sys, "stdin", stdin)
    yield master
    stdin.close()
    os.close(master)


def test_a_key_typed_is_read_and_enter_is_13(a_terminal):
    os.write(a_terminal, b"a")
    assert read_tty_key() == ord("a")
    os.write(a_terminal, b"\n")
    assert read_tty_key() == 13


def test_a_break_already_asked_for_ends_the_wait_with_no_key_typed(a_terminal):
    asked = []

    def interrupted():
        asked.append(1)
        return len(asked) >= 3                    # the break comes during the wait
    with pytest.raises(KeyboardInterrupt):
        read_tty_key(interrupted)
    assert len(asked) == 3
