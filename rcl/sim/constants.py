"""Constants of the simulated R-E Robot board: the simulator's own (clocks,
motor and PLL model, arm and gripper), and, imported here so the simulator
has them under one name, the robot's hardware facts (rcl/robot.py: port
map, bits, geometry) and the 80188's (rcl/i80188.py). Every number of the
hardware has one name and one tag saying where it comes from:

    ARTICLE   stated by the Radio-Electronics article (the seed document)
    INTEL     standard behaviour of the Intel part (8253, 80186/80188)
    PROPOSAL  chosen here where the article is silent, so that the
              simulator is concrete (the real board may have differed)
    derived   computed here from the numbers above it (tag of its sources)

Bit constants are masks (1 << bit), ready for `byte & MASK`; rcl/robot.py
draws the latches' and the status port's bits.
"""

from rcl import i80188
from rcl.robot import (  # noqa: F401  (the hardware facts, one name each)
    WHEEL_CIRC_IN, TRACK_IN, COUNTS_PER_INCH, COUNTS_PER_SPIN, N_MIN, CRPM_MAX, G_IN_S2,
    LEFT_8253, RIGHT_8253, MOTOR_PORT, AUX_PORT, STATUS_PORT, PCB_BASE, CTR_SPEED, CTR_FORWARD,
    CTR_REVERSE, CTR_CONTROL, M1_ON, M1_REV, M2_ON, M2_REV, M1_GO, M2_GO, ARM_ON, ARM_DOWN,
    GRIP_ON, GRIP_CLOSE, BEEPER, RELAYS_AUX_SHIFT, ARM_TOP, ARM_BOTTOM, GRIP_OPENED,
    GRIP_CLOSED, M1_LOCK, M2_LOCK, CHARGER)

# ---------------------------------------------------------------------------
# CLOCKS AND COUNTERS
# ---------------------------------------------------------------------------

F_8253_CLK = 125_000                # Hz, 2 MHz / 16 into each 8253 [ARTICLE]
N_MAX = 65_536                      # 8253 count range, written as 0 [ARTICLE]
ENCODER_CPR = 500                   # encoder counts per wheel revolution [ARTICLE]
T0_CLOCK_US = 1.5                   # 80188 timer 0 input period, 2 MHz / 3 [ARTICLE]
T0_CLOCK_HZ = 2_000_000 / 3         # the same clock as a frequency [ARTICLE]
T0_RCL_COUNT = 6667                 # timer 0 max count for the 10 ms tick [ARTICLE]
T0_BIOS_COUNT = 36_617              # power-on max count, 54.9255 ms [PROPOSAL]
TICKS_PER_DAY_RCL = 8_640_000       # 86,400 s / 10 ms [derived, ARTICLE]
TICKS_PER_DAY_BIOS = 1_573_040      # PC value, 0x1800B0 [PROPOSAL]
TICK_S = 0.010                      # RCL control tick, 100 per second [ARTICLE]

# ---------------------------------------------------------------------------
# DRIVE MOTOR + PLL MODEL (rcl/sim/motors.py)
# ---------------------------------------------------------------------------

A_MOTOR_G = 0.5                     # drive torque limit as an acceleration [PROPOSAL]
# 0.5 * 386.4 in/s^2 * 28.409 counts/in = 5,488.6 counts/s^2 [derived]
A_MOTOR_COUNTS_S2 = A_MOTOR_G * G_IN_S2 * COUNTS_PER_INCH
TAU_PLL_S = 0.020                   # PLL speed-loop time constant [PROPOSAL]
TAU_COAST_S = 0.300                 # freewheeling decay, ON=1 GO=0 [PROPOSAL]
TAU_BRAKE_S = 0.050                 # dynamic braking decay, ON=0 [PROPOSAL]
PLL_LOCK_TOLERANCE = 0.05           # lock bit: |rate| within 5 % of f_ref [PROPOSAL]
SUB_STEP_S = 0.001                  # physics sub-step, 10 per control tick [PROPOSAL]

# ---------------------------------------------------------------------------
# ARM AND GRIPPER
# ---------------------------------------------------------------------------

ARM_SPEED_IN_S = 1.0                # lift speed [PROPOSAL]
ARM_TRAVEL_IN = 8.0                 # lift travel 0.0 .. 8.0 in, power-on 8.0 [PROPOSAL]
GRIP_SPEED_IN_S = 0.5               # jaw speed [PROPOSAL]
GRIP_TRAVEL_IN = 3.0                # jaw opening 0.0 .. 3.0 in, power-on 0.0 [PROPOSAL]

# ---------------------------------------------------------------------------
# MEMORY AND INTERRUPTS
# ---------------------------------------------------------------------------

FORTH_CS = 0x1000                   # segment GET-CS returns [PROPOSAL]
VECTOR_TIMER0 = i80188.VECTOR_TIMER0        # 80188 timer 0 interrupt type [INTEL]
VECTOR_USER_TICK = i80188.VECTOR_USER_TICK  # BIOS user timer hook, INT 1Ch [ARTICLE]
