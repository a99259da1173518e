"""The R-E Robot's hardware facts that are not the simulation: its port
map, the relay and status bits, the wheels' geometry and units (tagged
as in rcl/sim/constants.py; docs/guide.md section 13 says why the
geometry is what it is). The simulator (rcl/sim), the trace reader
(rcl/track.py) and the robot assertions (rcl/testing) take them from
here; the simulator's own model parameters stay in rcl/sim/constants.py.

    MOTOR latch 0x88   7  6  5     4     3      2     1      0
                       -  -  M2-GO M1-GO M2-REV M2-ON M1-REV M1-ON
    AUX latch   0x89   7  6  5  4      3          2       1        0
                       -  -  -  BEEPER GRIP-CLOSE GRIP-ON ARM-DOWN ARM-ON
    STATUS      0x8A   7  6       5       4       3           2           1          0
                       0  CHARGER M2-LOCK M1-LOCK GRIP-CLOSED GRIP-OPENED ARM-BOTTOM ARM-TOP
"""
import math

from rcl import i80188

# ---------------------------------------------------------------------------
# GEOMETRY AND UNITS (docs/guide.md section 13)
# ---------------------------------------------------------------------------

WHEEL_CIRC_IN = 17.6                # 1 MPH = 1 wheel rev/s [PROPOSAL]
TRACK_IN = 44 / math.pi             # 14.006 in: a spin moves each wheel 44 in [PROPOSAL]
COUNTS_PER_INCH = 625 / 22          # 28.409 = ENCODER_CPR / WHEEL_CIRC_IN [derived]
COUNTS_PER_SPIN = 1250              # counts per wheel for a 360-degree spin [derived]
N_MIN = 50                          # smallest 8253 speed count, 5 MPH, 2500 Hz [PROPOSAL]
CRPM_MAX = 30_000                   # internal speed limit, centi-rpm, 300 rpm [PROPOSAL]
G_IN_S2 = 386.4                     # 1 G = 32.2 ft/s^2 [ARTICLE]

# ---------------------------------------------------------------------------
# PORT MAP
# ---------------------------------------------------------------------------

LEFT_8253 = 0x80                    # 8253 #1, motor 1 = left wheel [PROPOSAL]
RIGHT_8253 = 0x84                   # 8253 #2, motor 2 = right wheel [PROPOSAL]
MOTOR_PORT = 0x88                   # MOTOR relay/drive latch, write-only [PROPOSAL]
AUX_PORT = 0x89                     # AUX latch: arm, gripper, beeper [PROPOSAL]
STATUS_PORT = 0x8A                  # STATUS input, read-only [PROPOSAL]
PCB_BASE = i80188.PCB_BASE          # 80188 peripheral control block [INTEL]

# 8253 counter offsets from LEFT_8253 / RIGHT_8253 [PROPOSAL]
CTR_SPEED = 0                       # counter 0: speed reference, mode 3 [ARTICLE]
CTR_FORWARD = 1                     # counter 1: forward encoder counts [ARTICLE]
CTR_REVERSE = 2                     # counter 2: reverse encoder counts [ARTICLE]
CTR_CONTROL = 3                     # control word register [INTEL]

# ---------------------------------------------------------------------------
# MOTOR LATCH BITS, port 0x88 [PROPOSAL]
# ---------------------------------------------------------------------------

M1_ON = 0x01                        # bit 0: left relay closed (0 = braking short)
M1_REV = 0x02                       # bit 1: left direction reverse
M2_ON = 0x04                        # bit 2: right relay closed
M2_REV = 0x08                       # bit 3: right direction reverse
M1_GO = 0x10                        # bit 4: left PLL and drive current on
M2_GO = 0x20                        # bit 5: right PLL and drive current on

# ---------------------------------------------------------------------------
# AUX LATCH BITS, port 0x89 [PROPOSAL]
# ---------------------------------------------------------------------------

ARM_ON = 0x01                       # bit 0: lift motor running
ARM_DOWN = 0x02                     # bit 1: lift direction down (0 = up)
GRIP_ON = 0x04                      # bit 2: gripper motor running
GRIP_CLOSE = 0x08                   # bit 3: gripper closing (0 = opening)
BEEPER = 0x10                       # bit 4: piezo beeper sounding
RELAYS_AUX_SHIFT = 8                # AUX byte is the high byte of RCL's RELAYS cell

# ---------------------------------------------------------------------------
# STATUS BITS, port 0x8A [PROPOSAL]
# ---------------------------------------------------------------------------

ARM_TOP = 0x01                      # bit 0: lift at its upper limit switch
ARM_BOTTOM = 0x02                   # bit 1: lift at its lower limit switch
GRIP_OPENED = 0x04                  # bit 2: jaws at the fully-open limit
GRIP_CLOSED = 0x08                  # bit 3: jaws closed, or stalled on an object
M1_LOCK = 0x10                      # bit 4: left PLL locked
M2_LOCK = 0x20                      # bit 5: right PLL locked
CHARGER = 0x40                      # bit 6: on the charging contacts
