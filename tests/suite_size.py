"""How much of the long, random and soak tests a run does: all of it in
CI (CI set, as .ci/run sets it), a part in a default run, so that
`python3 -m pytest` stays quick (docs/testing.md, "What CI adds"). A
part is the first examples of the same seeded sequence, never others."""
import os

FULL = bool(os.environ.get("CI"))


def scaled(in_ci, by_default):
    """in_ci under CI, else by_default."""
    return in_ci if FULL else by_default
