"""rcl.hw: RCL driving a board over a link.

protocol.py   framing, CRC-16 and the one table of messages (docs/protocol.md)
link.py       LinkBoard: the host's rcl.board.Board over any pyserial port or usb://
session.py    the link's states and moves, why a link is lost, the request in flight
liveness.py   is the board still there: silence judged at reads, in link time
inorder.py    board frames taken in sequence order (held, NAK, a frame gone)
tickreplay.py what the host runs per TICK, and its TICK_DONE frames
lockstep.py   CLOCK and WAIT: the lockstep extension, simulated boards only
server.py     the board side: a SimBoard served in real time over a byte stream
boardcli.py   rcl-board: that server behind a pty or a TCP port
urlhandler/   pyserial URL handlers (rclsim://), registered on import
usb.py        the same frames over USB bulk endpoints; a simulated USB board
connect.py    --port URL (usb:// too), --usb, --list-ports, failures said plainly
"""
import serial

# pyserial finds URL handlers by module name (protocol_<scheme>) in these packages.
if "rcl.hw.urlhandler" not in serial.protocol_handler_packages:
    serial.protocol_handler_packages.append("rcl.hw.urlhandler")
