"""Shared pytest fixtures: a fresh bare F83 machine for every test; pytest's
`pytester` (a real pytest run in a temporary directory) for the tests of
rcl's own pytest plugin."""
import pytest

pytest_plugins = ["pytester"]


@pytest.fixture
def forth():
    import rcl
    return rcl.Forth()
