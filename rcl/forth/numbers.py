"""Number conversion, F83's way (f83-semantics.md section 4), with the
Forth 2012 prefixes (#decimal $hex %binary 'c').

    "-9.999"  ->  Number(value=-9999, dpl=3)    a double: DPL >= 0
    "725"     ->  Number(value=725, dpl=-1)     a single: DPL = -1

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

    @property
    def double(self):
        return self.dpl >= 0


def digit(c, base):
    """The value of character c as a digit in base, or None."""
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
    acc, dpl = 0, -1
    for c in text:
        d = digit(c, base)
        if d is not None:
            acc = (acc * base + d) & 0xFFFFFFFF
            if dpl != -1:
                dpl += 1
        elif c in PUNCTUATION:
            dpl = 0
        else:
            return Number(0, dpl, ok=False)
    if negative:
        acc = -acc & 0xFFFFFFFF
    return Number(acc, dpl)
