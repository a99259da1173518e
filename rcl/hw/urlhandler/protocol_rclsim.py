"""rclsim:// -- a simulated R-E Robot board in this process, speaking the
frame protocol, behind a pyserial port (modelled on pyserial's loop://).

URL format:  rclsim://[?option=value[&option=value...]]
options:
  corrupt=RATE   flip a bit in this fraction of the bytes, each direction
  seed=N         the corruption's random seed (default 1)
  cut_at=S       the link goes silent S seconds (board time) after opening
  cut_for=S      for S seconds (default: for good)
  rate=R         board time runs R times the wall clock (default 1)
  version=N      the board answers HELLO with protocol version N (a fault)

The board runs in a thread of its own, paced to the wall clock, through a
socket pair: the same rcl.hw.server.BoardServer that rcl-board serves.
The host judges its silence (Link lost) in the board's time, not the wall
clock's: see board_seconds.
`port.server` is that server (its `.board` is the SimBoard).
"""
import socket
import threading
import urllib.parse

from serial.serialutil import PortNotOpenError, SerialBase, SerialException, Timeout

OPTIONS = {"corrupt": float, "seed": int, "cut_at": float, "cut_for": float,
           "rate": float, "version": int}
FORMAT = "rclsim://[?corrupt=RATE&seed=N&cut_at=S&cut_for=S&rate=R&version=N]"


class Serial(SerialBase):
    """A pyserial port whose other end is a simulated board."""

    def open(self):
        from rcl.hw.server import BoardServer
        if self._port is None:
            raise SerialException("Port must be configured before it can be used.")
        if self.is_open:
            raise SerialException("Port is already open.")
        options = self.from_url(self.portstr)
        self.server = BoardServer(**options)
        self._sock, theirs = socket.socketpair()
        self._theirs = theirs
        self._done = threading.Event()
        self._thread = threading.Thread(
            target=self.server.serve_fd, args=(theirs.fileno(), self._done.is_set),
            daemon=True, name="rclsim-board")
        self._thread.start()
        self.is_open = True

    def from_url(self, url):
        parts = urllib.parse.urlsplit(url)
        if parts.scheme != "rclsim" or parts.netloc or parts.path not in ("", "/"):
            raise SerialException("expected a URL of the form %s, not %r" % (FORMAT, url))
        options = {}
        for key, values in urllib.parse.parse_qs(parts.query).items():
            if key not in OPTIONS:
                raise SerialException("unknown option %r: %s" % (key, FORMAT))
            try:
                options[key] = OPTIONS[key](values[0])
            except ValueError:
                raise SerialException("bad value for %s: %s" % (key, FORMAT)) from None
        return options

    def close(self):
        if self.is_open:
            self._done.set()
            self._thread.join(1.0)
            self._sock.close()
            self._theirs.close()
            self.is_open = False

    def board_seconds(self):
        """The board's own time: the host judges its silence by it."""
        return self.server.board_seconds()

    def _reconfigure_port(self):
        """Baud rate and framing mean nothing on a socket pair."""

    @property
    def in_waiting(self):
        if not self.is_open:
            raise PortNotOpenError()
        import select
        return 1 if select.select([self._sock], [], [], 0)[0] else 0

    def read(self, size=1):
        if not self.is_open:
            raise PortNotOpenError()
        import select
        out = bytearray()
        timeout = Timeout(self._timeout)
        while len(out) < size:
            left = timeout.time_left() if self._timeout is not None else None
            if not select.select([self._sock], [], [], left)[0]:
                if not self._thread.is_alive():
                    raise SerialException("the simulated board went away")
                break
            data = self._sock.recv(size - len(out))
            if not data:
                raise SerialException("the simulated board went away")
            out += data
            if timeout.expired():
                break
        return bytes(out)

    def write(self, data):
        """All of data, unless the board's thread has ended (a fault in the
        simulation): then the port fails, as a serial port whose device
        went away does, rather than wait for ever on a full socket."""
        if not self.is_open:
            raise PortNotOpenError()
        import select
        view = memoryview(bytes(data))
        while view:
            if not select.select([], [self._sock], [], 0.1)[1]:
                if not self._thread.is_alive():
                    raise SerialException("the simulated board went away")
                continue
            view = view[self._sock.send(view):]
        return len(data)

    def reset_input_buffer(self):
        while self.in_waiting:
            self._sock.recv(4096)

    def reset_output_buffer(self):
        """Nothing is buffered on our side."""
