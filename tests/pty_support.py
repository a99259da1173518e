"""Support for the tests that run rcl on a pty (pexpect)."""
import signal

import pexpect


def close(child):
    """End a child at a test's end. pexpect gives a child 0.1 s after each
    signal and raises if it still runs after SIGKILL; a busy machine can
    take longer than that to end it, so wait for it then."""
    try:
        child.close(force=True)
    except pexpect.ExceptionPexpect:
        if child.isalive():
            child.kill(signal.SIGKILL)
        child.wait()
