"""Number conversion, F83's way (docs/forth2012.md, "Core: F83's meanings"),
with the Forth 2012 prefixes (#decimal $hex %binary 'c').

    "-9.999"  ->  Number(value=-9999, dpl=3)    a double: DPL >= 0
    "725"     ->  Number(value=725, dpl=-1)     a single: DPL = -1
    "40000"   ->  Number(value=40000, dpl=-1, wide=True)
                  a single beyond a signed cell: F83 keeps the low 16 bits
                  (40000 U. prints 40000); `wide` lets RCL's FIXED refuse
                  it rather than read -25536

DPL counts the digits after the last punctuation character (, - . /).
A failed conversion still reports the DPL the scan reached (F83 sets DPL
while it scans), except when the token has no digit at all.
"""
from dataclasses import dataclass

PUNCTUATION = ",-./"
PREFIXES = {"#": 10, "$": 16, "%": 2}


@dataclass
class Number:
    value: int      # the 32-bit result, unsigned (mod 2**32)
    dpl: int        # -1: a single; otherwise digits after the last punctuation
    ok: bool = True
    wide: bool = False   # a single whose typed value does not fit a signed cell

    @property
    def double(self):
        return self.dpl >= 0


def digit(c, base):
    """The value of character c as a digit in base, or None. (c comes
    upper-cased, which may make two letters of one: ß is SS, U+FB06 ST.)"""
    if len(c) != 1:
        return None
    if "0" <= c <= "9":
        v = ord(c) - 48
    elif "A" <= c <= "Z":
        v = ord(c) - 55
    else:
        return None
    return v if v < base else None


def convert(token, base):
    """Convert token in base; None when it has no digit (DPL untouched)."""
    if len(token) == 3 and token[0] == "'" and token[2] == "'":
        return Number(ord(token[1]), -1)
    text = token.upper()
    if text[:1] in PREFIXES:
        base, text = PREFIXES[text[0]], text[1:]
    if not 2 <= base <= 36 or not any(digit(c, base) is not None for c in text):
        return None
    negative = text.startswith("-")
    if negative:
        text = text[1:]
    acc, dpl, exact = 0, -1, 0
    for c in text:
        d = digit(c, base)
        if d is not None:
            exact = exact * base + d
            acc = (acc * base + d) & 0xFFFFFFFF
            if dpl != -1:
                dpl += 1
        elif c in PUNCTUATION:
            dpl = 0
        else:
            return Number(0, dpl, ok=False)
    if negative:
        acc, exact = -acc & 0xFFFFFFFF, -exact
    return Number(acc, dpl, wide=dpl == -1 and not -0x8000 <= exact <= 0x7FFF)
