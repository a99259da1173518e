"""Port I/O and far memory: how Forth reaches the board (F83's CPU8086.BLK
words, and L@ L! LC@ LC! for the 80188's 1 MiB, added here where F83 would
write CODE words).

Each goes through the machine's board (rcl/board.py); a bare machine's
NullBoard floats every port at 0xFF. Port words end a compiled block
(kind CALL): a write may reprogram a timer and so move the next
interrupt, and a read must see the clock of its own moment.
"""
from rcl.board import FORTH_CS
from rcl.forth.memory import MASK
from rcl.forth.primitives import CALL, prim
from rcl.robot import AUX_PORT, MOTOR_PORT


@prim("PC!", "( c port -- ) 8-bit OUT", kind=CALL)
def pc_store(m):
    port = m.s.pop()
    byte = m.s.pop() & 0xFF
    m.board.out8(port, byte)
    if port == MOTOR_PORT or port == AUX_PORT:   # a move may start or end (moves.py)
        m.moves.latched(m, port, byte)


@prim("PC@", "( port -- c ) 8-bit IN, zero-extended", kind=CALL)
def pc_fetch(m):
    m.s[-1] = m.board.in8(m.s[-1]) & 0xFF


@prim("P!", "( n port -- ) 16-bit OUT", kind=CALL)
def p_store(m):
    port = m.s.pop()
    m.board.out16(port, m.s.pop())


@prim("P@", "( port -- n ) 16-bit IN", kind=CALL)
def p_fetch(m):
    m.s[-1] = m.board.in16(m.s[-1]) & MASK


@prim("LC@", "( seg off -- c ) a byte of the 1 MiB address space", kind=CALL)
def lc_fetch(m):
    off, seg = m.s.pop(), m.s.pop()
    m.s.append(m.board.far_fetch8(seg, off))


@prim("LC!", "( c seg off -- ) store a byte in the 1 MiB address space", kind=CALL)
def lc_store(m):
    off, seg, c = m.s.pop(), m.s.pop(), m.s.pop()
    m.board.far_store8(seg, off, c & 0xFF)


@prim("L@", "( seg off -- n ) a little-endian cell of the 1 MiB space", kind=CALL)
def l_fetch(m):
    off, seg = m.s.pop(), m.s.pop()
    b = m.board
    m.s.append(b.far_fetch8(seg, off) | (b.far_fetch8(seg, (off + 1) & MASK) << 8))


@prim("L!", "( n seg off -- ) store a cell in the 1 MiB space", kind=CALL)
def l_store(m):
    off, seg, n = m.s.pop(), m.s.pop(), m.s.pop()
    m.board.far_store8(seg, off, n & 0xFF)
    m.board.far_store8(seg, (off + 1) & MASK, n >> 8)


@prim("GET-CS", "( -- seg ) the code segment of the Forth system")
def get_cs(m):
    m.s.append(FORTH_CS)


@prim("RECONNECT", "( -- ) connect again to a board whose link was lost; "
      "say how it went", kind=CALL)
def reconnect(m):
    said = m.board.reconnect()
    m.type(" %s " % said)
    if said.startswith("Link up"):
        set_up_again(m)


def set_up_again(m):
    """A new session finds the board as at power-on (docs/protocol.md,
    "Sessions"): if RCL had been installed, INSTALL again (it programs the
    timer, the vector and the counters anew)."""
    installed, install = m.dictionary.find("INSTALLED"), m.dictionary.find("INSTALL")
    if installed and install and m.memory.fetch((installed[0] + 2) & MASK):
        m.execute(install[0])
