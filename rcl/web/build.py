"""Build the static site: the page files of rcl/web, a wheel of the
installed rcl, and the pinned Pyodide core and xterm.js from npm.

    DIR/index.html, app.js, worker.js, sw.js, style.css, ...   the page
    DIR/rcl-VERSION-py3-none-any.whl                          rcl itself
    DIR/pyodide/   pyodide.mjs, pyodide.asm.{mjs,wasm}, python_stdlib.zip, lock
    DIR/xterm/     xterm.mjs, xterm.css
    DIR/site.json  the wheel's name, the files the service worker caches

The wheel is made from the installed package's own files (so it works
from an installed rcl and from a source tree alike): Python modules,
kernel and screens, with a minimal dist-info. The page unpacks it into
Pyodide's site-packages itself (Pyodide's npm package has no micropip).
"""
import base64
import hashlib
import json
import os
import pathlib
import shutil
import subprocess
import tempfile
import zipfile

import rcl

HERE = pathlib.Path(__file__).parent
PAGE_FILES = ("index.html", "app.js", "worker.js", "sw.js", "style.css",
              "view.js", "console.js", "programs.js")
NPM_FILES = ("package.json", "package-lock.json")
PYODIDE_FILES = ("pyodide.mjs", "pyodide.asm.mjs", "pyodide.asm.wasm",
                 "python_stdlib.zip", "pyodide-lock.json")
XTERM_FILES = (("lib/xterm.mjs", "xterm.mjs"), ("css/xterm.css", "xterm.css"))
NPM_MISSING = ("rcl-web build needs node and npm (for the pinned Pyodide and xterm.js): "
               "install them, e.g. `sudo apt-get install nodejs npm`")


class BuildError(rcl.RclError):
    """The site cannot be built (npm missing or failing, a folder not writable)."""


# ------------------------------------------------------------------ the wheel
def package_files():
    """(name in the wheel, path on disk) of everything rcl needs to run: its
    modules and Forth files, the screens under rcl/screens. Not the page,
    not caches."""
    root = pathlib.Path(rcl.__file__).parent
    files = []
    for path in sorted(root.rglob("*")):
        rel = path.relative_to(root)
        if path.is_dir() or "__pycache__" in rel.parts or "node_modules" in rel.parts:
            continue
        if rel.parts[0] == "web" and path.suffix != ".py":
            continue
        if path.suffix in (".py", ".fs") or rel.parts[0] == "screens":
            files.append(("rcl/" + rel.as_posix(), path))
    if not (root / "screens").is_dir():          # a source tree: screens/ beside rcl/
        screens = pathlib.Path(rcl.SCREENS)
        for path in sorted(screens.rglob("*.fs")):
            files.append(("rcl/screens/" + path.relative_to(screens).as_posix(), path))
    return files


def record_line(name, data):
    digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
    return "%s,sha256=%s,%d" % (name, digest, len(data))


def build_wheel(folder):
    """-> the wheel's file name, written into folder."""
    version = rcl.__version__
    info = "rcl-%s.dist-info" % version
    name = "rcl-%s-py3-none-any.whl" % version
    meta = {
        info + "/METADATA": "Metadata-Version: 2.1\nName: rcl\nVersion: %s\n" % version,
        info + "/WHEEL": "Wheel-Version: 1.0\nGenerator: rcl-web\nRoot-Is-Purelib: true\n"
                         "Tag: py3-none-any\n",
    }
    records = []
    with zipfile.ZipFile(os.path.join(folder, name), "w", zipfile.ZIP_DEFLATED) as z:
        for arc, path in package_files():
            data = path.read_bytes()
            z.writestr(zipinfo(arc), data)
            records.append(record_line(arc, data))
        for arc, text in meta.items():
            z.writestr(zipinfo(arc), text)
            records.append(record_line(arc, text.encode()))
        records.append(info + "/RECORD,,")
        z.writestr(zipinfo(info + "/RECORD"), "\n".join(records) + "\n")
    return name


def zipinfo(arc):
    """A fixed date: the same sources make the same wheel."""
    info = zipfile.ZipInfo(arc, date_time=(2026, 1, 1, 0, 0, 0))
    info.compress_type = zipfile.ZIP_DEFLATED
    info.external_attr = 0o644 << 16
    return info


# ---------------------------------------------------------------- npm parts
def npm_modules(work):
    """`npm ci` of the pinned package.json/lock in a temporary copy: ->
    its node_modules folder."""
    npm = shutil.which("npm")
    if npm is None or shutil.which("node") is None:
        raise BuildError(NPM_MISSING)
    for f in NPM_FILES:
        shutil.copyfile(HERE / f, os.path.join(work, f))
    try:
        done = subprocess.run([npm, "ci", "--no-audit", "--no-fund", "--loglevel=error"],
                              cwd=work, capture_output=True, text=True, timeout=600)
    except (OSError, subprocess.TimeoutExpired) as e:
        raise BuildError("npm ci failed: %s" % e) from None
    if done.returncode:
        raise BuildError("npm ci failed:\n" + (done.stderr or done.stdout).strip())
    return pathlib.Path(work) / "node_modules"


def copy_npm_parts(modules, out):
    (out / "pyodide").mkdir(exist_ok=True)
    for f in PYODIDE_FILES:
        shutil.copyfile(modules / "pyodide" / f, out / "pyodide" / f)
    (out / "xterm").mkdir(exist_ok=True)
    for src, dest in XTERM_FILES:
        shutil.copyfile(modules / "@xterm" / "xterm" / src, out / "xterm" / dest)


# -------------------------------------------------------------------- site
def build(folder, modules=None):
    """Build the site into folder (made if missing). `modules`: an
    existing node_modules with the pinned packages, else `npm ci` runs.
    -> the list of the site's files, relative to folder."""
    out = pathlib.Path(folder)
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory(prefix="rcl-web-") as work:
            copy_npm_parts(pathlib.Path(modules) if modules else npm_modules(work), out)
        for f in PAGE_FILES:
            shutil.copyfile(HERE / f, out / f)
        wheel = build_wheel(out)
        files = sorted(p.relative_to(out).as_posix() for p in out.rglob("*")
                       if p.is_file() and p.name not in ("site.json", "sw.js"))
        version = hashlib.sha256("".join(
            f + hashlib.sha256((out / f).read_bytes()).hexdigest() for f in files).encode())
        site = {"wheel": wheel, "version": rcl.__version__,
                "build": version.hexdigest()[:16], "files": files}
        (out / "site.json").write_text(json.dumps(site, indent=1))
    except OSError as e:
        raise BuildError("cannot build into %s: %s" % (folder, e.strerror or e)) from None
    return files + ["site.json"]
