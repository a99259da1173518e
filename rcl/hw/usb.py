"""The frame protocol over USB: a vendor-class interface's two bulk
endpoints carry the same bytes a serial line would (`rcl --port
usb://VID:PID`, or `--usb VID:PID`), and a pyusb backend that presents the
simulated board as such a device, so that pyusb's own code runs in the
tests (`rcl --port usb://sim`).

    the board's USB device (docs/protocol.md, "Transports")
      configuration 1, interface 0: class 0xFF (vendor), 2 endpoints
        0x01 bulk OUT, 64 bytes   host -> board frames
        0x81 bulk IN,  64 bytes   board -> host frames
      the simulated one: VID:PID 1209:0001 (pid.codes' test ID),
      "rcl simulated R-E Robot board"

UsbPort gives a LinkBoard what it uses of a pyserial port: read, write,
in_waiting, close, is_open, portstr.
"""
import array
import errno
import re
import socket
import threading

import usb.backend
import usb.core
import usb.util

from rcl.hw.protocol import LinkError

SIM_VID, SIM_PID = 0x1209, 0x0001
EP_OUT, EP_IN, PACKET = 0x01, 0x81, 64
STRINGS = {1: "rcl", 2: "rcl simulated R-E Robot board", 3: "0001"}


# ------------------------------------------------------------ the backend
class Descriptor:
    """A descriptor: its fields as attributes (what pyusb reads)."""

    def __init__(self, **fields):
        self.__dict__.update(fields, extra_descriptors=[])


DEVICE = Descriptor(
    bLength=18, bDescriptorType=1, bcdUSB=0x0200, bDeviceClass=0, bDeviceSubClass=0,
    bDeviceProtocol=0, bMaxPacketSize0=64, idVendor=SIM_VID, idProduct=SIM_PID,
    bcdDevice=0x0100, iManufacturer=1, iProduct=2, iSerialNumber=3, bNumConfigurations=1,
    bus=1, address=42, speed=2, port_number=1, port_numbers=(1,))
CONFIG = Descriptor(
    bLength=9, bDescriptorType=2, wTotalLength=32, bNumInterfaces=1, bConfigurationValue=1,
    iConfiguration=0, bmAttributes=0x80, bMaxPower=50)
INTERFACE = Descriptor(
    bLength=9, bDescriptorType=4, bInterfaceNumber=0, bAlternateSetting=0, bNumEndpoints=2,
    bInterfaceClass=0xFF, bInterfaceSubClass=0, bInterfaceProtocol=0, iInterface=0)
ENDPOINTS = [Descriptor(bLength=7, bDescriptorType=5, bEndpointAddress=a, bmAttributes=2,
                        wMaxPacketSize=PACKET, bInterval=0, bRefresh=0, bSynchAddress=0)
             for a in (EP_OUT, EP_IN)]


class SimBoardBackend(usb.backend.IBackend):
    """pyusb's backend interface with one device on it: a simulated board
    (rcl.hw.server.BoardServer, in a thread) behind two bulk endpoints."""

    def __init__(self, **server_options):
        super().__init__()
        self.options = server_options
        self.server = None

    def enumerate_devices(self):
        yield "rcl-sim-board"

    def get_device_descriptor(self, dev):
        return DEVICE

    def get_configuration_descriptor(self, dev, config):
        return CONFIG

    def get_interface_descriptor(self, dev, intf, alt, config):
        if intf or alt:
            raise IndexError("Invalid interface index %d" % intf)
        return INTERFACE

    def get_endpoint_descriptor(self, dev, ep, intf, alt, config):
        return ENDPOINTS[ep]

    def open_device(self, dev):
        """Power the board on: a server thread on one end of a socket pair."""
        from rcl.hw.server import BoardServer
        self.server = BoardServer(**self.options)
        ours, theirs = socket.socketpair()
        done = threading.Event()
        thread = threading.Thread(target=self.server.serve_fd,
                                  args=(theirs.fileno(), done.is_set), daemon=True,
                                  name="usb-sim-board")
        thread.start()
        return {"sock": ours, "theirs": theirs, "done": done, "thread": thread}

    def close_device(self, handle):
        handle["done"].set()
        handle["thread"].join(1.0)
        handle["sock"].close()
        handle["theirs"].close()

    def set_configuration(self, handle, value):
        pass

    def get_configuration(self, handle):
        return 1

    def claim_interface(self, handle, intf):
        pass

    def release_interface(self, handle, intf):
        pass

    def bulk_write(self, handle, ep, intf, data, timeout):
        handle["sock"].sendall(bytes(data))
        return len(data)

    def bulk_read(self, handle, ep, intf, buff, timeout):
        sock = handle["sock"]
        sock.settimeout(timeout / 1000 if timeout else None)
        try:
            data = sock.recv(len(buff))
        except socket.timeout:
            raise usb.core.USBTimeoutError("Operation timed out", -7, errno.ETIMEDOUT) from None
        buff[:len(data)] = array.array("B", data)
        return len(data)

    def ctrl_transfer(self, handle, request_type, request, value, index, data, timeout):
        """GET_DESCRIPTOR for strings: all the control traffic pyusb sends."""
        if request_type != 0x80 or request != 6 or value >> 8 != 3:
            raise usb.core.USBError("Pipe error", -9, errno.EPIPE)
        n = value & 0xFF
        body = b"\x09\x04" if n == 0 else STRINGS.get(n, "").encode("utf-16-le")
        desc = bytes((2 + len(body), 3)) + body
        count = min(len(data), len(desc))
        data[:count] = array.array("B", desc[:count])
        return count

    def clear_halt(self, handle, ep):
        pass

    def reset_device(self, handle):
        pass

    def is_kernel_driver_active(self, handle, intf):
        return False


# ----------------------------------------------------------------- the port
class UsbPort:
    """A claimed board interface, read and written as a pyserial port is."""

    def __init__(self, dev, name):
        self.dev, self.portstr = dev, name
        dev.set_configuration()
        usb.util.claim_interface(dev, 0)
        self.buffer = bytearray()
        self.is_open = True

    @property
    def in_waiting(self):
        return len(self.buffer)

    def read(self, size=1):
        """What has come, up to a packet (waits at most 10 ms)."""
        if not self.buffer:
            try:
                self.buffer += bytes(self.dev.read(EP_IN, PACKET, timeout=10))
            except usb.core.USBTimeoutError:
                return b""
            except usb.core.USBError as e:
                raise OSError(e.errno, "USB: %s" % e) from None
        data, self.buffer = bytes(self.buffer[:max(size, PACKET)]), self.buffer[max(size, PACKET):]
        return data

    def write(self, data):
        try:
            for i in range(0, len(data), PACKET):
                self.dev.write(EP_OUT, data[i:i + PACKET], timeout=100)
        except usb.core.USBError as e:
            raise OSError(e.errno, "USB: %s" % e) from None
        return len(data)

    def close(self):
        if self.is_open:
            self.is_open = False
            usb.util.dispose_resources(self.dev)


def parse_id(text):
    """"VID:PID", each 1 to 4 hex digits -> (vid, pid); LinkError with the
    format otherwise."""
    found = re.fullmatch(r"([0-9A-Fa-f]{1,4}):([0-9A-Fa-f]{1,4})", text)
    if found is None:
        raise LinkError("usb://%s: a USB board is usb://VID:PID, VID:PID in hex "
                        "(e.g. usb://1209:0001), or usb://sim" % text)
    return int(found.group(1), 16), int(found.group(2), 16)


def usb_opener(text, **sim_options):
    """A callable opening the board at VID:PID ("sim": the simulated board
    through SimBoardBackend), for LinkBoard: `text` is what follows usb://."""
    if text == "sim":
        backend, (vid, pid) = SimBoardBackend(**sim_options), (SIM_VID, SIM_PID)
    else:
        backend, (vid, pid) = None, parse_id(text)

    def open_port():
        try:
            dev = usb.core.find(idVendor=vid, idProduct=pid, backend=backend)
        except usb.core.NoBackendError:
            raise LinkError("usb://%04x:%04x: no libusb backend: install libusb-1.0 "
                            "(apt install libusb-1.0-0)" % (vid, pid)) from None
        if dev is None:
            raise LinkError("usb://%04x:%04x: no such USB device (rcl --list-ports shows "
                            "what there is)" % (vid, pid))
        try:
            port = UsbPort(dev, "usb:%04x:%04x" % (vid, pid))
        except usb.core.USBError as e:
            raise LinkError(usb_failure(vid, pid, e)) from None
        port.backend = backend
        port.server = getattr(backend, "server", None)
        if port.server is not None:            # in this process: silence in its time
            port.board_seconds = port.server.board_seconds
        return port
    return open_port


def usb_failure(vid, pid, e):
    if e.errno == errno.EACCES:
        return ("USB %04x:%04x: permission denied; a udev rule gives it to your group: "
                'SUBSYSTEM=="usb", ATTRS{idVendor}=="%04x", ATTRS{idProduct}=="%04x", '
                'GROUP="plugdev", MODE="0660"' % (vid, pid, vid, pid))
    if e.errno == errno.EBUSY:
        return "USB %04x:%04x: busy (another program has claimed it)" % (vid, pid)
    return "USB %04x:%04x: %s" % (vid, pid, e)


def list_usb(backend=None):
    """Lines for the USB devices with a vendor-class interface of two bulk
    endpoints (boards rcl could drive)."""
    try:
        devices = list(usb.core.find(find_all=True, backend=backend))
    except usb.core.NoBackendError:
        raise LinkError("no libusb backend: install libusb-1.0 to list USB boards") from None
    lines = []
    for dev in devices:
        try:
            intf = next(iter(dev.configurations()))[(0, 0)]
        except (usb.core.USBError, KeyError, StopIteration, IndexError):
            continue
        bulk = [e for e in intf if usb.util.endpoint_type(e.bmAttributes)
                == usb.util.ENDPOINT_TYPE_BULK]
        if intf.bInterfaceClass == 0xFF and len(bulk) == 2:
            lines.append("usb %04x:%04x  %s" % (dev.idVendor, dev.idProduct, product(dev)))
        usb.util.dispose_resources(dev)
    return lines or ["no USB boards found"]


def product(dev):
    try:
        return dev.product or ""
    except (usb.core.USBError, ValueError):
        return "(name not readable)"
