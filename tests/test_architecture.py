"""The layers of docs/ARCHITECTURE.md and which may import which, read from
the sources (ast, nothing run): the Forth machine knows no board but the
interface, only the code that builds a simulated board imports rcl.sim,
and the link knows no RCL word and no 80188 address of its own. Also: rcl
imports and drives the robot with none of its optional packages."""
import ast
import pathlib
import re
import subprocess
import sys
import textwrap

import rcl
from rcl import i80188

PACKAGE = pathlib.Path(rcl.__file__).parent
ROOT = PACKAGE.parent
SCREENS = pathlib.Path(rcl.SCREENS)

# Outside rcl/sim, the modules that build a simulated board (and its observer).
BUILDS_A_SIMULATED_BOARD = {
    "rcl/__init__.py",            # rcl.open(): SimBoard, Sim, Pacer
    "rcl/hw/server.py",           # rcl-board and rclsim://: a SimBoard behind a link
    "rcl/hw/boardcli.py",         # rcl-board's command line: the server and its Sim
    "rcl/testing/moves.py",       # RecordingBoard, the SimBoard of rcl.testing's robots
    "rcl/web/session.py",         # the page's simulated board: its pace and per-tick frames
}
OPTIONAL = ("prompt_toolkit", "serial", "usb")


def modules(folder=""):
    """-> {path relative to the repository: [imported module names]}."""
    found = {}
    for path in sorted((PACKAGE / folder).rglob("*.py")):
        names = []
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module:
                names.append(node.module)
                names += ["%s.%s" % (node.module, a.name) for a in node.names]
            elif isinstance(node, ast.Import):
                names += [a.name for a in node.names]
        found[path.relative_to(ROOT).as_posix()] = names
    return found


def reaches(names, package):
    return [n for n in names if n == package or n.startswith(package + ".")]


def test_the_forth_machine_and_its_word_sets_import_nothing_of_a_board_but_the_interface():
    for folder in ("forth", "words"):
        for path, names in modules(folder).items():
            assert not reaches(names, "rcl.sim") and not reaches(names, "rcl.hw"), path


def test_the_boards_import_nothing_of_the_forth_machine():
    for folder in ("sim", "hw"):
        for path, names in modules(folder).items():
            assert not reaches(names, "rcl.forth") and not reaches(names, "rcl.words"), path


def test_outside_rcl_sim_only_the_code_that_builds_a_simulated_board_imports_it():
    importers = {path for path, names in modules().items()
                 if not path.startswith("rcl/sim/") and reaches(names, "rcl.sim")}
    assert importers == BUILDS_A_SIMULATED_BOARD


def screen_words():
    """Every name the screens define (colon words, variables, constants, CODE)."""
    words = set()
    for path in SCREENS.glob("*.fs"):
        words.update(re.findall(r"(?:^|\s)(?::|VARIABLE|2VARIABLE|CONSTANT|2CONSTANT|CODE|"
                                r"VALUE|DEFER|CREATE|WHEEL:)\s+(\S+)", path.read_text()))
    return {w for w in words if len(w) > 1 and w.upper() == w and not w.isdigit()}


def test_the_link_knows_no_rcl_word_and_no_80188_address_of_its_own():
    # RCL's words (its tick script included) are rcl/words' and the
    # screens'; the 80188's PCB and BIOS addresses are rcl/i80188.py's.
    words = screen_words()
    assert {"INSTALL", "?CNT1", "MOVING", "CONTROL"} <= words
    addresses = {i80188.PCB_BASE + r for r in (
        i80188.EOI_REG, i80188.MASK_REG, i80188.IN_SERVICE_REG, i80188.REQUEST_REG,
        i80188.STATUS_REG, i80188.TIMER_CONTROL_REG, i80188.T0_COUNT, i80188.T0_MAX_A,
        i80188.T0_MAX_B, i80188.T0_CONTROL)}
    addresses |= {i80188.PCB_BASE, i80188.BIOS_SEG, i80188.BIOS_TIMER, i80188.BIOS_IRET,
                  i80188.TICKS_ADDR, i80188.MIDNIGHT_ADDR, i80188.PER_DAY_ADDR}
    for path in sorted((PACKAGE / "hw").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Constant) and isinstance(node.value, str):
                assert node.value not in words, (path, node.lineno, node.value)
            if isinstance(node, ast.Constant) and type(node.value) is int:
                assert node.value not in addresses, (path, node.lineno, hex(node.value))
        assert not reaches(modules("hw")[path.relative_to(ROOT).as_posix()], "rcl.words")


def test_rcl_imports_and_drives_the_robot_without_its_optional_packages():
    # The browser has none of them: rcl.open() and a move must not need them.
    program = textwrap.dedent("""
        import sys

        class Absent:
            def find_spec(self, name, path=None, target=None):
                if name.split(".")[0] in %r:
                    raise ImportError("no " + name)

        sys.meta_path.insert(0, Absent())
        import rcl
        m = rcl.open()
        m.evaluate("RERB 1 FEET FORWARD")
        print(m.sim.wheel_counts, sorted(set(sys.modules) & set(%r)))
    """ % (OPTIONAL, OPTIONAL))
    run = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                         cwd=str(ROOT), timeout=300)
    assert run.returncode == 0, run.stderr
    counts, loaded = run.stdout.rsplit(" [", 1)
    assert loaded.strip() == "]"                  # none of them was loaded
    m = rcl.open()
    m.evaluate("RERB 1 FEET FORWARD")
    assert counts == str(m.sim.wheel_counts)      # the same move as with them


def code_strings(path):
    """The string constants of a module's code, its docstrings left out."""
    tree = ast.parse(path.read_text())
    docs = {id(node.body[0].value) for node in ast.walk(tree)
            if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef))
            and node.body and isinstance(node.body[0], ast.Expr)
            and isinstance(node.body[0].value, ast.Constant)}
    return [node.value for node in ast.walk(tree)
            if isinstance(node, ast.Constant) and isinstance(node.value, str)
            and id(node) not in docs]


def test_the_idle_rule_is_the_screens_alone():
    # IDLE? (screens/90-time.fs) is the one rule of when every tick's
    # handler would only read: (MS) asks that word, and no Python module of
    # the machine, its word sets or the simulated board reads what it reads.
    read_by_idle = ("MOVING", "ARM-BITS", "STOCK-CONTROL", "STOCK?")
    assert all(w in screen_words() | {"STOCK?"} for w in read_by_idle)
    for folder in ("forth", "words", "sim"):
        for path in sorted((PACKAGE / folder).rglob("*.py")):
            for text in code_strings(path):
                assert not any(w in text.split() for w in read_by_idle), (path, text)


def test_the_simulated_board_wires_the_8253s_through_the_chips_interface():
    # rcl/sim/i8253.py: clk(i), port(i), write_control, out_frequency;
    # the board reaches no counter inside a chip.
    tree = ast.parse((PACKAGE / "sim" / "board.py").read_text())
    reached = [node.lineno for node in ast.walk(tree)
               if isinstance(node, ast.Attribute) and node.attr == "counters"]
    assert reached == []
