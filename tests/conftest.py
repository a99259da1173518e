"""Shared pytest fixtures: a fresh bare F83 machine for every test; pytest's
`pytester` (a real pytest run in a temporary directory) for the tests of
rcl's own pytest plugin."""
import os
import shutil
import tempfile

import pytest

pytest_plugins = ["pytester"]
_cache = None


def pytest_configure(config):
    """The suite keeps rcl.open()'s start-up copies in a folder of its own
    (children it starts inherit it), never in the user's cache folder."""
    global _cache
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
