"""Forth test files as pytest items: `test_*.fs` runs once, on a fresh
robot (or a bare machine if it says `\\ rcl: bare`), and every T{ ... }T
at its top level is one item.

    test_box.fs::load       the file (and the configured files) loaded to
                            the end; fails with the error at file:line
    test_box.fs::line 7     the T{ on line 7: passed, failed (file:line,
                            the source, expected and actual stacks), or
                            skipped if the load stopped before it

The first item to run loads the file; the rest read what it heard. A
T{ ... }T that ran somewhere else (inside a definition, in an INCLUDE'd
file) has no item of its own: a failure there fails `load`.
"""
import os
import types
from dataclasses import dataclass, field

import pytest

from rcl.testing.scan import ScanError, scan


TESTER_WORDS = ("T{", "->", "}T")


class ForthTestFailure(Exception):
    """A Forth test failed; the message is the whole report."""


@dataclass
class Run:
    """What loading a test file did."""
    results: dict = field(default_factory=dict)     # (line, column) -> [Result]
    others: list = field(default_factory=list)      # results with no item
    error: object = None                            # the ForthError that stopped it
    output: str = ""
    redefined: list = field(default_factory=list)   # tester words the file replaced


def read_lines(path):
    with open(path, encoding="latin-1") as f:
        return [line.rstrip("\r\n") for line in f]


class ForthFile(pytest.File):
    """A test_*.fs file."""

    def collect(self):
        self.lines = read_lines(self.path)
        try:
            self.mode, specs = scan(self.lines)
        except ScanError as e:
            raise self.CollectError("%s:1: %s" % (self.path.name, e)) from None
        self.specs = specs
        self.keys = {(spec.line, spec.column) for spec in specs}
        self.run_ = None
        yield ForthLoad.from_parent(self, name="load")
        for spec in specs:
            yield ForthTest.from_parent(self, name=spec.name, spec=spec)

    def outcome(self):
        if self.run_ is None:
            self.run_ = self.load()
        return self.run_

    def load(self):
        from rcl.errors import Bye, ForthError
        from rcl.testing.plugin import machine
        from rcl.words.tester import state_of
        run, name = Run(), str(self.path)
        try:
            m = machine(self.config, self.mode)
            state_of(m).listener = lambda result: self.hear(m, run, name, result)
            m.include(name)
            run.output = m.take_output()
            run.redefined = [w for w in TESTER_WORDS
                             if (m.dictionary.find(w) or (None,))[0] != m.xt_of[w]]
        except ForthError as e:
            if e.code == -28:             # Ctrl-C: the machine is safe, stop pytest
                raise KeyboardInterrupt from None
            run.error, run.output = e, e.output
        except Bye:                       # the file asked rcl to leave
            run.error = ForthError(-1, "BYE: the file ended before its last line")
        return run

    def hear(self, m, run, name, result):
        if not result.ok and self.mode == "robot" and m.sim.board.moves.moves:
            from rcl.testing.assertions import report
            result.notes = report(m)         # only once the robot has moved
        if result.file == name and (result.line, result.column) in self.keys:
            run.results.setdefault((result.line, result.column), []).append(result)
        else:
            run.others.append(result)

    def spec_of_error(self, run):
        """The test that was running when the load stopped, or None."""
        error = run.error
        if error is None or error.file != str(self.path) or error.line is None:
            return None
        for spec in self.specs:
            if spec.line <= error.line <= spec.end_line \
                    and (spec.line, spec.column) not in run.results:
                return spec
        return None

    def source_line(self, file, line):
        try:
            lines = self.lines if file == str(self.path) else read_lines(file)
            return lines[line - 1]
        except (OSError, IndexError, TypeError):
            return None


def shown(path):
    """A file as the report names it: relative to here when it is below."""
    rel = os.path.relpath(path)
    return path if rel.startswith("..") else rel


def where(error):
    """`file:line` of an error, or the error itself when it has no place."""
    return "%s:%s" % (shown(error.file), error.line) if error.file else error.display()


def error_text(parent, error):
    lines = [("%s: " % where(error) if error.file else "") + error.display()]
    source = parent.source_line(error.file, error.line)
    if source is not None:
        lines.append("    " + source.strip())
    return "\n".join(lines)


def result_text(result):
    where = "%s:%s: " % (shown(result.file), result.line) if result.file else ""
    from rcl.words.tester import taken_text
    actual = taken_text(result.taken) if result.actual is None else stack_text(result.actual)
    lines = [where + result.message]
    lines.extend("    " + text.strip() for text in result.source)
    lines.append("  expected: " + stack_text(result.expected))
    lines.append("  actual:   " + actual)
    if result.notes:
        lines.append(result.notes)
    return "\n".join(lines)


def stack_text(cells):
    return " ".join(str(c) for c in cells) or "(empty)"


def skip(reason):
    """Skip, reported at the test's own file and line."""
    raise pytest.skip.Exception(reason, _use_item_location=True)


class FailureText(str):
    """A failure's text. Its first line is what the short summary shows
    (pytest 9 finds it in the text; pytest 8, the newest for Python 3.9 and
    PyPy, looks for `reprcrash.message`)."""

    @property
    def reprcrash(self):
        return types.SimpleNamespace(message=self.split("\n", 1)[0])


class ForthItem(pytest.Item):
    def repr_failure(self, excinfo, style=None):
        if isinstance(excinfo.value, ForthTestFailure):
            return FailureText(excinfo.value)
        return super().repr_failure(excinfo, style)


class ForthLoad(ForthItem):
    """The file loads to its end; T{ }T lines with no item of their own pass."""

    def runtest(self):
        run, parent = self.parent.outcome(), self.parent
        if run.output:
            self.add_report_section("call", "rcl output", run.output)
        problems = []
        if run.error is not None and parent.spec_of_error(run) is None:
            problems.append(error_text(parent, run.error))
        problems.extend(result_text(r) for r in run.others if not r.ok)
        if run.redefined:
            problems.append("%s: the file redefines %s (a tester of its own?); rcl has "
                            "them built in and sees only its own: leave that tester out"
                            % (shown(str(self.path)), " ".join(run.redefined)))
        if problems:
            raise ForthTestFailure("\n".join(problems))

    def reportinfo(self):
        return self.path, 0, "%s: load" % self.path.name


class ForthTest(ForthItem):
    """One T{ ... }T of the file."""

    def __init__(self, *, spec, **kwargs):
        super().__init__(**kwargs)
        self.spec = spec

    def runtest(self):
        run, parent, spec = self.parent.outcome(), self.parent, self.spec
        if parent.spec_of_error(run) is spec:
            raise ForthTestFailure(error_text(parent, run.error))
        results = run.results.get((spec.line, spec.column))
        if not results:
            if run.error is not None:
                skip("not reached: the load stopped at %s" % where(run.error))
            skip("T{ on line %d never ran" % spec.line)
        failed = [r for r in results if not r.ok]
        if failed:
            raise ForthTestFailure("\n".join(result_text(r) for r in failed))

    def reportinfo(self):
        return self.path, self.spec.line - 1, "%s: %s" % (self.path.name, self.name)
