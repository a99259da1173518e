"""Build hook: the RCL screens live in the top-level screens/ folder (the
layout DESIGN.md gives the project) and are installed into the package as
rcl/screens, where `rcl.SCREENS` finds them. Everything else is in
pyproject.toml."""
import pathlib
import shutil

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = pathlib.Path(__file__).parent


class build_py_with_screens(build_py):
    """build_py, then screens/**/*.fs copied to <build>/rcl/screens."""

    def run(self):
        super().run()
        target = pathlib.Path(self.build_lib) / "rcl" / "screens"
        for source in sorted((ROOT / "screens").rglob("*.fs")):
            dest = target / source.relative_to(ROOT / "screens")
            dest.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(source, dest)

    def get_outputs(self, include_bytecode=True):
        # Listed so that wheel and install record the copied screens.
        target = pathlib.Path(self.build_lib) / "rcl" / "screens"
        extra = [str(target / s.relative_to(ROOT / "screens"))
                 for s in sorted((ROOT / "screens").rglob("*.fs"))]
        return super().get_outputs(include_bytecode) + extra


setup(cmdclass={"build_py": build_py_with_screens})
