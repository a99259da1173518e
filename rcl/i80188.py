"""The 80188 board's addresses, in one place: the peripheral control block
(PCB) registers and bits, the interrupt types and vectors, and the BIOS
data area (Intel's 80188 data sheet; the BIOS keeps the IBM PC's tick
count, and docs/protocol.md section 4 lists the addresses a board serves).
The simulated chips (rcl/sim), RCL's CODE words (rcl/words), the link
(rcl/hw) and the host's tools all take them from here.

    I/O space                         memory (seg * 16 + off)
    0xFF00  PCB_BASE                  0000:0020  vector of type 8 (timer 0)
    +0x22   EOI                       0000:0070  vector of INT 1Ch (user tick)
    +0x28   interrupt mask            0040:006C  BIOS tick count, 32 bits
    +0x32   timer interrupt control   0040:0070  midnight flag
    +0x50   timer 0 count ...         0040:00F0  ticks per day, 32 bits
    +0x56   timer 0 control
"""

PCB_BASE = 0xFF00                   # PCB I/O base after reset [INTEL]

# Interrupt controller registers (offsets from PCB_BASE)
EOI_REG = 0x22
MASK_REG = 0x28
IN_SERVICE_REG = 0x2C
REQUEST_REG = 0x2E
STATUS_REG = 0x30
TIMER_CONTROL_REG = 0x32
EOI_NONSPECIFIC = 0x8000
EOI_TIMER = 0x0008                  # specific EOI, type 8 = the timers
TMR_BIT = 0x0001                    # timer bit of mask/in-service/request
TIMER_MASK = 0x0008                 # mask bit of the timer control 0x32

# Timer registers (offsets from PCB_BASE)
T0_COUNT, T0_MAX_A, T0_MAX_B, T0_CONTROL = 0x50, 0x52, 0x54, 0x56

# Timer control register bits
EN = 0x8000
INH = 0x4000
INT = 0x2000
RIU = 0x1000
MC = 0x0020
RTG = 0x0010
P = 0x0008
EXT = 0x0004
ALT = 0x0002
CONT = 0x0001

# Interrupt types and where their vectors are (segment 0, 4 bytes each)
TIMER_TYPES = (8, 18, 19)           # interrupt type of timer 0, 1, 2 [INTEL]
VECTOR_TIMER0 = 0x08                # timer 0 [INTEL]
VECTOR_USER_TICK = 0x1C             # the BIOS's user timer hook, INT 1Ch [ARTICLE]


def vector_address(n):
    """The offset in segment 0 of interrupt type n's vector (off, then seg)."""
    return 4 * n


# The BIOS: its timer handler and IRET, and its data area (segment 0 offsets)
BIOS_SEG, BIOS_TIMER, BIOS_IRET = 0xF000, 0xFEA5, 0xFF53
TICKS_ADDR = 0x46C                  # 0040:006C tick count since midnight, 32 bits
MIDNIGHT_ADDR = 0x470               # 0040:0070 set when the count wraps
PER_DAY_ADDR = 0x4F0                # 0040:00F0 ticks per day, 32 bits (our BIOS's)
