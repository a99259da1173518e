"""rcl: RCL, the Robotic Control Language of the 1986 R-E Robot, in Python.

`rcl.Forth()` is a bare F83 machine; see docs/API.md.
"""
from rcl.errors import Bye, ForthError, RclError
from rcl.forth.machine import Forth

__all__ = ["Forth", "ForthError", "RclError", "Bye"]
