"""rcl.hw: RCL driving a board over a link.

protocol.py   framing, CRC-16 and the one table of messages (docs/protocol.md)
link.py       LinkBoard: the host's rcl.board.Board over any pyserial port
server.py     the board side: a SimBoard served in real time over a byte stream
boardcli.py   rcl-board: that server behind a pty or a TCP port
urlhandler/   pyserial URL handlers (rclsim://)
"""
