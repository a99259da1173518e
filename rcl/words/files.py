"""Loading text files: INCLUDE INCLUDED REQUIRE REQUIRED.

A name is looked up beside the file being loaded first, then from the
current directory, then in the RCL screens folder (so that `INCLUDE
examples/listing1.fs` works from any directory once rcl is installed).
Lines may be of any length the input area holds.
"""
import os

from rcl.errors import ForthError, open_source
from rcl.forth import state
from rcl.forth.primitives import CALL, prim

# The folder RCL's screens were loaded from (rcl.open sets it; None: the
# installed ones), where INCLUDE looks last: the session's.
state.session("screens_dir", lambda m: None)
from rcl.words.compiling import parse_word


def resolve(m, name):
    if not name or "\0" in name:
        raise ForthError(-38, "File not found", name.replace("\0", "?"))
    for src in reversed(m.sources):
        if src.kind == "file" and src.name:
            near = os.path.join(os.path.dirname(src.name), name)
            if os.path.exists(near):
                return near
    if os.path.exists(name) or os.path.isabs(name):
        return name
    folder = m.screens_dir or screens_folder()
    there = os.path.join(folder, name)
    return there if os.path.isfile(there) else name


def screens_folder():
    import rcl                      # the package knows where it is installed
    return rcl.SCREENS


def include_file(m, name):
    path = resolve(m, name)
    f = open_source(path, name)
    m.included.add(os.path.abspath(path))
    with f:
        m.include_lines((line.rstrip("\r\n") for line in f), path)


def require_file(m, name):
    if os.path.abspath(resolve(m, name)) not in m.included:
        include_file(m, name)


@prim("INCLUDE", "( -- ) load the file named next", kind=CALL)
def include(m):
    include_file(m, parse_word(m))


@prim("INCLUDED", "( addr u -- ) load the file named by the string", kind=CALL)
def included(m):
    u, a = m.s.pop(), m.s.pop()
    include_file(m, m.memory.text(a, u))


@prim("REQUIRE", "( -- ) load the file named next unless it was loaded", kind=CALL)
def require(m):
    require_file(m, parse_word(m))


@prim("REQUIRED", "( addr u -- ) load the named file unless it was loaded", kind=CALL)
def required(m):
    u, a = m.s.pop(), m.s.pop()
    require_file(m, m.memory.text(a, u))
