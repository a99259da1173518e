"""Shared pytest fixtures: a fresh bare F83 machine for every test; pytest's
`pytester` (a real pytest run in a temporary directory) for the tests of
rcl's own pytest plugin."""
import gc
import os
import shutil
import signal
import tempfile
import time

import pytest
from _pytest.runner import runtestprotocol

import suite_size
from rcl.errors import ForthError
from rcl.hw.link import LinkLost
from starved import TIME_RAN_OUT, Starved

pytest_plugins = ["pytester"]
_cache = None

# Tests that run in real time (a pty, TCP, a firmware board, a browser):
# marked real_time, they run with the cyclic garbage collector off (below).
REAL_TIME = ("test_console_pty.py", "test_repl_pty.py", "test_ctrl_c_pty.py",
             "test_link.py", "test_link_late.py", "test_link_serve.py", "test_link_session.py",
             "test_firmware_", "test_sessions.py", "test_web_page.py", "conformance")


# Files that run a board program (the Uno image under simavr, the native
# firmware, rcl-board) run one after another on one worker. The Uno needs
# most of a core in real time, at a raised priority: two at once took
# both cores, and the kernel's own workers, which carry every pty's bytes,
# waited seconds for a turn. One Uno beside a native board, two CPU hogs
# and the other worker: both boards, heard over ptys, went silent for
# 250 ms and more, in 4 tests of 54 (docs/testing.md); one board at a time,
# none.
ONE_BOARD_AT_A_TIME = ("test_firmware_", "test_sessions.py", "conformance")


@pytest.hookimpl(tryfirst=True)
def pytest_collection_modifyitems(config, items):
    """Mark real-time tests; give each test its xdist group: its file (a
    file's module fixtures start once), or one group for the board files."""
    for item in items:
        if any(part in item.nodeid for part in REAL_TIME):
            item.add_marker(pytest.mark.real_time)
        board = any(part in item.nodeid for part in ONE_BOARD_AT_A_TIME)
        item.add_marker(pytest.mark.xdist_group("boards" if board else item.nodeid.split("::")[0]))


# rcl's own verdicts that time ran out: the board was not heard for 250 ms
# (Link lost: ForthError -292 while a word runs, LinkLost while rcl.open
# connects) or the host answered too late (Host too slow). In a real-time
# test they are the machine's doing when it starves the board or the host
# (docs/testing.md: a pty the kernel does not move, a process not run for
# 200 ms beside CPU hogs); such a test runs again, asserting the same, up
# to RUNS runs in all, and the summary names it; so does a test that found
# its own process was not run in time (starved.py). Any other failure, or
# a starved last run, stands.
RUNS = 3          # a PyPy host of the Uno beside two hogs was starved twice in a row


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    error = call.excinfo.value if call.excinfo is not None else None
    report.starved = (report.failed and call.when == "call"
                      and (isinstance(error, (Starved, LinkLost))
                           or isinstance(error, ForthError) and error.code in TIME_RAN_OUT))
    if report.starved:
        # the first run's error, and for a lost link its cause (silent, a frame gone)
        why = getattr(error, "why", None)
        told = "%s: %s" % (type(error).__name__, error)
        report.starved_why = told + (" (%s)" % why if why and why not in told else "")


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_protocol(item, nextitem):
    """A real-time test that failed starved (TIME_RAN_OUT) runs again, up to
    RUNS runs in all."""
    if item.get_closest_marker("real_time") is None:
        return None
    item.ihook.pytest_runtest_logstart(nodeid=item.nodeid, location=item.location)
    told = []                            # why each starved run starved
    for _ in range(RUNS):
        reports = runtestprotocol(item, nextitem=nextitem, log=False)
        starved = [r for r in reports if getattr(r, "starved", False)]
        if not starved:
            break
        told.append(starved[0].starved_why)
    if told:
        for r in reports:
            r.user_properties.append(("run again", " / ".join(told[:RUNS - 1])))
    for r in reports:
        item.ihook.pytest_runtest_logreport(report=r)
    item.ihook.pytest_runtest_logfinish(nodeid=item.nodeid, location=item.location)
    return True


def pytest_terminal_summary(terminalreporter):
    """Name every real-time test that ran again, and why."""
    again = {}
    for reports in terminalreporter.stats.values():
        for r in reports:
            for name, why in getattr(r, "user_properties", ()):
                if name == "run again" and getattr(r, "when", None) == "call":
                    again[r.nodeid] = (why, r.outcome)
    if again:
        terminalreporter.section("real-time tests run again (a run starved)")
        for nodeid, (why, outcome) in sorted(again.items()):
            terminalreporter.line("%s: %s; again: %s" % (nodeid, why, outcome))


def pytest_xdist_auto_num_workers(config):
    """-n auto (pyproject.toml): in CI two workers, as every busy-machine
    run of docs/testing.md was measured. By default a worker per core, and
    one more when the cores are free as the run starts: about half of a
    worker's time is spent waiting on real-time boards and pty children
    (on 2 idle cores, the same day: 4 min 24 s with two workers, 3 min
    34 s with three), but beside other work a third worker starved the
    real-time tests (2 failures beside two CPU hogs, none with two)."""
    if suite_size.FULL:
        return 2
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    cores = cores or 1
    idle = idle_cores(cores)
    return cores + 1 if idle is not None and idle > cores - 0.5 else max(cores, 2)


def idle_cores(cores, seconds=0.3):
    """How many of the cores were idle over the next `seconds` (Linux's
    /proc/stat), or None where that cannot be read."""
    def times():
        with open("/proc/stat") as f:
            fields = [int(x) for x in f.readline().split()[1:]]
        return fields[3] + fields[4], sum(fields)          # idle and iowait, all
    try:
        idle0, all0 = times()
        time.sleep(seconds)
        idle1, all1 = times()
    except (OSError, ValueError, IndexError):
        return None
    return cores * (idle1 - idle0) / max(1, all1 - all0)


@pytest.fixture(autouse=True)
def _no_collection_pauses_in_real_time(request):
    """A real-time test runs with the cyclic garbage collector off. The
    process holds the objects of thousands of tests before it, and one
    full collection of them took 250-470 ms here: longer than the board's
    250 ms watchdog, so a free-running board rightly stopped its motors
    (Host too slow) for a pause an rcl process of its own never has
    (docs/testing.md). Off for the test only; collected as usual after."""
    if request.node.get_closest_marker("real_time") is None or not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


def pytest_configure(config):
    """The suite keeps rcl.open()'s start-up copies in a folder of its own
    (children it starts inherit it), never in the user's cache folder."""
    global _cache
    # A run started in the background by a non-interactive shell (`pytest &`
    # in a script, some CI runners) inherits SIGINT ignored, and every rcl
    # it starts would too: the Ctrl-C tests would then see no Ctrl-C at all.
    if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)
    config.addinivalue_line("markers", "real_time: runs against the wall clock (conftest.py)")
    if "RCL_CACHE_DIR" not in os.environ:
        _cache = os.environ["RCL_CACHE_DIR"] = tempfile.mkdtemp(prefix="rcl-test-cache-")


def pytest_unconfigure(config):
    if _cache is not None:
        shutil.rmtree(_cache, ignore_errors=True)
        del os.environ["RCL_CACHE_DIR"]


@pytest.fixture
def forth():
    import rcl
    return rcl.Forth()
