"""The `rcl` command line: choose a machine, load files, run words, then
read standard input, either at an interactive prompt or as a pipe.

    rcl [FILE ...] [-e WORDS] [--bare] [--board-only] [--realtime]
        [--start HH:MM|now] [--screens DIR] [--image FILE] [--trace CSV]
        [--plot PNG] [--version] [--help]

    make_machine(args) --> load FILEs in order --> run each -e WORDS
        --> stdin is a terminal?  yes: repl.Repl (the ok prompt)
                                  no:  run_pipe (plain source, no prompts)

Exit status: 0 at the end of input or on BYE, 1 if an error happened
outside the interactive prompt (a FILE, a -e, a piped line), 2 for a bad
command line. Nothing here ever lets a Python traceback reach the user.
"""
import signal
import sys
import threading


def leave_quietly(signum, frame):
    raise SystemExit(128 + signum)


# Ctrl-C while rcl loads (the machine, the words, the board: some 0.4 s)
# leaves with status 130 and no traceback; nothing runs yet to stop.
_loading = threading.current_thread() is threading.main_thread() \
    and signal.getsignal(signal.SIGINT) is signal.default_int_handler
if _loading:
    signal.signal(signal.SIGINT, leave_quietly)
try:
    import argparse
    import contextlib
    import io
    import os

    import rcl
    import rcl.forth.machine  # noqa: F401  (the heavy part, while Ctrl-C is quiet)
    from rcl import repl
    from rcl.forth import wordloc
    from rcl.terminal import is_dumb
finally:
    if _loading:
        signal.signal(signal.SIGINT, signal.default_int_handler)

BANNER = ("rcl %s \N{EM DASH} an F83-style Forth for the R-E Robot (%s). "
          "BYE to leave, #help for the prompt's commands.")


def version():
    try:
        from importlib.metadata import version as dist_version
        return dist_version("rcl")
    except Exception:
        return getattr(rcl, "__version__", "0.1.0")   # a source tree, not installed


# ------------------------------------------------------------------ output
CLEAR_SCREEN = "\x1b[2J\x1b[H"     # ANSI: erase the screen, cursor to the top left


class Output:
    """The machine's output stream, plus the text on the current screen line.

    The prompt needs that text (`tail`) to draw the user's line after it,
    the F83 way; the pipe needs nothing but the text itself.
    """

    def __init__(self, stream, flush_each, clears=False):
        self.stream = stream
        self.flush_each = flush_each
        self.clears = clears      # a terminal: PAGE's form feed clears the screen
        self.tail = ""

    def write(self, text):
        if self.clears and "\f" in text:
            # A terminal shows a form feed as a line feed at best; a file or
            # a pipe keeps it, the page break it is.
            text = text.replace("\f", CLEAR_SCREEN)
        self.send(text, self.flush_each)
        cut = max(text.rfind(end) + len(end) if end in text else 0
                  for end in ("\n", "\r", CLEAR_SCREEN))
        self.tail = text[cut:] if cut > 0 else (self.tail + text)[-4096:]

    def redraw(self, text):
        """Write text the screen already held (it does not move the tail)."""
        self.send(text, True)

    def send(self, text, flush):
        try:
            self.stream.write(text)
            if flush:
                self.stream.flush()
        except BrokenPipeError:
            raise StdoutClosed() from None
        except (OSError, ValueError) as e:          # disk full, closed: say so
            raise StdoutClosed(getattr(e, "strerror", None) or str(e)) from None

    def end_line(self):
        if self.tail:
            self.write("\n")

    def flush(self):
        self.send("", True)


class StdoutClosed(BaseException):
    """Standard output cannot be written: whoever read it went away (`rcl
    ... | head`: leave quietly), or the system refused (the reason given:
    say it). Not an Exception, so the machine's error handling lets it
    through to main."""


class LineFeed:
    """Piped standard input as the machine's keyboard: whole lines for the
    interpreter and ACCEPT, single characters for KEY (Enter reads as 13)."""

    def __init__(self, stream):
        self.stream = stream
        self.pending = ""         # the rest of a line KEY has started

    def line(self):
        text, self.pending = self.pending or self.stream.readline(), ""
        return text.rstrip("\r\n") if text else None

    def key(self):
        if not self.pending:
            self.pending = self.stream.readline()
            if not self.pending:
                raise rcl.ForthError(-39, "No input")
        c, self.pending = self.pending[0], self.pending[1:]
        return 13 if c == "\n" else ord(c)


# ----------------------------------------------------------------- machine
def make_machine(args, write):
    """The machine the command line drives: the simulated board with RCL
    (rcl.open), the board alone (--board-only), or plain Forth (--bare);
    from a saved system with --image; its time of day from --start."""
    ImageError = ()                     # catches nothing: no image to refuse
    if args.image:                      # (image.py's hashing is not loaded otherwise)
        from rcl.forth.image import ImageError, load
    try:
        if args.bare:
            m = rcl.Forth(write=write)
            if args.image:
                load(m, args.image)
            return m
        if args.port or args.usb:
            m = open_on_link(args, write)
        else:
            screens = False if args.board_only else (args.screens or True)
            m = rcl.open(write=write, realtime=args.realtime, screens=screens, image=args.image)
    except ImageError as e:
        sys.stderr.write("rcl: --image: %s\n" % e)
        raise SystemExit(2) from None
    except rcl.ForthError as e:         # the user's screens (--screens) or image failed
        sys.stderr.write(where(e, "--image" if args.image else "--screens") + "\n")
        raise SystemExit(1) from None
    if args.start is not None:
        set_time_of_day(m, args.start)
    return m


def describe(args):
    if args.port or args.usb:
        return "board on %s" % (args.port or "USB " + args.usb)
    if args.bare:
        return "bare machine"
    return "simulated board" + (", no RCL screens" if args.board_only else "")


def start_time(text):
    """--start: `HH:MM` (24-hour) or `now` -> seconds after midnight."""
    if text.lower() == "now":
        import datetime                 # only for --start now (kept out of start-up)
        t = datetime.datetime.now().time()
        return t.hour * 3600 + t.minute * 60 + t.second
    try:
        hh, mm = text.split(":")
        hh, mm = int(hh), int(mm)
    except ValueError:
        hh = mm = -1
    if not (0 <= hh < 24 and 0 <= mm < 60):
        raise argparse.ArgumentTypeError("%r is not HH:MM (24-hour) or now" % text)
    return hh * 3600 + mm * 60


def set_time_of_day(m, seconds):
    """The BIOS time of day, in ticks of the rate it counts at now (on any
    board: the simulated one, or one over a link)."""
    _, per_day = m.board.time_of_day()
    m.board.set_time_of_day(seconds * per_day // 86400)


def screens_dir(text):
    if not os.path.isfile(os.path.join(text, "rcl.fs")):
        raise argparse.ArgumentTypeError("%s holds no rcl.fs (RCL's load screen)" % text)
    return text


def find_file(path, m):
    """A FILE of the command line: where named, else in the screens folder
    (`rcl examples/listing1.fs` from any directory)."""
    if os.path.exists(path) or os.path.isabs(path):
        return path
    there = os.path.join(getattr(m, "screens_dir", None) or rcl.SCREENS, path)
    return there if os.path.isfile(there) else path


def add_link_args(p):
    """--port, --usb, --list-ports: a board on a link (rcl.hw)."""
    link = p.add_mutually_exclusive_group()
    link.add_argument("--port", metavar="URL",
                      help="drive a board on a serial port or URL (/dev/ttyUSB0, "
                           "socket://127.0.0.1:7000, usb://1209:0001, usb://sim, rclsim://)")
    link.add_argument("--usb", metavar="VID:PID",
                      help="the same as --port usb://VID:PID (bulk endpoints)")
    p.add_argument("--list-ports", action="store_true",
                   help="list serial ports and USB boards, then leave")


def open_on_link(args, write):
    """RCL on the board at --port or --usb; a refusal, or the link lost
    while RCL loads, is said and exits 2."""
    from rcl.hw.protocol import LinkError
    try:
        return rcl.open(write=write, port=args.port, usb=args.usb, image=args.image)
    except LinkError as e:
        sys.stderr.write("rcl: %s\n" % e)
        raise SystemExit(2) from None
    except rcl.ForthError as e:          # e.g. Link lost while RCL loads: said, not "internal"
        sys.stderr.write("rcl: loading RCL onto the board: %s\n" % e)
        raise SystemExit(2) from None


def list_ports():
    from rcl.hw.connect import list_ports as lines
    for line in lines():
        print(line)
    return 0


# --------------------------------------------------------------- arguments
class VersionAction(argparse.Action):
    """--version: the version looked up only when asked (importlib.metadata
    alone costs a sixth of the start-up)."""

    def __init__(self, option_strings, dest, **kwargs):
        super().__init__(option_strings, dest, nargs=0,
                         help="show program's version number and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        print("rcl " + version())
        parser.exit()


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="rcl", description="RCL, an F83-style Forth for the 1986 R-E Robot.",
        epilog="Files load first, in order, then each -e, then standard input: "
               "a prompt on a terminal, else plain Forth source (no prompts). "
               "A FILE or -e that fails stops the rest and the piped input "
               "(exit 1); a terminal still gets the prompt. "
               "At the prompt, HELP shows how to start.")
    p.add_argument("files", nargs="*", metavar="FILE",
                   help="Forth source to load; also looked for in RCL's screens "
                        "folder (examples/listing1.fs is the article's square)")
    p.add_argument("-e", dest="words", action="append", default=[], metavar="WORDS",
                   help="Forth words to run after the files (may repeat)")
    p.add_argument("--bare", action="store_true",
                   help="a bare F83 machine, no board and no RCL screens")
    p.add_argument("--board-only", action="store_true",
                   help="the simulated board without RCL's screens (build RCL "
                        "layer by layer; INCLUDE rcl.fs loads them all)")
    p.add_argument("--realtime", action="store_true",
                   help="the simulated robot keeps pace with the wall clock, "
                        "also while the prompt waits")
    p.add_argument("--start", type=start_time, metavar="HH:MM|now",
                   help="the time of day to start at (24-hour), or the host's")
    p.add_argument("--screens", type=screens_dir, metavar="DIR",
                   help="load RCL from DIR/rcl.fs instead of the installed screens")
    p.add_argument("--image", metavar="FILE",
                   help="start from a system saved by SAVE-SYSTEM (not the RCL screens)")
    p.add_argument("--trace", metavar="FILE.csv",
                   help="write the board's trace (a row per tick that changed) at the end")
    p.add_argument("--plot", metavar="FILE.png",
                   help="draw path, wheel speeds and following error at the end "
                        "(.png .svg .pdf; needs matplotlib)")
    add_link_args(p)
    p.add_argument("--version", action=VersionAction)
    args = p.parse_intermixed_args(argv)
    if args.bare and (args.board_only or args.realtime or args.start is not None
                      or args.screens):
        p.error("--bare has no board: --board-only, --realtime, --start and "
                "--screens need one")
    return args


# ------------------------------------------------------------------- loads
def where(e, name):
    """`file:line: text` for an error of a FILE or -e, then the words it
    came from, if any (wordloc.py)."""
    if e.file:
        text = str(e)
    elif e.code in (-37, -38):
        text = "%s: %s" % (name, e.message)
    else:
        text = "%s: %s" % (name, e.display())
    return "\n".join([text] + wordloc.describe(e.words()))


def report(out, text):
    """An error of the command line, on stderr, after what stdout holds."""
    out.end_line()
    out.flush()
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


def run_startup(m, args, out):
    """Load the FILEs, then run each -e. -> True, False on an error; Bye
    passes through."""
    steps = [(m.include, find_file(path, m), path) for path in args.files]
    steps += [(m.evaluate, words, "-e") for words in args.words]
    for action, arg, name in steps:
        if action == m.include and is_image(arg):
            report(out, "%s: a saved system, not Forth source: start from it with "
                        "rcl --image %s" % (name, name))
            return False
        try:
            action(arg)
        except rcl.ForthError as e:
            report(out, where(e, name))
            return False
        except KeyboardInterrupt:               # between words: the VM did not see it
            report(out, "%s: Interrupted" % name)
            return False
    return True


def is_image(path):
    """Does the file begin as SAVE-SYSTEM's images do (image.MAGIC; image.py
    is not loaded for this)? A FIFO or device is not opened here."""
    if not os.path.isfile(path):
        return False
    try:
        with open(path, "rb") as f:
            return f.read(8) == b"RCLIMAGE"
    except OSError:
        return False                  # include says why


# -------------------------------------------------------------------- pipe
def run_pipe(m, out, feed):
    """Interpret piped lines; a line that printed something ends its output
    with a newline; every error shows as on F83's screen, and the next line
    still runs, except the rest of a definition the error
    abandoned (repl.OpenDefinition). -> 0, or 1 if any line failed."""
    status, guard = 0, repl.OpenDefinition(m)
    while True:
        line = feed.line()
        if line is None:
            return status
        if guard.skipping:
            out.write(line + guard.skip(line) + "\n")
            continue
        guard.before()
        try:
            m.evaluate(line)
        except rcl.ForthError as e:
            out.write(repl.error_text(e) + "\n")   # from a file: file:line first
            name = guard.failed(line, e)
            if name:
                out.write("%s is abandoned: the lines up to its ; are skipped\n" % name)
            status = 1
        except rcl.Bye:
            return status
        except Exception as e:
            out.write(internal(m, e) + "\n")
            status = 1
        out.end_line()          # one line's output never runs into the next's
        out.flush()


def internal(m, exc):
    """An exception the machine should not have let out: abort it and say
    what happened, F83-style, without a traceback."""
    try:
        m.abort()
    except Exception:
        pass
    return " Internal error: %s: %s " % (type(exc).__name__, exc)


# ----------------------------------------------------------------- leaving
LEAVING_SIGNALS = ("SIGTERM", "SIGHUP")


@contextlib.contextmanager
def robot_safe_at_exit(m):
    """However rcl leaves (BYE, end of input, an error, SIGTERM or SIGHUP),
    the robot is left in its safe state. A signal while Forth runs is taken
    at the next primitive boundary (as Ctrl-C is), otherwise at once."""
    def on_signal(signum, frame):
        m.board.stop_motors()
        if m.in_forth and not m.in_input:
            m.request_break(leave=signum)
        else:
            raise rcl.errors.Terminated(signum)
    saved = {}
    for name in LEAVING_SIGNALS:
        if hasattr(signal, name):
            saved[name] = signal.signal(getattr(signal, name), on_signal)
    try:
        yield
    finally:
        for name, handler in saved.items():
            signal.signal(getattr(signal, name), handler)
        try:
            m.write = None                # nothing more to show
            m.shutdown()
        except BaseException:             # noqa: B036  still stop the motors
            pass
        m.board.stop_motors()
        m.board.close()                   # a board on a link: its tick stopped too


# -------------------------------------------------------------------- main
def run(argv):
    """Run with --trace/--plot recorded from start to end, whatever ends it."""
    args = parse_args(argv)
    if sys.stdout is None:
        raise StdoutClosed("standard output is closed")
    if args.list_ports:
        return list_ports()
    if not (args.trace or args.plot):
        return run_machine(args)
    from rcl.recording import Recording, RecordingError
    recording = []

    def record(m):
        try:
            title = " ".join(["rcl"] + [os.path.basename(f) for f in args.files]
                             + ["-e '%s'" % w for w in args.words])
            recording.append(Recording(m, args.trace, args.plot, title))
        except RecordingError as e:
            sys.stderr.write("rcl: %s\n" % e)
            raise SystemExit(2)
    try:
        status = run_machine(args, record)
    finally:
        for error in recording[0].finish() if recording else ():
            sys.stderr.write("rcl: %s\n" % error)
            status = 1
    return status


def run_machine(args, record=None):
    for stream in (sys.stdout, sys.stderr, sys.stdin):
        if hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="replace")
    interactive = sys.stdin is not None and sys.stdin.isatty()
    out = Output(sys.stdout, flush_each=interactive or sys.stdout.isatty(),
                 clears=sys.stdout.isatty() and not is_dumb())
    m = make_machine(args, out.write)
    if record:
        record(m)
    with robot_safe_at_exit(m):
        return drive(m, args, out, interactive)


def drive(m, args, out, interactive):
    """Files, -e, then standard input: a pipe or the prompt. -> exit status."""
    if not interactive:
        feed = LineFeed(sys.stdin or io.StringIO())   # stdin closed: no input
        m.read_line, m.read_key = feed.line, feed.key
        try:
            if not run_startup(m, args, out):
                return 1
            status = run_pipe(m, out, feed)
        except rcl.Bye:
            status = 0
        out.end_line()                           # the shell's prompt starts on its own line
        return status
    shell = repl.Repl(m, out)
    out.write(BANNER % (version(), describe(args)) + "\n")
    try:
        status = 0 if run_startup(m, args, out) else 1
    except rcl.Bye:
        out.end_line()
        return 0
    shell.run()
    return status


def main(argv=None):
    """Entry point of the `rcl` console script and `python3 -m rcl`."""
    try:
        return run(argv)
    except SystemExit as e:                      # argparse: --help, bad usage
        return e.code if isinstance(e.code, int) else 0 if e.code is None else 2
    except KeyboardInterrupt:
        return 130
    except rcl.errors.Terminated as e:
        return 128 + (e.args[0] if e.args else signal.SIGTERM)
    except (StdoutClosed, BrokenPipeError) as e:
        # Say why, unless the reader simply went away; and keep Python's
        # exit-time flush of stdout from complaining either.
        if e.args:
            try:
                sys.stderr.write("rcl: cannot write standard output: %s\n" % e.args[0])
            except Exception:
                pass
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except Exception:
            pass
        return 1
    except Exception as e:
        try:
            sys.stderr.write("rcl: internal error: %s: %s\n" % (type(e).__name__, e))
        except Exception:
            pass
        return 2
