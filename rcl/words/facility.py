"""Facility word set (Forth 2012 chapter 10) beyond F83's KEY? PAGE MS:
AT-XY, EMIT?, EKEY and its key codes, TIME&DATE. The structure words
(BEGIN-STRUCTURE +FIELD FIELD: ...) are Forth, in rcl/kernel/03-tools.fs.

EKEY reads the keys a terminal sends: a plain character is itself; the
ANSI sequences of the cursor and function keys (ESC [ A, ESC [ 1 ; 5 C,
ESC O P, ESC [ 15 ~ ...) become one code each, K-UP ... K-F12, with the
K-SHIFT-MASK K-ALT-MASK K-CTRL-MASK bits of their modifiers:

    bit 15 set: a special key     bits 8..10: shift alt ctrl   bits 0..7: which key

TIME&DATE: the date is the host's (no board has a calendar); the time of
day is the board's BIOS count (0040:006C ticks since midnight, 0040:00F0
ticks a day) when a board answers there, as the simulated one does, else
the host's clock.
"""
import time

from rcl.forth.memory import MASK, signed
from rcl.forth.primitives import prim
from rcl.words.io import next_key

SPECIAL = 0x8000
SHIFT, ALT, CTRL = 0x100, 0x200, 0x400
KEYS = ["LEFT", "RIGHT", "UP", "DOWN", "HOME", "END", "PRIOR", "NEXT",
        "INSERT", "DELETE"] + ["F%d" % i for i in range(1, 13)]
CODE = {name: SPECIAL | i for i, name in enumerate(KEYS)}
FINAL = {"A": "UP", "B": "DOWN", "C": "RIGHT", "D": "LEFT", "H": "HOME", "F": "END",
         "P": "F1", "Q": "F2", "R": "F3", "S": "F4"}
TILDE = {1: "HOME", 2: "INSERT", 3: "DELETE", 4: "END", 5: "PRIOR", 6: "NEXT",
         15: "F5", 17: "F6", 18: "F7", 19: "F8", 20: "F9", 21: "F10", 23: "F11", 24: "F12"}
BIOS_SEG, TICK_COUNT, PER_DAY = 0x40, 0x6C, 0xF0


def key_waiting(m):
    return bool(m.keys) or (m.key_ready is not None and m.key_ready())


def escape_sequence(m):
    """After ESC: the rest of an ANSI key sequence -> key code, or None."""
    if not key_waiting(m):
        return None
    intro = chr(next_key(m))
    if intro not in "[O":
        return None
    params = ""
    while key_waiting(m):
        c = chr(next_key(m))
        if c.isdigit() or c == ";":
            params += c
            continue
        nums = [int(p) for p in params.split(";") if p]
        name = TILDE.get(nums[0]) if c == "~" and nums else FINAL.get(c)
        if name is None:
            return None
        mods = nums[1] - 1 if len(nums) > 1 else 0
        return CODE[name] | (SHIFT if mods & 1 else 0) | (ALT if mods & 2 else 0) \
            | (CTRL if mods & 4 else 0)
    return None


@prim("EKEY", "( -- x ) the next keyboard event: a character, or a K- code")
def ekey(m):
    c = next_key(m) & 0xFF
    if c == 27:
        code = escape_sequence(m)
        m.s.append(27 if code is None else code)
    else:
        m.s.append(c)


@prim("EKEY?", "( -- f ) is a keyboard event waiting?")
def ekey_q(m):
    m.s.append(MASK if key_waiting(m) else 0)


@prim("EKEY>CHAR", "( x -- x false | c true ) the character an event is, if any")
def ekey_to_char(m):
    m.s.append(0 if m.s[-1] & SPECIAL else MASK)


@prim("EKEY>FKEY", "( x -- u f ) f true if x is a special key, u its K- code")
def ekey_to_fkey(m):
    m.s.append(MASK if m.s[-1] & SPECIAL else 0)


def key_constant(name, value):
    prim(name, "( -- u ) a key code for EKEY>FKEY")(lambda m: m.s.append(value))


for _name, _code in CODE.items():
    key_constant("K-" + _name, _code)
key_constant("K-SHIFT-MASK", SHIFT)
key_constant("K-ALT-MASK", ALT)
key_constant("K-CTRL-MASK", CTRL)


@prim("EMIT?", "( -- f ) can EMIT go on without waiting? (always)")
def emit_q(m):
    m.s.append(MASK)


@prim("AT-XY", "( col row -- ) put the cursor there, 0 0 the top left (ANSI)")
def at_xy(m):
    row, col = signed(m.s.pop()), signed(m.s.pop())
    m.type("\x1b[%d;%dH" % (max(row, 0) + 1, max(col, 0) + 1))


def board_seconds(m):
    """Seconds since midnight by the board's BIOS count, or None."""
    def cell32(off):
        return sum(m.board.far_fetch8(BIOS_SEG, off + i) << (8 * i) for i in range(4))
    per_day = cell32(PER_DAY)
    if per_day in (0, 0xFFFFFFFF):               # nothing there: a floating bus
        return None
    return cell32(TICK_COUNT) % per_day * 86400 // per_day


@prim("TIME&DATE", "( -- sec min hour day month year ) the board's time of day, "
      "or the host's; the host's date")
def time_and_date(m):
    now = time.localtime()
    secs = board_seconds(m)
    if secs is None:
        secs = now.tm_hour * 3600 + now.tm_min * 60 + now.tm_sec
    m.s.extend((secs % 60, secs // 60 % 60, secs // 3600,
                now.tm_mday, now.tm_mon, now.tm_year))
