"""Random lines for the whole system (rcl.open()), hostile ones included,
and the checks made after each: shared by tests/test_fuzz_robot.py and
bench/robustness.py (which prints the figures docs/performance.md quotes).

A line is a few tokens: words of the RCL dictionary, numbers of every
size, commands with units, and hostile pieces (interrupts off, masked, the
vector moved, the control word replaced, odd timer periods, settings no
check can work with, EMPTY, FORGET). Left out, as the bare machine's fuzz
leaves out raw stores: words whose purpose is to write memory, ports or
the relay latches at an address or with a value from the stack (a user
who types `ARM-ON ENABLE` has switched the arm on by hand), and words that
write the host's files.
"""
import random

import rcl
from rcl.forth.memory import MASK

LOW_LEVEL = {"!", "C!", "2!", "+!", "ON", "OFF", "FILL", "ERASE", "BLANK", "CMOVE",
             "CMOVE>", "MOVE", "DEFER!", "EXECUTE", "CATCH", "COMPILE,", "UPPER",
             "ACCEPT", "EXPECT", "HIDE", "REVEAL", "SUBSTITUTE", "UNESCAPE",
             "TRAVERSE-WORDLIST", "PC!", "P!", "L!", "LC!", "ENABLE", "LATCH", "GO",
             "REVERSE", "CW", "CCW", "BEEP-ON", "REF!", "SEND", "SET-SPEED", "ALLOT",
             "ALLOCATE", "RESIZE", "FREE", ",", "C,", "2,", "KEY", "EKEY", "EXPECT",
             "N>R", "NR>", "AT-XY", "PAGE", "LOCALS|", "(LOCAL)"}
HOST_FILES = {"SAVE-SYSTEM", "SAVE-TRACE", "PLOT", "CREATE-FILE", "DELETE-FILE",
              "RENAME-FILE", "WRITE-FILE", "WRITE-LINE", "RESIZE-FILE", "OPEN-FILE",
              "USING", "FLUSH", "SAVE-BUFFERS", "UPDATE", "INCLUDED", "INCLUDE-FILE",
              "REQUIRED", "INCLUDE", "REQUIRE", "CREATE-BLOCKS", "MORE", "TRACE-ON"}
HOSTILE = ["INT-OFF", "INT-ON", "MASK", "UNMASK", "0 0 28 SET-INT", "' NOOP IS CONTROL",
           "' DROP IS CONTROL", "' QUIT IS CONTROL", "' BYE IS CONTROL", "' DUP IS CONTROL",
           "' (CONTROL) IS CONTROL", "1 SET-TIMER", "0 SET-TIMER", "6667 SET-TIMER",
           "UNINSTALL", "0 ACCEL !", "32767 FERR-LIMIT !", "-1 FERR-LIMIT !", "1 ACCEL !",
           "30000 ACCEL !", "MOVING ON", "ARM-BITS ON", "7 PENDING-UNIT !", "0 DEVICE !",
           "-5 SPEED-UNIT !", "EMPTY", "FORGET CANARY", ": CONTROL ;", "' ABORT IS ON-ABORT",
           "-1. WAIT-UNTIL", "TICKS@ 300. D+ WAIT-UNTIL", "99999999. TICKS!",
           "RCL-RATE", "BIOS-RATE", "1 SET-TIMER INSTALL"]
COMMANDS = ["FORWARD", "BACKWARD", "LEFT", "RIGHT", "UP", "DOWN", "OPEN", "CLOSE"]
UNITS = ["INCHES", "FEET", "MILES", "DEGREES", "MPH", "IPS", "FPS", "FPM", "G",
         "AM", "PM", "MS", "SECONDS", "MINUTES"]
NUMBERS = ["0", "1", "-1", "2", "3.5", "0.1", "25.5", "40000", "-40000", "70000", "65535",
           "32767", "-32768", "1193.0464", "1194", "99999999999", "1.", "-1.", "0.00001",
           "12", "9.99999"]
BUDGET = 9_000                  # primitives' worth of virtual time a line (0.25 s)
MOTOR_BITS, ARM_BITS = 0x35, 0x0F   # M1-ON M2-ON M1-GO M2-GO (the direction bits move nothing); arm, gripper


def machine():
    """A full system with a canary word above the fence (as a user's)."""
    m = rcl.open()
    m.evaluate(": CANARY  1 2 + . ;")
    m.memory.store(m.a_fence, m.dictionary.here)
    m.step_limit = BUDGET
    return m


def dictionary_words(m):
    d = m.dictionary
    names = {d.name_of((lfa + 2) & MASK) for wid in (m.forth_wid, m.root_wid)
             for lfa in d.lfas(wid)}
    return sorted(n for n in names if n and n not in LOW_LEVEL | HOST_FILES and n != "CANARY")


def lines(n, seed, words):
    """n random lines, the same for the same seed."""
    rng = random.Random(seed)
    pieces = [lambda: rng.choice(words), lambda: rng.choice(NUMBERS),
              lambda: str(rng.randint(-2**20, 2**20)),
              lambda: "%s %s" % (rng.choice(NUMBERS), rng.choice(UNITS)),
              lambda: "%s %s %s" % (rng.choice(NUMBERS), rng.choice(UNITS),
                                    rng.choice(COMMANDS)),
              lambda: rng.choice(HOSTILE), lambda: "INSTALL"]
    weights = [8, 3, 1, 3, 3, 2, 1]
    for _ in range(n):
        yield " ".join(rng.choices(pieces, weights)[0]() for _ in range(rng.randint(1, 5)))


def reset_user_state(m):
    """What a user would put back by hand: decimal, the usual search order,
    interpreting (an abandoned definition is left as F83 leaves it)."""
    m.abort()
    m.memory.store(m.a_base, 10)
    m.dictionary.set_order([m.forth_wid, m.root_wid])
    m.memory.store(m.a_current, m.forth_wid)


def motors_on(m):
    motor, aux = m.sim.relays
    return bool(motor & MOTOR_BITS or aux & ARM_BITS)


def run_line(m, text):
    """Run one line; -> its outcome: 'ok', 'bye', or the error's message
    (a message kind). Raises AssertionError when a check fails: a Python
    exception, an internal error, motors on after the line, a dead canary."""
    try:
        m.evaluate(text)
        outcome = "ok"
    except rcl.ForthError as e:
        assert e.code != -4095, "internal error on %r: %s" % (text, e)
        outcome = e.message.split(" in the tick handler")[0] + \
            (" (tick fault)" if " in the tick handler" in e.message else "")
    except rcl.Bye:
        outcome = "bye"
    assert not motors_on(m), "motors on after %r" % text
    reset_user_state(m)
    try:
        canary = m.evaluate("CANARY")
    except rcl.ForthError as e:
        # A tick handler the line put in (`' QUIT IS CONTROL`) faults at the
        # next tick, which may come while the canary runs: the line's fault,
        # reported as F83 reports it, in whatever runs; the tick is off now.
        assert " in the tick handler" in e.message, "canary dead after %r: %s" % (text, e)
        assert not motors_on(m), "motors on after %r" % text
        reset_user_state(m)
        canary = m.evaluate("CANARY")
    assert canary == "3 ", "canary dead after %r" % text
    return outcome
