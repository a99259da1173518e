/* What the portable core needs from a board: a byte stream, a clock,
 * the tick timer, two wheel drivers with encoders, the AUX outputs and
 * the limit switches. One implementation per target (hal/). */
#ifndef RCL_HAL_H
#define RCL_HAL_H
#include <stdint.h>

void hal_init(void);
const char *hal_name(void);         /* the board, for IDENTIFY */

int hal_getc(void);                 /* next received byte, -1 if none */
/* waits while the send buffer is full, a bounded time (a byte that
 * still finds no room is lost, and counted) */
void hal_putc(uint8_t byte);

uint32_t hal_micros(void);          /* board time in us, wraps at 2^32 */
/* the clock of HEARTBEAT, which the host's 250 ms silence rule reads:
 * board time on a microcontroller; the wall clock on the native board,
 * whose board time may wait for the host or run faster than real time
 * (the watchdog keeps to board time everywhere) */
uint32_t hal_link_micros(void);
uint8_t hal_take_ms(void);          /* 1 ms speed-loop periods since last call */
uint8_t hal_take_ticks(void);       /* tick timer expiries since last call */
/* the tick timer's period: count x prescale half-microseconds, exactly
 * (each 1..65536); count 0 stops it */
void hal_tick_period(uint32_t count, uint32_t prescale);

/* wheel 0 left, 1 right. duty -255..255 (+ forward); brake: both driver
 * inputs low with the enable on (ON = 0); duty 0 without brake coasts. */
void hal_wheel(uint8_t wheel, int16_t duty, uint8_t brake);
uint32_t hal_encoder(uint8_t wheel); /* quadrature edges so far, + forward, mod 2^32 */

void hal_aux(uint8_t aux);          /* AUX latch: arm, gripper, beeper */
uint8_t hal_switches(void);         /* bit 0 arm limit, bit 1 jaw limit: 1 = closed */
void hal_led(uint8_t on);

/* Events for the native build (a test's log, and its pacing: it never
 * runs a tick ahead of the host); nothing on a microcontroller. */
enum { NOTE_HELLO, NOTE_MOTOR, NOTE_WATCHDOG, NOTE_SAFE, NOTE_SILENCE, NOTE_TICK_SENT,
       NOTE_TICK_DONE };
void hal_note(uint8_t event, uint32_t value);

/* 1 while the native board holds its time for the host's answer to a
 * tick (the board then sends HEARTBEATs every 10 ms, so that a lost
 * TICK is asked for again at once and a frame's corrupted LEN byte is
 * passed quickly); always 0 on a microcontroller */
uint8_t hal_holding(void);

/* What went wrong on the line since power-on (saturating counts), and
 * the resets by the hardware watchdog, for IDENTIFY. */
typedef struct hal_errors {
    uint16_t framing, overrun;      /* received bytes: UART frame errors; bytes lost */
    uint16_t lost;                  /* bytes not sent: no room within putc's bound */
    uint8_t watchdog;               /* resets by the hardware watchdog */
} hal_errors;
void hal_errors_get(hal_errors *e);

/* The main loop is alive: a microcontroller's hardware watchdog resets
 * the board (its pins safe first) when this is not called for 64 ms. */
void hal_feed_watchdog(void);
#ifdef TEST_HANG_PORT
void hal_test_hang(uint8_t value);  /* a test image's fault: the main loop stops */
#endif

void hal_args(int argc, char **argv);  /* the native build's options */
void hal_idle(void);                /* nothing to do until the next event */
#endif
