"""Opening a link: a URL or device (`rcl --port`), and `rcl --list-ports`;
the usual failures said plainly. Every transport is a URL:

    open_link(port="socket://127.0.0.1:7000")  -> LinkBoard
    open_link(port="/dev/ttyUSB0")             (115200 baud, 8N1, exclusive)
    open_link(port="rclsim://")                (a simulated board in-process)
    open_link(port="usb://1209:0001")          (vendor-class bulk endpoints, VID:PID)
    open_link(port="usb://sim")                (the simulated board as a USB device)
    open_link(usb="1209:0001")                 (`rcl --usb`: the same as usb://1209:0001)

usb:// is rcl's (rcl/hw/usb.py, through pyusb); every other URL is
pyserial's, rclsim:// included (rcl/hw/urlhandler/).

A board that resets when its port opens (Arduino-class boards do, on DTR)
is waited for: the handshake repeats HELLO for up to HELLO_WAIT seconds and
the frame reader skips whatever the board prints while it boots.
"""
import errno
import grp
import os

import serial

from rcl.hw.protocol import LinkError

BAUD = 115200


USB = "usb://"


def open_link(port=None, usb=None):
    """A LinkBoard on the port URL (usb="VID:PID" is port="usb://VID:PID")."""
    from rcl.hw.link import LinkBoard
    url = USB + usb if usb is not None else port
    if url.startswith(USB):
        return LinkBoard(usb_opener(url))
    return LinkBoard(lambda: open_serial(url))


def usb_opener(url):
    """The opener of a usb:// URL (pyusb is needed only here)."""
    try:
        from rcl.hw import usb
    except ImportError:
        raise LinkError("%s: USB needs pyusb (pip install pyusb) and libusb-1.0" % url) from None
    return usb.usb_opener(url[len(USB):])


def open_serial(url):
    """The pyserial port for url, opened exclusively; LinkError if it fails."""
    try:
        return serial.serial_for_url(url, baudrate=BAUD, timeout=0.01, exclusive=True)
    except ValueError as e:
        raise LinkError("%s: %s" % (url, e)) from None
    except (serial.SerialException, OSError) as e:
        raise LinkError(open_failure(url, e)) from None


def close_port(port):
    """Close a port; one opened exclusively gives its lock up first. A
    thread still inside select() on the port (the link's reader, not run
    since on a busy machine) keeps the file open past close(), and its
    lock with it: the next open of the port, even this process's own,
    would find it busy."""
    fd = getattr(port, "fd", None)
    if getattr(port, "exclusive", False) and isinstance(fd, int):
        try:
            import fcntl
            fcntl.flock(fd, fcntl.LOCK_UN)
        except (ImportError, OSError):
            pass
    port.close()


def open_failure(url, exc):
    """What to tell the user when url would not open."""
    code = getattr(exc, "errno", None)
    text = str(exc)
    if code == errno.ENOENT or "No such file" in text:
        return "%s: no such port (rcl --list-ports shows the ports there are)" % url
    if code == errno.EACCES or "Permission denied" in text:
        return "%s: permission denied; %s" % (url, group_hint(url))
    if code in (errno.EAGAIN, errno.EBUSY) or "exclusively lock" in text or "busy" in text:
        return "%s: port busy (another program has it open)" % url
    if "Connection refused" in text:
        return "%s: connection refused (is rcl-board --tcp running there?)" % url
    return "%s: %s" % (url, text)


def group_hint(path):
    """Which group may open the device, and how to join it."""
    try:
        group = grp.getgrgid(os.stat(path).st_gid).gr_name
    except (OSError, KeyError):
        group = "dialout"
    return ("members of group %r may open it: sudo usermod -aG %s $USER, "
            "then log in again" % (group, group))


def list_ports():
    """Lines describing the serial ports and the USB devices rcl could use."""
    from serial.tools import list_ports as lp
    lines = []
    for p in sorted(lp.comports(), key=lambda p: p.device):
        extra = " (USB %04X:%04X)" % (p.vid, p.pid) if p.vid is not None else ""
        lines.append("%s  %s%s" % (p.device, p.description or "", extra))
    if not lines:
        lines.append("no serial ports found")
    try:
        from rcl.hw.usb import list_usb
        lines.extend(list_usb())
    except (LinkError, ImportError) as e:
        lines.append("USB: %s" % e)
    return lines
