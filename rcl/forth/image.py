"""The system image: what SAVE-SYSTEM writes and `rcl --image` starts from.

F83's SAVE-SYSTEM writes the running system as a program. Here the file
holds everything of the machine that the Forth system is, and nothing of
the board (its 8253s, relays, vector table and clock start afresh):

    offset  size  field
    0       8     magic b"RCLIMAGE"
    8       2     image format (FORMAT), little-endian
    10      16    rcl version, ASCII, NUL-padded
    26      32    build fingerprint: SHA-256 of the primitive table and the
                  memory layout (code fields hold primitive numbers, so an
                  image only runs on the build that made it)
    58      4     payload length in bytes
    62      32    checksum: SHA-256 of bytes 0..61 and the payload
    94      ...   payload, zlib: a 4-byte JSON length, the JSON (the
                  Python-side state), the 64 KiB memory, its header marks

The memory image carries the dictionary, every user variable and RCL's
settings (they are Forth variables); the JSON carries what lives beside
it in Python, the system state each word set declares (rcl/forth/state.py:
the execution tokens the compiler lays down, the FORTH and ROOT word
lists, the files REQUIRE has seen, the block file's name, the primitives'
virtual-time costs, the heap's blocks, REPLACES' table); it is the same
snapshot a new machine is copied from. Compiled code and name caches are
rebuilt.

Reading checks, in order, and refuses with ImageError: the magic (not an
image), the format, the length (truncated), the checksum (damaged), the
version and fingerprint (another build), then the payload's shape.
"""
import hashlib
import json
import os
import stat
import struct
import zlib

from rcl.errors import RclError
from rcl.forth import memory as layout, state
from rcl.forth.memory import SIZE
from rcl.forth.primitives import REGISTRY
from rcl.safefile import write_atomically

MAGIC = b"RCLIMAGE"
FORMAT = 1
HEAD = struct.Struct("<8sH16s32sI")          # magic format version fingerprint length
CHECK = 32
# An image holds the 64 KiB memory, its header marks and a JSON of the
# Python-side state: far less than these, which bound what is read and inflated.
MAX_JSON = 1 << 20
MAX_RAW = 4 + MAX_JSON + 2 * SIZE
MAX_FILE = HEAD.size + CHECK + MAX_RAW + (MAX_RAW >> 8) + 64   # (zlib's worst growth)
MAX_COST = 36_000_000 * 1000            # a primitive of at most a second


class ImageError(RclError):
    """A system image that cannot be written or is refused."""


def version():
    import rcl
    return rcl.__version__


def fingerprint():
    """What an image depends on: every primitive's number, name and kind,
    and the memory layout."""
    from rcl.forth.machine import USER_VARIABLES
    table = ["%d %s %s" % (p.number, p.name, p.kind.value) for p in REGISTRY[1:]]
    table += ["%s %d" % (k, getattr(layout, k)) for k in
              ("USER_AREA", "DICT_START", "DICT_LIMIT", "BLOCK_BUFFERS", "INPUT_AREA")]
    table += USER_VARIABLES
    return hashlib.sha256("\n".join(table).encode()).digest()


# ------------------------------------------------------------------ save
def python_state(snap):
    """The Python-side part of a snapshot (rcl/forth/state.py): what the
    JSON holds."""
    return {k: v for k, v in snap.items() if k not in ("memory", "headers")}


def memory_copy(m, mem):
    """The memory as it should start: interpreting, from the terminal."""
    mem = bytearray(mem)
    for a in (m.a_state, m.a_blk, m.a_in, m.a_ntib):
        mem[a:a + 2] = b"\0\0"
    return bytes(mem)


def encode(m):
    snap = state.snapshot(m)
    meta = json.dumps(python_state(snap)).encode()
    payload = zlib.compress(struct.pack("<I", len(meta)) + meta + memory_copy(m, snap["memory"])
                            + snap["headers"], 9)
    head = HEAD.pack(MAGIC, FORMAT, version().encode()[:16], fingerprint(), len(payload))
    return head + hashlib.sha256(head + payload).digest() + payload


def save(m, path):
    """Write m's system image to path (atomically: old file or new, whole)."""
    data = encode(m)
    try:
        write_atomically(path, lambda f: f.write(data))
    except OSError as e:
        raise ImageError("cannot write %s: %s" % (path, e.strerror)) from None


# ------------------------------------------------------------------ load
def decode(data, name):
    """-> (meta, mem, watch) of an image's bytes, or ImageError."""
    if len(data) < len(MAGIC) + 2 or data[:len(MAGIC)] != MAGIC:
        raise ImageError("%s is not an rcl system image" % name)
    fmt = struct.unpack_from("<H", data, len(MAGIC))[0]
    if fmt != FORMAT:
        raise ImageError("%s was saved by another version of rcl (image format %d, "
                         "this rcl reads %d)" % (name, fmt, FORMAT))
    if len(data) < HEAD.size + CHECK:
        raise ImageError("%s is truncated (%d bytes, not even a header)" % (name, len(data)))
    _, _, ver, fp, length = HEAD.unpack_from(data)
    body = HEAD.size + CHECK
    if len(data) != body + length:
        raise ImageError("%s is truncated (%d bytes of %d)" % (name, len(data), body + length)
                         if len(data) < body + length else
                         "%s is damaged (%d bytes after the image)" % (name, len(data) - body - length))
    if hashlib.sha256(data[:HEAD.size] + data[body:]).digest() != data[HEAD.size:body]:
        raise ImageError("%s is damaged (checksum mismatch)" % name)
    ver = ver.rstrip(b"\0").decode("ascii", "replace")
    if ver != version() or fp != fingerprint():
        raise ImageError("%s was saved by another version of rcl (%s%s); this is rcl %s: "
                         "load your source and SAVE-SYSTEM again"
                         % (name, ver, "" if ver != version() else ", another build", version()))
    return unpack(data[body:], name)


def unpack(payload, name):
    try:
        inflate = zlib.decompressobj()
        raw = inflate.decompress(payload, MAX_RAW + 1)      # never more than an image holds
        if len(raw) > MAX_RAW or inflate.unconsumed_tail:
            raise ValueError("it inflates past %d bytes" % MAX_RAW)
        n = struct.unpack_from("<I", raw)[0]
        meta = json.loads(raw[4:4 + n])
        mem, watch = raw[4 + n:4 + n + SIZE], raw[4 + n + SIZE:]
        if len(mem) != SIZE or len(watch) != SIZE:
            raise ValueError("memory of %d bytes" % len(mem))
        meta = checked_meta(meta)
    except (zlib.error, struct.error, ValueError, KeyError, TypeError, AttributeError,
            RecursionError) as e:
        raise ImageError("%s is damaged (%s)" % (name, e)) from None
    return meta, mem, watch


def checked_meta(meta):
    """The JSON's fields, each of the type and range SAVE-SYSTEM writes, or
    ValueError (a checksum only says the bytes are what was written).
    Images saved before the heap was kept name two fields otherwise."""
    if not isinstance(meta, dict):
        raise ValueError("its state is not a table")
    for old, new in (("block_file", "blocks"), ("costs", "cost")):
        if old in meta:
            meta[new] = meta.pop(old)

    def cell(v, what):
        if type(v) is not int or not 0 <= v <= 0xFFFF:
            raise ValueError("%s is not a cell: %r" % (what, v))
        return v

    def text(v, what):
        if not isinstance(v, str):
            raise ValueError("%s is not text: %r" % (what, v))
        return v

    def table(v, what):
        if not isinstance(v, dict):
            raise ValueError("%s is not a table" % what)
        return v

    def rows(v, what, width):
        if not isinstance(v, list) or not all(isinstance(r, list) and len(r) == width for r in v):
            raise ValueError("%s is not a list of %d-field rows" % (what, width))
        return v

    def line(v, what):
        if v is not None and (type(v) is not int or v < 0):
            raise ValueError("%s is not a line number: %r" % (what, v))
        return v
    included = meta.get("included", [])
    if not isinstance(included, list):
        raise ValueError("included is not a list")
    blocks = meta.get("blocks")
    heap = table(meta.get("heap", {"used": [], "free": []}), "heap")
    checked = dict(meta, **{
        "xt_of": {text(k, "a word's name"): cell(v, k)
                  for k, v in table(meta["xt_of"], "xt_of").items()},
        "forth_wid": cell(meta["forth_wid"], "forth_wid"),
        "root_wid": cell(meta["root_wid"], "root_wid"),
        "included": [text(f, "an included file") for f in included],
        "blocks": None if blocks is None else text(blocks, "blocks"),
        "cost": {text(k, "a primitive's name"): cost(v, k)
                 for k, v in table(meta.get("cost", {}), "cost").items()},
        "replacements": {text(k, "a replaced name"): text(v, "a replacement")
                         for k, v in table(meta.get("replacements", {}), "replacements").items()},
        "heap": {part: [[cell(a, "a heap block"), cell(n, "a heap block's size")]
                        for a, n in rows(heap.get(part, []), "the heap's " + part, 2)]
                 for part in ("used", "free")},
        "locations": [[cell(a, "a source place"), None if f is None else text(f, "a file"),
                       line(n, "a source line")]
                      for a, f, n in rows(meta.get("locations", []), "locations", 3)],
    })
    if "heap_floor" in meta:
        checked["heap_floor"] = cell(meta["heap_floor"], "heap_floor")
    return checked


def cost(v, name):
    if type(v) is not int or not 0 <= v <= MAX_COST:
        raise ValueError("the cost of %s is not a number of clock units: %r" % (name, v))
    return v


def read(path):
    """The file's bytes: a regular file of at most MAX_FILE bytes (a FIFO,
    a device or a huge file is refused before anything is read)."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as e:
        raise ImageError("cannot read %s: %s" % (path, e.strerror)) from None
    with os.fdopen(fd, "rb") as f:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise ImageError("%s is not a regular file (an image is a file "
                             "SAVE-SYSTEM wrote)" % path)
        if info.st_size > MAX_FILE:
            raise ImageError("%s is not an rcl system image (%d bytes; an image "
                             "holds at most %d)" % (path, info.st_size, MAX_FILE))
        try:
            return f.read(MAX_FILE + 1)
        except OSError as e:
            raise ImageError("cannot read %s: %s" % (path, e.strerror)) from None


def load(m, path):
    """Make m the system saved in path. Everything is checked before the
    machine is touched: a refused image leaves m as it was."""
    meta, mem, watch = decode(read(path), path)
    meta["memory"], meta["headers"] = mem, watch
    state.restore(m, meta)
