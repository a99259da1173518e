"""SAVE-SYSTEM: the running system as a file to start from (F83's word;
the file's layout is rcl/forth/image.py's). `rcl --image FILE` starts
from it."""
from rcl.errors import ForthError
from rcl.forth.primitives import CALL, prim
from rcl.words.compiling import parse_word


@prim("SAVE-SYSTEM", "( -- ) write the whole system image to the file named next",
      kind=CALL)
def save_system(m):
    from rcl.forth import image         # hashlib, zlib, json: only when saving
    name = parse_word(m)
    try:
        image.save(m, name)
    except image.ImageError as e:
        raise ForthError(-37, str(e)) from None
