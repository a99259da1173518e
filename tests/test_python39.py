"""rcl runs on Python 3.9 too (Debian's pypy3 is 3.9): every module of the
repository parses with 3.9's grammar and uses no annotation 3.9 cannot
evaluate. A cheap guard; .ci/run runs the whole suite under pypy3 as well."""
import ast
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOURCES = sorted(p for d in ("rcl", "tests", "bench") for p in (ROOT / d).rglob("*.py"))


def union_annotations(tree):
    """Annotations written `X | Y`, which 3.9 evaluates and refuses."""
    if any(isinstance(n, ast.ImportFrom) and n.module == "__future__"
           and any(a.name == "annotations" for a in n.names) for n in tree.body):
        return []
    found = []
    for node in ast.walk(tree):
        notes = []
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            notes = [a.annotation for a in node.args.args + node.args.kwonlyargs
                     + node.args.posonlyargs] + [node.returns]
        elif isinstance(node, ast.AnnAssign):
            notes = [node.annotation]
        for note in notes:
            if note is not None and any(isinstance(n, ast.BinOp) and isinstance(n.op, ast.BitOr)
                                        for n in ast.walk(note)):
                found.append(node.lineno)
    return found


def test_there_are_sources_to_check():
    assert len(SOURCES) > 50


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: str(p.relative_to(ROOT)))
def test_every_module_is_python_3_9(path):
    source = path.read_text(encoding="utf-8")
    tree = ast.parse(source, str(path), feature_version=(3, 9))
    assert not union_annotations(tree), "X | Y annotations at lines %s" % union_annotations(tree)
