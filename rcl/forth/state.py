"""The machine's state, declared: what each word set keeps on the machine,
and the one snapshot of it that the boot copy, the start cache and
SAVE-SYSTEM all take.

Two kinds, each declared next to the words that use it:

    system(name, fresh, save, load)   part of the Forth system: the 64 KiB
        image only makes sense with it (the xts the compiler lays down, the
        word lists, the heap's blocks, REQUIRE's files). A snapshot holds
        it as plain data: save(m) -> JSON-able, load(m, data) puts it back.
    session(name, fresh)              belongs to one run (a trace being
        recorded, the tester's depth, open files): a machine starts with
        fresh(m) and a restored one starts with it again.

    snapshot(m) -> {"memory": bytes, "headers": bytes, name: plain data ...}
    restore(m, snap)                  m becomes that system; its session
                                      state starts fresh; caches rebuilt

Memory is the truth; the snapshot adds only what lives beside it in
Python. The header marks are kept (the name tables are rebuilt from them);
the compiled-code marks are not (compiled code is rebuilt on first use).
"""
from rcl.forth.memory import WATCH_HEADER

SYSTEM = {}      # name -> (fresh, save, load)
SESSION = {}     # name -> fresh
KEEP_HEADER = bytes(range(256)).translate(bytes(b & WATCH_HEADER for b in range(256)))


def _get(name):
    return lambda m: getattr(m, name)


def _set(name):
    return lambda m, data: setattr(m, name, data)


def system(name, fresh, save=None, load=None):
    """Declare system state `name`: fresh(m) its value on a new machine;
    save/load default to the attribute itself (plain data already)."""
    SYSTEM[name] = (fresh, save or _get(name), load or _set(name))


def session(name, fresh):
    """Declare session state `name`: fresh(m) at start and after a restore."""
    SESSION[name] = fresh


def init(m):
    """Every declared field at its fresh value."""
    for name, (fresh, _, _) in SYSTEM.items():
        setattr(m, name, fresh(m))
    for name, fresh in SESSION.items():
        setattr(m, name, fresh(m))


def snapshot(m):
    """The system m is, as plain data (m is not changed)."""
    snap = {name: save(m) for name, (_, save, _) in SYSTEM.items()}
    snap["memory"] = bytes(m.mem)
    snap["headers"] = bytes(m.watch).translate(KEEP_HEADER)
    return snap


def restore(m, snap):
    """Make m the system of snap: memory, header marks, every system field
    (a field snap lacks starts fresh), every session field fresh; the
    stacks emptied, the compiled code and name tables rebuilt."""
    m.mem[:] = snap["memory"]
    m.watch[:] = snap["headers"]
    for name, (fresh, _, load) in SYSTEM.items():
        if name in snap:
            load(m, snap[name])
        else:
            setattr(m, name, fresh(m))
    for name, fresh in SESSION.items():
        setattr(m, name, fresh(m))
    del m.s[:], m.rs[:]
    m.dictionary.cache.clear()
    m.dictionary.generation += 1
    m.invalidate()
