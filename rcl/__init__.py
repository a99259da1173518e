"""rcl: RCL, the Robotic Control Language of the 1986 R-E Robot, in Python.

`rcl.Forth()` is a bare F83 machine; see docs/API.md.
"""
import os

__version__ = "0.1.0"

from rcl.errors import Bye, ForthError, RclError  # noqa: E402

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


def __getattr__(name):
    """rcl.Forth, imported when first asked for: `import rcl` stays light,
    so the command line can take Ctrl-C while the machine loads (cli.py)."""
    if name == "Forth":
        from rcl.forth.machine import Forth
        return Forth
    raise AttributeError("module 'rcl' has no attribute %r" % name)


def open(realtime=False, write=None, screens=True, image=None,  # noqa: A001  (DESIGN.md's name)
         board=None, port=None, usb=None):
    """A running system: a machine wired to a simulated board with RCL
    loaded and INSTALL run (screens=False: the board alone; a folder: RCL
    from that folder's rcl.fs instead of the installed one), with `.sim`
    (rcl.sim.observe.Sim) to observe the robot and inject faults. With
    realtime=True the virtual clock keeps pace with the wall clock.
    image="file": the system SAVE-SYSTEM wrote instead of the screens, its
    interrupt handler installed again (rcl.forth.image.ImageError if the
    file is refused). `board` is a fresh SimBoard (or subclass) to use
    instead of a new one.
    port="URL" (any pyserial URL or device) or usb="VID:PID": RCL on a
    board over the link instead (rcl.hw; rcl.hw.protocol.LinkError if it
    cannot connect); `.sim` only when the board is rclsim://'s simulation."""
    if port is not None or usb is not None:
        return open_link(port, usb, write, screens, image)
    from rcl.forth.machine import Forth
    from rcl.sim.board import SimBoard
    from rcl.sim.observe import Sim
    from rcl.sim.pace import Pacer
    if board is None and image is None and screens:     # the same every time: kept
        from rcl import startcache

        def load():
            fresh = Forth(board=SimBoard())
            fresh.sim = Sim(fresh.board)
            load_rcl(fresh, screens, None)
            return fresh
        folder = screens if isinstance(screens, str) else SCREENS
        m = startcache.open_loaded(folder, write, load)
        m.sim = Sim(m.board)              # a copy's session, as load_rcl leaves one
        m.screens_dir, m.documented_end = folder, m.dictionary.here
    else:
        board = board if board is not None else SimBoard()
        m = Forth(write=write, board=board)
        m.sim = Sim(board)
        load_rcl(m, screens, image)
    if realtime:
        m.board.pacer = Pacer(m.clock)
    return m


def load_rcl(m, screens, image):
    """RCL onto m's board: from a saved image, the screens (the installed
    ones, or screens="folder"), or nothing (screens=False)."""
    m.screens_dir = screens if isinstance(screens, str) else SCREENS
    if image is not None:
        start_image(m, image)
    elif screens:
        m.include(os.path.join(m.screens_dir, "rcl.fs"))
    m.documented_end = m.dictionary.here      # HELP: later words are the user's


def start_image(m, path):
    """Load a saved system onto m's fresh board: if RCL was installed when
    it was saved, INSTALL again (the vector, timer and counters are the
    board's, not the image's), then the safe state (relays off)."""
    from rcl.forth import image
    image.load(m, path)
    hit = m.dictionary.find("INSTALLED")
    if hit is not None and m.memory.fetch((hit[0] + 2) & 0xFFFF) and m.dictionary.find("INSTALL"):
        m.evaluate("INSTALL")
    m.safe_state()


def open_link(port, usb, write, screens, image):
    """RCL on a board over a link (rcl --port / --usb)."""
    from rcl.forth.machine import Forth
    from rcl.hw.connect import open_link as connect
    board = connect(port=port, usb=usb)
    try:
        m = Forth(write=write, board=board)
        server = getattr(board.port, "server", None)
        if server is not None:
            from rcl.sim.observe import Sim
            m.sim = Sim(server.board)
        load_rcl(m, screens, image)
        m.compile_ahead()     # the ticks are answered in real time from the first move
    except BaseException as e:
        if isinstance(e, ForthError) and e.code == -292 and board.why:
            e.message = "%s (%s)" % (e.message, board.why)   # why, said before the link closes
        board.close()         # a start that failed leaves no host connected
        raise
    return m
