"""Shared pytest fixtures: a fresh bare F83 machine for every test."""
import pytest


@pytest.fixture
def forth():
    import rcl
    return rcl.Forth()
