"""Help at the prompt: HELP, RCL-WORDS, and the word-boundary wrapping WORDS
uses. What a word is comes from rcl/wordinfo.py (the screens' stack
comments and the primitives' declarations), imported when first asked
for, since it reads the machine's own tables."""
from rcl.errors import ForthError
from rcl.forth import state
from rcl.forth.primitives import CALL, prim

# Where the documented words end (rcl.open sets it once RCL is loaded;
# None: FENCE): HELP says a word defined after it is defined again.
state.session("documented_end", lambda m: None)

START = """\
rcl: RCL, the Robotic Control Language of the 1986 R-E Robot, on F83 Forth.
  The article's first command:   RERB 2 MPH 3.4 FEET FORWARD
  Then:   .POSE  where the robot is    .SETTINGS  speed and distances
          .TIME  the time of day       90 DEGREES LEFT   ARM 2 INCHES UP
  HELP name      a word's stack effect, its layer or word set, what it does
  RCL-WORDS      RCL's words, layer by layer;   WORDS  every word, newest first
  The article's listings, from any directory:
          INCLUDE examples/listing1.fs   (the square; listing2 to 6, arm.fs)
  #help          the prompt's own commands;  BYE leaves
"""
NO_RCL = """\
rcl: an F83 Forth. RCL is not loaded on this machine (--bare: no board;
--board-only: the board without RCL's screens, INCLUDE rcl.fs loads them all).
  HELP name      a word's stack effect, its word set, what it does
  WORDS          every word, newest first;  BYE leaves
"""


def wrap(names, width, indent=""):
    """Lines of names joined by two blanks, broken only between names."""
    lines, line = [], indent
    for name in names:
        gap = "" if line == indent else "  "
        if line != indent and len(line) + len(gap) + len(name) > width:
            lines.append(line)
            line, gap = indent, ""
        line += gap + name
    if line != indent:
        lines.append(line)
    return lines


def columns(m):
    """The width output wraps at: the terminal's, as the prompt sets it."""
    return getattr(m, "columns", None) or 80


@prim("HELP", "( \"name\" -- ) a word's stack effect, where it is from and what it "
              "does; alone, how to start", kind=CALL)
def help_word(m):
    from rcl import wordinfo
    name, _ = m.parse_name()
    if not name:
        m.type("\n" + (START if m.dictionary.find("RERB") else NO_RCL))
        return
    hit = m.dictionary.find(name)
    if hit is None:
        raise ForthError(-13, "?", name.upper())
    entry, word = wordinfo.lookup(name), name.upper()
    if entry is None:
        m.type("\n%s  a word of your own: SEE %s shows it\n" % (word, word))
        return
    m.type("\n" + entry.help() + "\n")
    end = m.documented_end
    if hit[0] >= (end if end is not None else m.memory.fetch(m.a_fence)):
        m.type("  (defined again since start-up: SEE %s shows this one)\n" % word)


@prim("RCL-WORDS", "( -- ) RCL's words, layer by layer, as each screen lists them",
      kind=CALL)
def rcl_words(m):
    from rcl import wordinfo
    width = columns(m)
    out = []
    for title, names in wordinfo.layers():
        present = [n for n in names if m.dictionary.find(n) is not None]
        if present:
            out.append(title + ":")
            out.extend(wrap(present, width, "  "))
    m.type("\n" + "\n".join(out) + "\n" if out else "RCL is not loaded ")
