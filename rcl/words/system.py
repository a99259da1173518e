"""System words: BYE, ENVIRONMENT?, PAUSE, F83's MS in virtual time, and
?DURATION (a wait's count checked)."""
from rcl.errors import Bye, ForthError
from rcl.forth.memory import MASK
from rcl.forth.primitives import CALL, CLOCK_HZ, prim

ENVIRONMENT = {
    "/COUNTED-STRING": [255], "/HOLD": [255], "/PAD": [84],
    "ADDRESS-UNIT-BITS": [8], "FLOORED": [MASK], "MAX-CHAR": [255],
    "MAX-D": [0xFFFF, 0x7FFF], "MAX-N": [0x7FFF], "MAX-U": [0xFFFF],
    "MAX-UD": [0xFFFF, 0xFFFF], "RETURN-STACK-CELLS": [1000],
    "STACK-CELLS": [1000], "WORDLISTS": [8], "#LOCALS": [32],
}


@prim("BYE", "( -- ) leave rcl")
def bye(m):
    m.shutdown()                  # the robot safe before anyone leaves
    raise Bye()


@prim("ENVIRONMENT?", "( addr u -- false | i*x true ) ask about the system")
def environment_q(m):
    u, a = m.s.pop(), m.s.pop()
    value = ENVIRONMENT.get(m.memory.text(a, u).upper())
    if value is None:
        m.s.append(0)
    else:
        m.s.extend(value)
        m.s.append(MASK)


@prim("PAUSE", "( -- ) let other tasks run: nothing, in a single-task system")
def pause(m):
    pass


@prim("MS", "( u -- ) wait u milliseconds of virtual time (F83's delay)", kind=CALL)
def ms(m):
    m.advance_to(m.clock + m.s.pop() * (CLOCK_HZ // 1000))


@prim("?DURATION", "( n -- n ) abort with \" Out of range \" if a wait's count n is "
      "negative (RCL's SECONDS and MINUTES: ?DO would take -1 as 65535)")
def q_duration(m):
    # A primitive, not `DUP 0< ABORT" ..."` in the screen: loading RCL then
    # takes the same virtual time, so INSTALL sets the timers in the same phase.
    if m.s[-1] & 0x8000:
        raise ForthError(-2, "Out of range")


@prim("CLOCK@", "( -- d ) the virtual clock in microseconds")
def clock_fetch(m):
    us = (m.clock * 1_000_000 // CLOCK_HZ) & 0xFFFFFFFF
    m.s.extend((us & MASK, us >> 16))


@prim("HALT", "( -- ) wait for the next interrupt, as the 80188's HLT does", kind=CALL)
def halt(m):
    due = getattr(m.irq, "due", None) if m.irq is not None else None
    if due is not None and not m.masked:
        m.advance_to(max(m.clock, due))
