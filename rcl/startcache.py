"""RCL loaded once, started many times: the system `rcl.open()` builds
from the screens, kept for the next open.

Loading the screens interprets some 4,000 words and compiles the words
their loading runs: about 30 ms, a third of `rcl -e BYE`, and a large
part of every test that opens a system. What it leaves is the same each
time (the board and the virtual clock included: rcl.fs ends just after a
tick), so the first open keeps a copy and later ones start from it:

* in the same process, as pickled bytes in memory (the test suite opens
  hundreds of systems);
* across processes, in a file in the user's cache folder ($RCL_CACHE_DIR,
  else $XDG_CACHE_HOME/rcl, else ~/.cache/rcl).

A copy is used only for exactly the code and screens it was made from: its
key lists rcl's version, the Python implementation, the screens folder,
and the name, size and modification time of every file of the rcl package
and of the screens folder; the file stores the key in full and a CRC of
the payload, and anything that does not match (another build, a damaged
or half-written file) is ignored and written again; copies no start has
written for a week (other builds') are removed. The file is trusted
as Python trusts its own __pycache__: both are written by the user's own
account, and a cache folder that cannot be written just means no cache.

What a copy holds: the Forth system as the one snapshot of
rcl/forth/state.py takes it (the memory, its header marks and every
system field a word set declares: what a new machine is copied from at
boot and what SAVE-SYSTEM writes), the machine's time (its clock, the
next housekeeping, the interrupts so far) and count of files included,
and the board, pickled as the load left it. A copy is a new machine
restored from that snapshot, its session state fresh, at that time, on
that board; compiled code is rebuilt on first use (the compiled code and
the reference loop take the same virtual time: tests/test_compiler_*).
The first open returns a copy too, so every system rcl.open() gives
starts the same way.
"""
import io
import os
import pickle
import sys
import time
import zlib

import rcl
from rcl.forth import state
from rcl.forth.machine import Forth

MAGIC = b"RCLSTART2\n"
PACKAGE = os.path.dirname(os.path.abspath(__file__))
_kept = {}                                  # key -> pickled copy, this process
LOADED = ("clock", "hk_next", "interrupts", "file_ids")  # the machine's, as the load left them
STALE_S = 7 * 24 * 3600                     # a copy unused this long is removed


def key(screens_dir):
    """What a copy depends on, as text: any change to rcl or the screens changes it."""
    lines = ["%s %s %s" % (rcl.__version__, sys.implementation.cache_tag,
                           os.path.abspath(screens_dir))]
    for folder in (PACKAGE, os.path.abspath(screens_dir)):
        for root, dirs, files in os.walk(folder):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            for name in sorted(files):
                if name.endswith((".py", ".fs")):
                    path = os.path.join(root, name)
                    st = os.stat(path)
                    lines.append("%s %d %d" % (path, st.st_size, st.st_mtime_ns))
    return "\n".join(lines)


def folder():
    base = os.environ.get("RCL_CACHE_DIR")
    if not base:
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(xdg, "rcl")
    return base


def path_for(k):
    return os.path.join(folder(), "start-%s-%08x.pickle" % (
        sys.implementation.cache_tag, zlib.crc32(k.encode())))


def _new(cls):
    return cls.__new__(cls)


def _set_attributes(obj, state):
    for name, value in state.items():
        setattr(obj, name, value)


class _Pickler(pickle.Pickler):
    """Pickles rcl's own objects so that unpickling sets their attributes
    one by one, as __init__ did, instead of filling in their __dict__ at
    once: on CPython 3.11 an object whose __dict__ was asked for keeps it
    as a plain dict, and every attribute read of the machine and board
    (the tick reads thousands) is slower by a fifth."""

    def reducer_override(self, obj):
        cls = type(obj)
        if cls.__module__.startswith("rcl.") and not isinstance(obj, BaseException) \
                and hasattr(obj, "__dict__"):
            return _new, (cls,), dict(obj.__dict__), None, None, _set_attributes
        return NotImplemented


def snapshot(m):
    """The loaded system m as a copy's bytes: state.snapshot(m), the
    machine's time and its board (m itself is left as it was)."""
    board = m.board
    board.machine = None                    # the board alone, not the machine again
    try:
        out = io.BytesIO()
        _Pickler(out, protocol=pickle.HIGHEST_PROTOCOL).dump(
            (state.snapshot(m), [getattr(m, name) for name in LOADED], board))
        return out.getvalue()
    finally:
        board.machine = m


def restored(data, write):
    """A new machine made from a copy's bytes, writing to `write`."""
    snap, loaded, board = pickle.loads(data)
    m = Forth(write=write, system=snap)
    for name, value in zip(LOADED, loaded):
        setattr(m, name, value)
    m.board = board
    board.attach(m)                         # its interrupts from the copy's time on
    return m


def fetch(k):
    """The pickled system for key k, from this process or the cache file; or None."""
    data = _kept.get(k)
    if data is not None:
        return data
    try:
        with open(path_for(k), "rb") as f:
            blob = f.read()
    except OSError:
        return None
    head = MAGIC + k.encode() + b"\0"
    if not blob.startswith(head) or len(blob) < len(head) + 4:
        return None
    crc, data = blob[len(head):len(head) + 4], blob[len(head) + 4:]
    if int.from_bytes(crc, "little") != zlib.crc32(data):
        return None
    _kept[k] = data
    return data


def keep(k, data):
    """Keep a pickled system under key k, here and (if it can) in the cache file."""
    _kept[k] = data
    try:
        os.makedirs(folder(), exist_ok=True)
        from rcl.safefile import write_atomically
        blob = MAGIC + k.encode() + b"\0" + zlib.crc32(data).to_bytes(4, "little") + data
        write_atomically(path_for(k), lambda f: f.write(blob))
        forget_stale(path_for(k))
    except OSError:
        pass                                # no cache folder: the next start loads again


def forget_stale(keeping, age=STALE_S):
    """Remove copies not written for `age` seconds (other builds' or trees'),
    so that the cache folder does not grow with every change to rcl."""
    now = time.time()
    for entry in os.scandir(os.path.dirname(keeping)):
        if entry.name.startswith("start-") and entry.name.endswith(".pickle") \
                and entry.path != keeping and now - entry.stat().st_mtime > age:
            os.remove(entry.path)


def open_loaded(screens_dir, write, load):
    """A system with RCL loaded from screens_dir: a copy of the one kept, or
    load() -> a machine (with no output callback), kept for next time."""
    k = key(screens_dir)
    m = copy_of(k, fetch(k), write)
    if m is None:
        m = load()
        if m.out:                           # the load said something: not the same
            if write is not None:           # every time, so not kept
                write("".join(m.out))
                del m.out[:]
            m.write = write
            return m
        data = snapshot(m)
        keep(k, data)
        # A copy even the first time: pickling asked the board's objects for
        # their __dict__, which leaves the loaded board slower (see _Pickler).
        m = restored(data, write)
    return m


def copy_of(k, data, write):
    """The system kept in data, or None (no data, or none this code can
    read: it is forgotten, and the screens are loaded again)."""
    if data is None:
        return None
    try:
        return restored(data, write)
    except Exception:                       # noqa: B902  (whatever a stale pickle raises)
        _kept.pop(k, None)
        return None
