"""What each word is: its stack effect, where it comes from and one line
saying what it does, for HELP, RCL-WORDS and docs/words.md.

Two sources, so nothing is kept twice by hand:

    primitives   the @prim declaration: "( n1 n2 -- n3 ) what it does",
                 its word set from the module it lives in (rcl/words/core.py
                 -> core), else the function's docstring
    Forth words  the screens (screens/*.fs, RCL's layers) and the kernel
                 (rcl/kernel/*.fs): a defining word and its name, the stack
                 comment after the name, the `\\ comment` after that; the
                 layer is the file's first line

        : TAKE  ( cmd# -- )   \\ PENDING: the distance given, else the last one
          ^name  ^effect          ^description

A word defined again later (FORWARD in layers 1 and 8) is described by its
last definition, the one the dictionary finds.
"""
import os
import re
from dataclasses import dataclass

import rcl
from rcl.forth.machine import KERNEL_DIR, USER_VARIABLES
from rcl.forth.primitives import REGISTRY

DEFINERS = {":": "", "VARIABLE": "( -- addr )", "2VARIABLE": "( -- addr )",
            "CONSTANT": "( -- n )", "2CONSTANT": "( -- d )", "CREATE": "( -- addr )",
            "DEFER": "", "CODE": "", "VALUE": "( -- n )", "VOCABULARY": "( -- )"}
STACK_COMMENT = re.compile(r"\s*(\([^)]*\))\s*(.*)")


@dataclass
class Entry:
    name: str
    effect: str          # "( n1 n2 -- n3 )", or "" when unknown
    where: str           # "core word set", "Layer 8, command language"
    text: str            # one line: what it does
    source: str = ""     # the defining line, when there is no description
    file: str = ""       # where it is defined (a primitive: "")
    line: int = 0

    def help(self):
        """What HELP prints: name and effect, where from, what it does."""
        what = self.text or ("defined as: " + self.source if self.source else "")
        lines = ["%s  %s" % (self.name, self.effect or "( ? )"), "  " + self.where]
        return "\n".join(lines + (["  " + what] if what else []))


# ---------------------------------------------------------------- primitives
def primitive_entries():
    entries = {}
    for p in REGISTRY[1:]:
        if p.hidden:                     # as at boot: a runtime with a header is listed
            continue
        effect, text = split_effect(p.effect)
        where = "%s word set" % p.fn.__module__.rsplit(".", 1)[-1] if p.fn else \
            "inner interpreter"
        entries[p.name.upper()] = Entry(p.name, effect, where, text or first_line(p.doc))
    for voc in ("FORTH", "ROOT"):
        entries[voc] = Entry(voc, "( -- )", "vocabulary",
                             "put the %s vocabulary first in the search order" % voc)
    for var in USER_VARIABLES:
        entries[var] = Entry(var, "( -- addr )", "system variable",
                             "the system variable %s (a cell in the user area)" % var)
    return entries


def split_effect(declared):
    m = STACK_COMMENT.match(declared or "")
    if not m:
        return "", (declared or "").strip()
    return m.group(1), m.group(2).strip()


def first_line(text):
    return text.strip().split("\n")[0].strip() if text else ""


# --------------------------------------------------------------- Forth words
def layer_title(first):
    """`\\ Layer 8, command language: ...` -> `Layer 8, command language`."""
    title = first.lstrip("\\").strip()
    return title.split(":")[0].strip().rstrip(".")


def file_entries(path, where=None):
    """The words a Forth source file defines, in order: a defining word met
    while interpreting (not one compiled inside a definition, nor a name
    after `'`, `[CHAR]` ... or in a comment or string). A word defined into
    another vocabulary (ROOT's WORDS, which runs FORTH's) describes
    nothing of its own."""
    with open(path, encoding="latin-1") as f:
        lines = [line.rstrip("\n") for line in f]
    where = where or layer_title(lines[0] if lines else "")
    definers = dict(DEFINERS)
    definers.update(own_definers(lines))
    found, scan = [], Scan()
    for number, line in enumerate(lines, 1):
        defs = [(d, name, end) for d, name, end in scan.line(line) if d.upper() in definers]
        for definer, name, end in defs:
            if scan.current != "FORTH":
                continue
            definer = definer.upper()
            effect, text = describe(line[end:], len(defs) == 1, definer)
            effect = effect or definers[definer]
            found.append(Entry(name, effect, where, text, line.strip(), path, number))
    return found


class Scan:
    """Forth source read as the outer interpreter reads it, a line at a
    time: which names follow a word while interpreting, and the vocabulary
    definitions go to."""

    SKIP_NEXT = {"'", "[']", "CHAR", "[CHAR]", "POSTPONE", "[COMPILE]", "COMPILE"}
    TEXT = {"(": ")", ".(": ")", '."': '"', 'S"': '"', 'C"': '"', 'ABORT"': '"', '."': '"'}

    def __init__(self):
        self.compiling = False
        self.current = "FORTH"
        self.last = ""

    def line(self, line):
        """[(word, the name after it, where the name ends)] for each word
        interpreted (not compiled) on this line and followed by a name."""
        out, i, skip = [], 0, False
        tokens = list(re.finditer(r"\S+", line))
        k = 0
        while k < len(tokens):
            t = tokens[k]
            word = t.group().upper()
            k += 1
            if skip:
                skip = False
                continue
            if word == "\\":
                break
            close = self.TEXT.get(word)
            if close is not None:
                end = line.find(close, t.end() + 1)
                end = len(line) if end < 0 else end + 1
                while k < len(tokens) and tokens[k].start() < end:
                    k += 1
                continue
            if word in self.SKIP_NEXT:
                skip = True
                continue
            if self.compiling:
                if word in (";", "[", ";CODE"):
                    self.compiling = False
                continue
            if word == "]":
                self.compiling = True
            elif word == "DEFINITIONS":
                self.current = "FORTH" if self.last in ("PREVIOUS", "ONLY", "FORTH") \
                    else self.last
            elif k < len(tokens):
                out.append((t.group(), tokens[k].group(), tokens[k].end()))
                if word == ":":
                    self.compiling = True
                    k += 1
            self.last = word
        return out


def own_definers(lines):
    """The file's own defining words (`: WHEEL: ... CREATE ... ;`): each
    name they define gives an address, as CREATE's do."""
    code = " ".join(line.split("\\ ", 1)[0] for line in lines if not line.startswith("\\"))
    found = {}
    for m in re.finditer(r"(?:^|\s):\s+(\S+)(.*?)\s;(?=\s|$)", code):
        if "CREATE" in m.group(2).upper().split():
            found[m.group(1).upper()] = "( -- addr )"
    return found


def definition_pattern(definers):
    names = sorted(definers, key=len, reverse=True)
    return re.compile(r"(?:^|\s)(%s)\s+(\S+)" % "|".join(map(re.escape, names)),
                      re.IGNORECASE)


def describe(rest, alone, definer):
    """Stack comment and description from what follows a defined name: the
    `\\ comment` of a line defining one word, or a CODE word's prose."""
    effect, text = "", ""
    m = STACK_COMMENT.match(rest)
    if m and rest.lstrip().startswith("( "):
        effect, rest = m.group(1), m.group(2)
        if definer == "CODE" and "\\" not in rest:
            text = rest.strip()
    if "\\ " in rest and alone:
        text = rest.split("\\ ", 1)[1].strip()
        m = STACK_COMMENT.match(text)
        if m and not effect and text.startswith("( "):   # `32 CONSTANT BL  \ ( -- c ) the blank`
            effect, text = m.group(1), m.group(2)
    return effect, text


def screen_files():
    """RCL's layers in load order (the load screen rcl.fs excepted)."""
    folder = rcl.SCREENS
    return [os.path.join(folder, n) for n in sorted(os.listdir(folder))
            if n.endswith(".fs") and n != "rcl.fs"]


def kernel_files():
    return [os.path.join(KERNEL_DIR, n) for n in sorted(os.listdir(KERNEL_DIR))
            if n.endswith(".fs")]


def forth_entries():
    entries = {}
    for path in kernel_files():
        for e in file_entries(path, "F83 kernel (in Forth)"):
            entries[e.name.upper()] = e
    for path in screen_files():
        for e in file_entries(path):
            entries[e.name.upper()] = e
    return entries


def layers():
    """[(layer title, [words it adds])] from each screen's `Adds` lines."""
    result = []
    for path in screen_files():
        with open(path, encoding="latin-1") as f:
            head = [line.lstrip("\\").strip() for line in f if line.startswith("\\")][:6]
        text = " ".join(head)
        m = re.search(r"Adds (.*?)(?:Relies|$)", text)
        known = entries()
        names = [w.rstrip(".,") for w in (m.group(1).split() if m else [])]
        names = [w for w in dict.fromkeys(names) if w.upper() == w and w in known]
        result.append((layer_title(head[0] if head else ""), names))
    return result


_CACHE = {}


def entries():
    """Every documented word: NAME (upper case) -> Entry."""
    if not _CACHE:
        _CACHE.update(primitive_entries())
        _CACHE.update(forth_entries())
    return _CACHE


def lookup(name):
    return entries().get(name.upper())
