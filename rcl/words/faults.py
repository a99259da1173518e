"""The CODE word behind the prompt's fault words (STALL-LEFT UNSTALL
LOAD-LEFT ENCODER-LEFT-OFF ..., screens/97-hobbyist.fs, a layer beyond the
article): it reaches the board's fault injection through the board
interface (Board.inject_fault). The simulated board has it; any other
board refuses, and the word says so.
"""
from rcl.board import NoFaults
from rcl.errors import ForthError
from rcl.forth.memory import signed
from rcl.forth.primitives import prim

FAULTS = ("stall", "load", "encoder")
WHEELS = ("left", "right")


@prim("FAULT!", "( x wheel# fault# -- ) a fault on a wheel (0 left, 1 right): "
      "fault 0 stall (x a flag), 1 load (x 0 to 100 percent), 2 encoder "
      "(x false: it stops counting)", hidden=True)
def fault_store(m):
    fault, wheel, value = m.s.pop(), m.s.pop(), signed(m.s.pop())
    if fault >= len(FAULTS) or wheel >= len(WHEELS):
        raise ForthError(-24, "Bad fault")
    if FAULTS[fault] == "load" and not 0 <= value <= 100:
        raise ForthError(-24, "Load is 0 to 100 percent")
    try:
        m.board.inject_fault(FAULTS[fault], WHEELS[wheel], value)
    except NoFaults as e:
        raise ForthError(-21, str(e)) from None
