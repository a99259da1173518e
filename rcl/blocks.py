"""Block files and text files, one into the other.

    python -m rcl.blocks FILE.fs FILE.blk     text -> block file
    python -m rcl.blocks FILE.blk FILE.fs     block file -> text

A block file is F83's: 1024-byte blocks, each shown as a screen of 16
lines of 64 characters, no line ends stored. Text becomes screens as F83
users laid them out: screen 0 is left for a title (line 0 names the
file), the text begins at screen 1, 16 lines a screen, so `1 n THRU`
loads it all. A line longer than 64 columns (tabs expand to 8) is
refused with its line number, never cut. Back to text, screens 1 on give
the lines, trailing blanks and trailing empty lines dropped; screen 0 is
the title and has no place in the text (the tool says so if it holds
more than its line 0).

An existing output file is never overwritten (say --force to allow it).
"""
import argparse
import os
import sys

BLOCK = 1024
LINE = 64
LINES = 16


class BlockFormatError(ValueError):
    """Text that cannot become screens: the offending line numbers."""

    def __init__(self, name, lines):
        self.lines = lines
        shown = ", ".join(str(n) for n in lines[:10]) + (" ..." if len(lines) > 10 else "")
        super().__init__("%s: line%s %s longer than %d columns"
                         % (name, "s" if len(lines) > 1 else "", shown, LINE))


def text_lines(text):
    return [line.expandtabs(8) for line in text.splitlines()]


def text_to_blocks(text, name="text"):
    """The block file (bytes) for text: title screen 0, text from screen 1."""
    lines = text_lines(text)
    long = [i + 1 for i, line in enumerate(lines) if len(line) > LINE]
    if long:
        raise BlockFormatError(name, long)
    title = ("\\ %s" % os.path.basename(name))[:LINE]
    body = [title] + [""] * (LINES - 1) + lines
    body += [""] * (-len(body) % LINES)
    return b"".join(line.ljust(LINE).encode("latin-1", "replace") for line in body)


def screen_lines(data, n):
    """The 16 lines of screen n, trailing blanks dropped."""
    block = data[n * BLOCK:(n + 1) * BLOCK].decode("latin-1")
    return [block[i:i + LINE].rstrip() for i in range(0, BLOCK, LINE)]


def blocks_to_text(data):
    """-> (text of screens 1 on, screen 0's lines past its title line)."""
    count = len(data) // BLOCK
    lines = [line for n in range(1, count) for line in screen_lines(data, n)]
    while lines and not lines[-1]:
        lines.pop()
    extra = [line for line in screen_lines(data, 0)[1:] if line] if count else []
    return "".join(line + "\n" for line in lines), extra


def is_block_file(path, raw):
    """A .blk or .scr name, or content with no line end in it."""
    return os.path.splitext(path)[1].lower() in (".blk", ".scr") or b"\n" not in raw


def convert(src, dst, force=False):
    """Convert src to dst (the direction from src's kind); -> notes to show."""
    if os.path.exists(dst) and not force:
        raise FileExistsError("%s exists (--force to replace it)" % dst)
    with open(src, "rb") as f:
        raw = f.read()
    if is_block_file(src, raw):
        text, extra = blocks_to_text(raw)
        out = text.encode("latin-1")
        notes = ["screen 0 (the title) is not in the text: " + " | ".join(extra)] if extra else []
    else:
        out = text_to_blocks(raw.decode("latin-1"), src)
        notes = ["%d screens: 0 the title, 1-%d the text (1 %d THRU loads it)"
                 % (len(out) // BLOCK, len(out) // BLOCK - 1, len(out) // BLOCK - 1)]
    with open(dst, "wb") as f:
        f.write(out)
    return notes


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python -m rcl.blocks",
                                 description="Convert a text file to an F83 block file "
                                 "(1024-byte screens) or a block file back to text.")
    ap.add_argument("source", help="a text file (.fs ...) or a block file (.blk)")
    ap.add_argument("target", help="the file to write")
    ap.add_argument("--force", action="store_true", help="replace the target if it exists")
    args = ap.parse_args(argv)
    try:
        for note in convert(args.source, args.target, args.force):
            print(note)
    except (OSError, ValueError) as exc:
        print("rcl.blocks: %s" % exc, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
