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


class ImageError(RclError):
    """A system image that cannot be written or is refused."""


def version():
    import rcl
    return rcl.__version__


def fingerprint():
    """What an image depends on: every primitive's number, name and kind,
    and the memory layout."""
    from rcl.forth.machine import USER_VARIABLES
    table = ["%d %s %s" % (p.number, p.name, p.kind) for p in REGISTRY[1:]]
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
        raw = zlib.decompress(payload)
        n = struct.unpack_from("<I", raw)[0]
        meta = json.loads(raw[4:4 + n])
        mem, watch = raw[4 + n:4 + n + SIZE], raw[4 + n + SIZE:]
        if len(mem) != SIZE or len(watch) != SIZE:
            raise ValueError("memory of %d bytes" % len(mem))
        meta["xt_of"] = {str(k): int(v) for k, v in meta["xt_of"].items()}
        meta["forth_wid"], meta["root_wid"] = int(meta["forth_wid"]), int(meta["root_wid"])
    except (zlib.error, struct.error, ValueError, KeyError, TypeError, AttributeError) as e:
        raise ImageError("%s is damaged (%s)" % (name, e)) from None
    return meta, mem, watch


def read(path):
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as e:
        raise ImageError("cannot read %s: %s" % (path, e.strerror)) from None


def load(m, path):
    """Make m the system saved in path. Everything is checked before the
    machine is touched: a refused image leaves m as it was."""
    meta, mem, watch = decode(read(path), path)
    for old, new in (("block_file", "blocks"), ("costs", "cost")):   # before the heap was kept
        if old in meta:
            meta[new] = meta.pop(old)
    meta["memory"], meta["headers"] = mem, watch
    state.restore(m, meta)
