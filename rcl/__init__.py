"""rcl: RCL, the Robotic Control Language of the 1986 R-E Robot, in Python.

`rcl.Forth()` is a bare F83 machine; see docs/API.md.
"""
__version__ = "0.1.0"

from rcl.errors import Bye, ForthError, RclError  # noqa: E402
from rcl.forth.machine import Forth  # noqa: E402

__all__ = ["Forth", "ForthError", "RclError", "Bye"]
