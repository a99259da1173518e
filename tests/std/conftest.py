"""Fixtures for the Forth 2012 standard-conformance tests.

`rcl` is imported inside the fixture so that the tests collect even while
the VM is still being written.
"""
import pytest


def results(forth, text):
    """Evaluate `text` on `forth` and return the data stack (bottom first)."""
    forth.evaluate(text)
    return list(forth.stack)


@pytest.fixture
def forth():
    import rcl

    return rcl.Forth()


@pytest.fixture
def run(forth):
    """`results` bound to this test's machine: run("1 2 +") -> [3]."""
    return lambda text: results(forth, text)


@pytest.fixture
def out(forth):
    """What evaluating `text` prints: out("5 .") -> "5 "."""
    return forth.evaluate


@pytest.fixture
def forth_error():
    """The rcl.ForthError class, for pytest.raises."""
    import rcl

    return rcl.ForthError


@pytest.fixture(params=["bare", "full"])
def system(request):
    """Each optional word set is tested on both: a bare machine (rcl --bare)
    and the full system, RCL loaded on the simulated board (rcl.open())."""
    import rcl

    return rcl.Forth() if request.param == "bare" else rcl.open()


@pytest.fixture
def sys_run(system):
    """`results` on `system`: sys_run("1 2 +") -> [3]."""
    return lambda text: results(system, text)
