"""Writing a file so that no failure leaves it damaged: write a temporary
file beside it, then rename it over the old one (atomic on POSIX and
Windows), so the file is either the old one or the whole new one."""
import os


def temporary_beside(path):
    """-> (fd, name) of a new file in path's folder, with the mode a plain
    open() would give path (mkstemp's is 0600)."""
    import tempfile                     # only when writing (not at every start)
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(prefix=".%s." % os.path.basename(path), dir=folder)
    try:
        mode = os.stat(path).st_mode & 0o777
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        mode = 0o666 & ~umask
    os.chmod(tmp, mode)
    return fd, tmp


def write_atomically(path, write, binary=True):
    """Call write(f) on a temporary file beside path, then put it in path's
    place. Any error (OSError, or whatever write raises) leaves path as it
    was and removes the temporary file."""
    fd, tmp = temporary_beside(path)
    try:
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"newline": ""})) as f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise
