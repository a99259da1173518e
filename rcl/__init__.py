"""rcl: RCL, the Robotic Control Language of the 1986 R-E Robot, in Python.

`rcl.Forth()` is a bare F83 machine; see docs/API.md.
"""
import os

__version__ = "0.1.0"

from rcl.errors import Bye, ForthError, RclError  # noqa: E402
from rcl.forth.machine import Forth  # noqa: E402

__all__ = ["Forth", "ForthError", "RclError", "Bye", "open"]


def _screens_folder():
    """The RCL screens: rcl/screens once installed (setup.py copies the
    top-level screens/ there), else screens/ beside the package in a
    source checkout or an editable install."""
    here = os.path.dirname(os.path.abspath(__file__))
    installed = os.path.join(here, "screens")
    if os.path.isdir(installed):
        return installed
    return os.path.join(os.path.dirname(here), "screens")


SCREENS = _screens_folder()


def open(realtime=False, write=None, screens=True):  # noqa: A001  (DESIGN.md's name)
    """A running system: a machine wired to a simulated board with RCL
    loaded and INSTALL run (screens=False: the board alone; a folder: RCL
    from that folder's rcl.fs instead of the installed one), with `.sim`
    (rcl.sim.observe.Sim) to observe the robot and inject faults. With
    realtime=True the virtual clock keeps pace with the wall clock."""
    from rcl.sim.board import SimBoard
    from rcl.sim.observe import Sim
    from rcl.sim.pace import Pacer
    board = SimBoard()
    m = Forth(write=write, board=board)
    m.sim = Sim(board)
    m.screens_dir = screens if isinstance(screens, str) else SCREENS
    if screens:
        m.include(os.path.join(m.screens_dir, "rcl.fs"))
    m.documented_end = m.dictionary.here      # HELP: later words are the user's
    if realtime:
        board.pacer = Pacer(m.clock)
    return m
