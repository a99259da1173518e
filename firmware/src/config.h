/* The firmware's numbers: protocol (docs/protocol.md), the emulated
 * R-E Robot board, and what the link keeps in RAM. */
#ifndef RCL_CONFIG_H
#define RCL_CONFIG_H

#ifndef PROTOCOL_VERSION
#define PROTOCOL_VERSION 1          /* a test build overrides it (make VERSION=2) */
#endif
#define FIRMWARE_VERSION_STRING "1.1"

#define SYNC 0xA5
#define MAX_PAYLOAD 64
#define FRAME_MAX (MAX_PAYLOAD + 6)

/* Board frames kept for NAK. The protocol's 128 would take 3 KiB; 16
 * frames are 160 ms of ticks, and the host asks again within 10 ms of
 * seeing a gap (docs/protocol.md, "What this firmware keeps"). */
#define WINDOW 16
#define SAVED_MAX 26                /* TICK with 16 script reads: 6 + 4 + 16 */

#define INPUT_PER_PASS 16            /* bytes taken between two looks at the timers */
#define HEARTBEAT_US 50000UL
#define HOLD_HEARTBEAT_US 10000UL   /* native board waiting for the host (hal.h) */
#define WATCHDOG_US 250000UL
#define FRAME_GAP_US 50000UL       /* a frame incomplete this long after its SYNC is none */
#define TICK_US 10000U              /* reported in IDENTIFY: RCL's rate, in whole us */
/* The shortest tick the board serves, in half-us: the wire carries the
 * longest TICK (26 bytes) in 2.3 ms at 115200 baud. A shorter period
 * programmed into timer 0 runs at this one. */
#define TICK_MIN_HALF_US 5000UL

/* The emulated board: the R-E Robot's port map (docs/firmware.md, "What it emulates") */
#define LEFT_8253 0x80
#define RIGHT_8253 0x84
#define MOTOR_PORT 0x88
#define AUX_PORT 0x89
#define STATUS_PORT 0x8A
#define FORTH_SEG 0x1000
#define SCRIPT_MAX 16               /* SNAPSHOT records: 64-byte payload / 4 */

/* MOTOR latch bits */
#define M1_ON 0x01
#define M1_REV 0x02
#define M2_ON 0x04
#define M2_REV 0x08
#define M1_GO 0x10
#define M2_GO 0x20
/* AUX latch bits */
#define ARM_ON 0x01
#define ARM_DOWN 0x02
#define GRIP_ON 0x04
#define GRIP_CLOSE 0x08
#define BEEPER 0x10
#define AUX_SAFE_CLEAR (ARM_ON | GRIP_ON | BEEPER)
/* STATUS bits */
#define ARM_TOP 0x01
#define ARM_BOTTOM 0x02
#define GRIP_OPENED 0x04
#define GRIP_CLOSED 0x08
#define M1_LOCK 0x10
#define M2_LOCK 0x20

/* The robot. RCL measures distance in the R-E Robot's encoder counts:
 * 500 a turn of a wheel 17.6 inches round, 625/22 counts an inch; its
 * speeds in counts/s (the 8253's 125 kHz / N). The firmware turns its own
 * encoder's quadrature edges into those counts, EDGES_PER_COUNT_NUM /
 * EDGES_PER_COUNT_DEN edges a count:
 *
 *     edges per count = edges per wheel turn x 22 / (625 x wheel
 *                       circumference in inches)
 *
 * The R-E Robot's 500-line encoder on a 17.6-inch wheel: 2000 x 22 /
 * (625 x 17.6) = 4. A robot with 1320 edges a turn (11 lines, 30:1
 * gears) on 65 mm wheels (8.04 in round): 5.78, written 578 / 100.
 * docs/firmware.md, "A new robot". Make takes them: make
 * EDGES_PER_COUNT=578/100. MOTOR_MAX_EDGES_PER_S is the motor's speed at
 * full duty, in edges/s, for the speed loop's feed-forward. */
#define REF_CLOCK_HZ 125000UL
#ifndef EDGES_PER_COUNT_NUM
#define EDGES_PER_COUNT_NUM 4L
#endif
#ifndef EDGES_PER_COUNT_DEN
#define EDGES_PER_COUNT_DEN 1L
#endif
#ifndef MOTOR_MAX_EDGES_PER_S
#define MOTOR_MAX_EDGES_PER_S 12000L
#endif

#endif
