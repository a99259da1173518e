"""The project's own documents: docs/words.md is generated from the screens'
stack comments and the primitives' declarations and names every word of
RCL's dictionary; HELP, RCL-WORDS and WORDS at the prompt; README and
docs/ point only at files inside the repository."""
import os
import re

import pytest

import rcl
from rcl import docgen, wordinfo
from rcl.forth.primitives import RUNTIME

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


@pytest.fixture(scope="module")
def machine():
    return rcl.open()


def dictionary_names(m):
    d = m.dictionary
    return {d.name_of(lfa + 2) for wid in (m.forth_wid, m.root_wid)
            for lfa in d.lfas(wid)} - {None}


def test_every_word_of_the_rcl_dictionary_is_in_words_md(machine):
    text = open(os.path.join(ROOT, "docs", "words.md"), encoding="utf-8").read()
    listed = {n.replace("\\|", "|") for n in re.findall(r"^\| `(.+?)` \|", text, re.M)}
    assert dictionary_names(machine) - listed == set()


def test_words_md_is_what_docgen_writes_today():
    text = open(os.path.join(ROOT, "docs", "words.md"), encoding="utf-8").read()
    assert text == docgen.generate(), "run: python -m rcl.docgen"


def test_a_screen_word_takes_its_stack_comment_layer_and_line_comment():
    e = wordinfo.lookup("WAIT-UNTIL")
    assert (e.effect, e.where) == ("( d -- )", "Layer 9, time")
    assert e.text == "until the time of day is exactly d (maybe tomorrow)"


def test_a_primitive_takes_its_declaration_and_word_set():
    e = wordinfo.lookup("INCLUDE")
    assert (e.effect, e.where, e.text) == ("( -- )", "files word set", "load the file named next")


def test_a_later_definition_describes_the_word(machine):
    assert wordinfo.lookup("FORWARD").where == "Layer 8, command language"


def test_help_shows_stack_effect_layer_and_description(machine):
    out = machine.evaluate("HELP wait-until")
    assert out == ("\nWAIT-UNTIL  ( d -- )\n  Layer 9, time\n"
                   "  until the time of day is exactly d (maybe tomorrow)\n")


def test_help_alone_shows_the_first_command_and_the_listings(machine):
    out = machine.evaluate("HELP")
    assert "RERB 2 MPH 3.4 FEET FORWARD" in out
    assert "INCLUDE examples/listing1.fs" in out


def test_help_on_a_bare_machine_says_rcl_is_not_loaded():
    assert "RCL is not loaded" in rcl.Forth().evaluate("HELP")


def test_help_of_an_unknown_word_is_f83s_question_mark(machine):
    with pytest.raises(rcl.ForthError) as e:
        machine.evaluate("HELP NOSUCH")
    assert e.value.screen() == "NOSUCH  ? "


def test_help_of_a_users_own_word_points_to_see(machine):
    assert "SEE SQUARE" in machine.evaluate(": SQUARE DUP * ; HELP SQUARE")


def test_rcl_words_lists_the_command_layer(machine):
    out = machine.evaluate("RCL-WORDS")
    assert "Layer 8, command language:\n  RERB  ARM  FORWARD  BACKWARD" in out
    assert "Layer 9, time:\n  MS  SECONDS  MINUTES  BEEP  AM  PM" in out


def test_words_wraps_between_words_within_the_width(machine):
    machine.columns = 40
    try:
        lines = machine.evaluate("WORDS").rstrip("\n").split("\n")
    finally:
        machine.columns = None
    assert len(lines) > 10
    assert all(len(line) <= 40 for line in lines)
    assert not any(line.startswith(" ") or line.endswith(" ") for line in lines)


def markdown_files():
    docs = os.path.join(ROOT, "docs")
    return [os.path.join(ROOT, "README.md")] + [
        os.path.join(docs, n) for n in sorted(os.listdir(docs)) if n.endswith(".md")]


@pytest.mark.parametrize("path", markdown_files(), ids=os.path.basename)
def test_documents_point_only_inside_the_repository(path):
    text = open(path, encoding="utf-8").read()
    assert "shared/" not in text and "/work/" not in text
    for target in re.findall(r"\]\(([^)#\s]+)", text):
        if "://" in target:
            continue
        assert os.path.exists(os.path.join(os.path.dirname(path), target)), target


def test_help_of_a_word_the_user_defined_again_says_so():
    m = rcl.open()
    out = m.evaluate(": FORWARD 1 ; HELP FORWARD")
    assert "Layer 8, command language" in out
    assert "defined again since start-up: SEE FORWARD shows this one" in out


@pytest.mark.parametrize("path", ["README.md", os.path.join("docs", "guide.md")])
def test_the_first_commands_pose_in_the_documents_is_what_rcl_prints(path):
    text = open(os.path.join(ROOT, path), encoding="utf-8").read()
    shown = re.search(r"^\s+\.POSE (x .*?deg)  ok$", text, re.M).group(1)
    out = rcl.open().evaluate("RERB 2 MPH 3.4 FEET FORWARD .POSE")
    assert out.strip() == shown


def screen_files():
    return sorted(os.path.join(d, n) for d, _, names in os.walk(os.path.join(ROOT, "screens"))
                  for n in names if n.endswith(".fs"))


@pytest.mark.parametrize("path", screen_files(), ids=os.path.basename)
def test_the_screens_cite_only_documents_that_ship(path):
    text = open(path, encoding="utf-8").read()
    for cited in re.findall(r"[\w./-]+\.md\b", text):
        assert os.path.exists(os.path.join(ROOT, cited)), cited


def test_the_saving_examples_pose_is_what_rcl_prints(tmp_path):
    """docs/saving.md: a word saved with SAVE-SYSTEM, run from --image."""
    import subprocess
    import sys
    text = open(os.path.join(ROOT, "docs", "saving.md"), encoding="utf-8").read()
    shown = re.search(r'-e "HOME \.POSE BYE"\n\s+(x .*?deg)\n', text).group(1)
    env = dict(os.environ, PYTHONPATH=ROOT)
    run = lambda *a, **k: subprocess.run([sys.executable, "-m", "rcl", *a], cwd=tmp_path,  # noqa: E731
                                         env=env, capture_output=True, text=True, **k)
    run(input=": HOME  RERB 2 FEET BACKWARD ;  SAVE-SYSTEM robot.img\n")
    assert run("--image", "robot.img", "-e", "HOME .POSE BYE", input="").stdout.strip() == shown


def words_md_rows():
    """(name, stack effect) of every row of docs/words.md."""
    text = open(os.path.join(ROOT, "docs", "words.md"), encoding="utf-8").read()
    return [(n.replace("\\|", "|"), e.replace("\\|", "|"))
            for n, e in re.findall(r"^\| `(.+?)` \| `(.*?)` \|", text, re.M)]


def test_every_entry_of_words_md_is_the_words_own(machine):
    """The dictionary says what each word is: a primitive's row carries its
    declaration; a word defined in Forth, its own defining line (the file
    and line the machine recorded when it defined the word), with the stack
    comment right after its name there."""
    from rcl.forth.memory import PRIM_LIMIT
    from rcl.forth.primitives import REGISTRY
    from rcl.forth.wordloc import defined_at
    wrong = []
    for name, effect in words_md_rows():
        hit = machine.dictionary.find(name)
        if hit is None:
            continue                          # (a word of another vocabulary)
        xt, entry = hit[0], wordinfo.lookup(name)
        cf = machine.memory.fetch(xt)
        p = REGISTRY[cf] if cf < PRIM_LIMIT else None
        if p is not None and (p.kind is not RUNTIME or p.name == name):   # (BREAK) is a runtime
            if (p.name, wordinfo.split_effect(p.effect)[0]) != (name, effect):
                wrong.append((name, effect, p.name, p.effect))
            continue
        file, line = defined_at(machine, xt)
        if file is None:                      # laid down at boot: FORTH, BASE ...
            if entry.where not in ("vocabulary", "system variable"):
                wrong.append((name, effect, "no place"))
            continue
        said = (os.path.realpath(entry.file), entry.line, entry.effect)
        if said != (os.path.realpath(file), line, effect):
            wrong.append((name, effect, entry.file, entry.line, file, line))
            continue
        text = open(file, encoding="latin-1").read().split("\n")[line - 1]
        after = re.search(r"(?i)(?:^|\s)%s(\s+\(\s[^)]*\))?" % re.escape(name), text)
        if after is None or (after.group(1) and after.group(1).strip() != effect):
            wrong.append((name, effect, text))
    assert wrong == []


@pytest.mark.parametrize("name", ["OVER", "HERE", "EMIT", ";", "WORDS"])
def test_help_of_a_word_used_inside_other_definitions_is_its_own(machine, name):
    out = machine.evaluate("HELP %s" % name)
    assert out.startswith("\n%s  ( " % name) and "word set" in out and "defined as" not in out
