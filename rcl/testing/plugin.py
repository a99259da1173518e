"""rcl's pytest plugin (the `pytest11` entry point `rcl`): pytest loads it
by itself wherever rcl is installed; it adds only names that start with
rcl, and test_*.fs files (turn that off with `rcl_test_files =` empty).

Fixtures, fresh for each test:
    rcl_robot   rcl.open(): the simulated robot, RCL loaded, moves kept
    rcl_forth   rcl.Forth(): a bare F83 machine
Settings (pytest.ini [pytest], or pyproject.toml [tool.pytest.ini_options]):
    rcl_load        files loaded into every robot first (relative to rootdir)
    rcl_load_bare   files loaded into every bare machine first
    rcl_test_files  name patterns of Forth test files (default test_*.fs)
Marker:
    @pytest.mark.rcl_load("box.fs")   more files for this test's machines,
                                      relative to the test file
"""
import fnmatch

import pytest


def pytest_addoption(parser):
    parser.addini("rcl_load", "files loaded into every rcl robot first (rcl_robot, "
                  "test_*.fs)", type="linelist", default=[])
    parser.addini("rcl_load_bare", "files loaded into every bare rcl machine first "
                  "(rcl_forth, test_*.fs with `\\ rcl: bare`)", type="linelist", default=[])
    parser.addini("rcl_test_files", "name patterns of Forth test files pytest collects",
                  type="args", default=["test_*.fs"])


def pytest_configure(config):
    config.addinivalue_line("markers", "rcl_load(*files): load these files (relative to "
                            "the test file) into this test's rcl machines")


def pytest_collect_file(file_path, parent):
    patterns = parent.config.getini("rcl_test_files")
    if file_path.suffix == ".fs" and any(fnmatch.fnmatch(file_path.name, p) for p in patterns):
        from rcl.testing.forthfile import ForthFile
        return ForthFile.from_parent(parent, path=file_path)
    return None


def configured(config, mode):
    """The files the settings load into a machine of this mode, as paths."""
    names = config.getini("rcl_load" if mode == "robot" else "rcl_load_bare")
    return [config.rootpath / name for name in names]


def machine(config, mode, more=()):
    """A fresh robot or bare machine with the configured files, then `more`,
    loaded. A file that fails to load raises rcl.ForthError (file:line)."""
    from rcl import testing
    files = configured(config, mode) + list(more)
    return testing.robot(files) if mode == "robot" else testing.bare(files)


def fixture_machine(request, mode):
    from rcl.errors import ForthError
    more = [request.path.parent / name
            for mark in request.node.iter_markers("rcl_load") for name in mark.args]
    try:
        return machine(request.config, mode, more)
    except ForthError as e:
        pytest.fail("rcl could not load the test's files: %s" % e, pytrace=False)


@pytest.fixture
def rcl_robot(request):
    """A fresh simulated robot (rcl.open()) with the configured files loaded;
    its board keeps the last moves for the rcl.testing assertions."""
    return fixture_machine(request, "robot")


@pytest.fixture
def rcl_forth(request):
    """A fresh bare machine (rcl.Forth()) with the configured files loaded."""
    return fixture_machine(request, "bare")
