"""THE LOCKSTEP EXTENSION, host side: used with simulated boards only
(rcl-board and rclsim://, whose IDENTIFY sets flag bit 0; docs/protocol.md
section 5, "Lockstep"). Firmware never sets the flag, and a host never
sends CLOCK or WAIT to a board that did not.

A lockstep board holds its time for the host: from a TICK until the
host's final TICK_DONE and its WAIT for the next tick, and, before timer 0
ticks at all, everywhere but where the host's CLOCK frames put it. So the
host tells it its own virtual time (CLOCK) before each port or memory
access while the board is not ticking, and says WAIT while it waits for a
tick. This module keeps that state; rcl/hw/link.py sends the frames.
"""
from rcl.board import CLOCK_HZ

US = CLOCK_HZ // 1_000_000


class HostTime:
    """The host's virtual time as a lockstep board is told it."""

    def __init__(self, time_zero=None):
        self.time_zero = time_zero     # the machine's clock at HELLO (attach, connect)
        self.follows = True            # no tick yet: the board keeps the host's time
        self.told_us = 0               # ... and has it up to here

    def clock_us(self, clock):
        """-> the `us` of a CLOCK frame to send before an access at the
        machine's `clock`, or None (not following, or already told)."""
        if not self.follows or self.time_zero is None:
            return None
        us = (clock - self.time_zero) // US
        if us == self.told_us:
            return None
        self.told_us = us
        return us & 0xFFFFFFFF
