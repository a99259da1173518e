"""Files and images that would exhaust memory or wait forever get a clear
refusal, with memory bounded: FIFOs and devices are refused before a read,
an image's size and inflated size are checked before reading or inflating,
every field of an image is checked, READ-LINE reads at most its buffer,
a block file is read a block at a time, and MORE on a full disk leaves the
file as it was."""
import errno
import hashlib
import json
import os
import struct
import subprocess
import sys
import zlib

import pytest

import rcl
from rcl.forth import image
from rcl.forth.image import ImageError

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(*args, stdin="", limit_mb=None):
    """python -m rcl ARGS, optionally under an address-space limit."""
    env = dict(os.environ, PYTHONPATH=ROOT)
    pre = None
    if limit_mb:
        def pre():
            import resource
            resource.setrlimit(resource.RLIMIT_AS, (limit_mb << 20, limit_mb << 20))
    done = subprocess.run([sys.executable, "-m", "rcl", *args], input=stdin, env=env,
                          capture_output=True, text=True, timeout=120, preexec_fn=pre)
    assert "Traceback" not in done.stdout + done.stderr
    assert "MemoryError" not in done.stdout + done.stderr
    assert "internal error" not in done.stderr.lower() + done.stdout.lower()
    return done


def sparse(path, size):
    with open(str(path), "wb") as f:
        f.truncate(size)
    return str(path)


def test_an_image_that_is_a_fifo_or_a_device_is_refused_at_once(tmp_path):
    fifo = str(tmp_path / "fifo")
    os.mkfifo(fifo)
    for path in (fifo, "/dev/zero"):
        done = run("--image", path)
        assert done.stderr == "rcl: --image: %s is not a regular file (an image is a " \
                              "file SAVE-SYSTEM wrote)\n" % path
        assert done.returncode == 2


def test_a_2_gib_image_is_refused_before_it_is_read(tmp_path):
    path = sparse(tmp_path / "big.img", 2 << 30)
    done = run("--image", path, limit_mb=1024)
    assert "is not an rcl system image (2147483648 bytes" in done.stderr
    assert done.returncode == 2


def signed_image(meta=None, payload=None):
    """Image bytes with a valid header and checksum around payload (or a
    payload of meta and blank memory)."""
    if payload is None:
        js = json.dumps(meta).encode()
        payload = zlib.compress(struct.pack("<I", len(js)) + js + bytes(2 * 65536))
    head = image.HEAD.pack(image.MAGIC, image.FORMAT, image.version().encode()[:16],
                           image.fingerprint(), len(payload))
    return head + hashlib.sha256(head + payload).digest() + payload


def test_a_zlib_bomb_is_refused_without_inflating_it():
    bomb = zlib.compress(bytes(200 << 20), 9)            # about 200 KB of payload
    with pytest.raises(ImageError, match="damaged .it inflates past"):
        image.decode(signed_image(payload=bomb), "bomb.img")


GOOD = {"xt_of": {"DUP": 300}, "forth_wid": 1000, "root_wid": 1002, "included": [],
        "block_file": None, "costs": {}}


@pytest.mark.parametrize("field,value", [("costs", {"DUP": "x"}), ("included", 5),
                                         ("costs", {"DUP": -1}), ("xt_of", {"DUP": 70000}),
                                         ("forth_wid", "a"), ("block_file", 7),
                                         ("xt_of", [1, 2]), ("root_wid", None)])
def test_every_field_of_an_image_is_checked(field, value):
    meta = dict(GOOD, **{field: value})
    with pytest.raises(ImageError, match="is damaged"):
        image.decode(signed_image(meta), "bad.img")


def test_a_valid_meta_passes_the_checks():
    meta, mem, watch = image.decode(signed_image(GOOD), "good.img")
    assert (meta["xt_of"], len(mem), len(watch)) == ({"DUP": 300}, 65536, 65536)


def test_an_image_whose_block_file_is_dev_zero_starts_without_it(tmp_path):
    m = rcl.Forth()
    m.evaluate("SAVE-SYSTEM %s" % (tmp_path / "a.img"))
    data = image.read(str(tmp_path / "a.img"))
    meta, mem, watch = image.decode(data, "a.img")
    meta["block_file"] = "/dev/zero"
    js = json.dumps(meta).encode()
    payload = zlib.compress(struct.pack("<I", len(js)) + js + mem + watch)
    path = tmp_path / "z.img"
    path.write_bytes(signed_image(payload=payload))
    done = run("--bare", "--image", str(path), stdin="2 3 + .\n", limit_mb=1024)
    assert (done.stdout, done.returncode) == ("5 \n", 0)


@pytest.mark.parametrize("word", ["INCLUDE", "USING"])
def test_include_and_using_refuse_dev_zero_and_a_fifo(word, tmp_path):
    fifo = str(tmp_path / "fifo")
    os.mkfifo(fifo)
    done = run(stdin="%s /dev/zero\n%s %s\n2 3 + .\n" % (word, word, fifo))
    lines = done.stdout.split("\n")
    assert "not a regular file" in lines[0] and "not a regular file" in lines[1]
    assert lines[2] == "5 "


def test_read_line_reads_at_most_its_buffer_from_a_huge_line(tmp_path):
    path = sparse(tmp_path / "zeros", 1536 << 20)        # no line end in 1.5 GB
    done = run("--bare", stdin='S" %s" R/O OPEN-FILE DROP  HERE 40000 ROT READ-LINE . . U.\n'
               % path, limit_mb=1024)
    assert done.stdout == "0 -1 40000 \n"


def test_using_a_512_mib_block_file_reads_it_a_block_at_a_time(tmp_path):
    path = sparse(tmp_path / "big.blk", 512 << 20)
    done = run("--bare", stdin="USING %s  500000 BLOCK C@ .\n" % path, limit_mb=640)
    assert done.stdout == "0 \n"


class FullDisk:
    """A real file whose writes stop after `room` bytes with ENOSPC, as a
    full file system's do."""

    def __init__(self, f, room):
        self.f, self.room = f, room

    def write(self, data):
        self.f.write(data[:self.room])
        self.f.flush()
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    def __getattr__(self, name):
        return getattr(self.f, name)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.f.close()


def test_more_on_a_full_disk_reports_it_and_leaves_the_file_as_it_was(tmp_path, monkeypatch):
    from rcl.words import blocks
    path = str(tmp_path / "s.blk")
    m = rcl.Forth()
    m.evaluate("2 CREATE-BLOCKS %s" % path)
    monkeypatch.setattr(blocks, "open_file", lambda p, mode: FullDisk(open(p, mode), 3000))
    with pytest.raises(rcl.ForthError, match="No space left on device"):
        m.evaluate("10 MORE")
    assert os.path.getsize(path) == 2 * 1024
    monkeypatch.undo()
    with pytest.raises(rcl.ForthError, match="Block 2 out of range"):
        m.evaluate("2 BLOCK DROP")                    # still 2 blocks, nothing lost
    m.evaluate("1 BLOCK DROP  3 MORE  4 BLOCK DROP")  # and MORE works again
