"""rcl.hw: RCL driving a board over a link.

protocol.py   framing, CRC-16 and the one table of messages (docs/protocol.md)
link.py       LinkBoard: the host's rcl.board.Board over any pyserial port
server.py     the board side: a SimBoard served in real time over a byte stream
boardcli.py   rcl-board: that server behind a pty or a TCP port
urlhandler/   pyserial URL handlers (rclsim://), registered on import
usb.py        the same frames over USB bulk endpoints; a simulated USB board
connect.py    --port, --usb, --list-ports, and their failures said plainly
"""
import serial

# pyserial finds URL handlers by module name (protocol_<scheme>) in these packages.
if "rcl.hw.urlhandler" not in serial.protocol_handler_packages:
    serial.protocol_handler_packages.append("rcl.hw.urlhandler")
