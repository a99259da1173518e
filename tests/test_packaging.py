"""Packaging: the top-level screens/ folder is built into the package as
rcl/screens (setup.py's build step), so that an installed rcl finds RCL
and the article's listings from any directory. The built tree is run
from a directory outside the checkout, as an installed package would be."""
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    pytest.importorskip("setuptools")
    lib = tmp_path_factory.mktemp("build") / "lib"
    done = subprocess.run([sys.executable, "setup.py", "-q", "build_py", "-d", str(lib)],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return lib


def run_built(lib, cwd, *args):
    env = dict(os.environ, PYTHONPATH=str(lib))
    return subprocess.run([sys.executable, *args], cwd=cwd, env=env, input="",
                          capture_output=True, text=True, timeout=120)


def test_the_build_puts_every_screen_and_listing_into_the_package(built):
    screens = sorted(os.listdir(os.path.join(ROOT, "screens", "examples")))
    assert sorted(os.listdir(built / "rcl" / "screens" / "examples")) == screens
    assert (built / "rcl" / "screens" / "rcl.fs").is_file()


def test_the_built_package_finds_its_screens_inside_itself(built, tmp_path):
    done = run_built(built, tmp_path, "-c", "import rcl; print(rcl.SCREENS)")
    assert done.stdout.strip() == str(built / "rcl" / "screens")


def test_the_built_package_includes_a_listing_from_any_directory(built, tmp_path):
    done = run_built(built, tmp_path, "-m", "rcl", "-e", "INCLUDE examples/listing1.fs .POSE")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("x ")
