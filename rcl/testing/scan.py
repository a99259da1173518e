"""Finding the tests in a Forth test file without running it, so that
pytest can list them: each T{ interpreted at the top level of the file is
one test, named by its line.

    \\ rcl: bare                       <- a directive among the first comment lines
    : SQUARE  DUP * ;                  <- T{ inside a definition is not a test
    T{ 3 SQUARE -> 9 }T                <- test "line 3", column just past T{
    T{ 1 2 ( a comment ) + -> 3 }T     <- comments and strings are skipped

The column is the value >IN has just after T{ is parsed (the tester
notes it too), so a test found here and a result heard at run time meet
on (line, column). Tokens are split at blanks and control characters as
the outer interpreter splits them.
"""
import re
from dataclasses import dataclass

DIRECTIVE = re.compile(r"^\\\s*rcl:\s*(\w+)", re.IGNORECASE)
MODES = ("robot", "bare")
STRINGS = {'S"', '."', 'C"', 'ABORT"', 'S\\"', '"'}      # text up to the next "
NAMES = {":", "CHAR", "[CHAR]", "'", "[']", "POSTPONE", "[COMPILE]", "CREATE",
         "VARIABLE", "CONSTANT", "2VARIABLE", "2CONSTANT", "VALUE", "DEFER",
         "IS", "TO", "FORGET", "INCLUDE", "REQUIRE", "VOCABULARY", "MARKER"}


class ScanError(Exception):
    """The file asks for something this scanner does not know."""


@dataclass
class Spec:
    """One test found in the file."""
    line: int                 # 1-based line of T{
    column: int               # >IN just past T{
    end_line: int             # line of the matching }T (line if none)
    source: list              # the lines from T{ to }T
    name: str = ""


def next_token(text, i):
    """(token, end) of the next blank-delimited token from text[i:], or None."""
    n = len(text)
    while i < n and text[i] <= " ":
        i += 1
    if i >= n:
        return None
    j = i
    while j < n and text[j] > " ":
        j += 1
    return text[i:j], j


def after(text, end):
    """>IN once the token ending at `end` is parsed (past one delimiter)."""
    return end + 1 if end < len(text) else end


class Scanner:
    def __init__(self, lines):
        self.lines = lines
        self.specs = []
        self.open = None          # the Spec whose }T is not yet seen
        self.defining = False
        self.comment = False      # inside ( ... ) across lines

    def scan(self):
        for number, text in enumerate(self.lines, 1):
            self.scan_line(number, text)
        for spec in self.specs:
            spec.source = self.lines[spec.line - 1:spec.end_line]
        return self.specs

    def scan_line(self, number, text):
        pos = 0
        if self.comment:
            pos = self.skip_to(text, 0, ")", multiline=True)
        while pos is not None:
            found = next_token(text, pos)
            if found is None:
                return
            pos = self.token(number, text, found[0].upper(), found[1])

    def token(self, number, text, word, end):
        """Act on one token; -> where to go on, None to skip the line."""
        if word in ("\\", "TESTING"):
            return None
        if word in ("(", ".("):
            return self.skip_to(text, after(text, end), ")", multiline=word == "(")
        if word in STRINGS:
            return self.skip_to(text, after(text, end), '"')
        if word in NAMES:                  # the next token is a name
            self.defining = self.defining or word == ":"
            name = next_token(text, end)
            return name[1] if name else end
        if word == ":NONAME":
            self.defining = True
        elif word == ";":
            self.defining = False
        elif word == "T{" and not self.defining:
            self.open = Spec(number, after(text, end), number, [])
            self.specs.append(self.open)
        elif word == "}T" and not self.defining and self.open is not None:
            self.open.end_line, self.open = number, None
        return end

    def skip_to(self, text, start, char, multiline=False):
        """Past the next `char`; None (rest of line) if there is none."""
        close = text.find(char, start)
        self.comment = multiline and close < 0
        return None if close < 0 else close + 1


def mode_of(lines):
    """"robot" or "bare": a `\\ rcl: bare` line among the leading comment
    lines asks for a bare machine."""
    for text in lines:
        if not text.strip():
            continue
        if not text.lstrip().startswith("\\"):
            break
        match = DIRECTIVE.match(text.lstrip())
        if match:
            mode = match.group(1).lower()
            if mode not in MODES:
                raise ScanError("%r: the directive is `\\ rcl: robot` or `\\ rcl: bare`"
                                % text.strip())
            return mode
    return "robot"


def scan(lines):
    """-> (mode, specs) of a test file's lines, each spec named by its line
    (`line 7`, then `line 7.2` for a second test on the same line)."""
    specs = Scanner(lines).scan()
    seen = {}
    for spec in specs:
        n = seen[spec.line] = seen.get(spec.line, 0) + 1
        spec.name = "line %d" % spec.line + (".%d" % n if n > 1 else "")
    return mode_of(lines), specs
