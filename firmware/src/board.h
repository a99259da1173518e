/* The R-E Robot's board as the host sees it: ports 0x80-0x8A, the PCB,
 * the vector table and BIOS data area, the per-tick script, and the
 * BIOS's timer-0 handler (count the tick, run the script, INT 1Ch). */
#ifndef RCL_BOARD_H
#define RCL_BOARD_H
#include <stdint.h>

void board_power_on(void);
void board_out8(uint16_t port, uint8_t value);
uint8_t board_in8(uint16_t port);
void board_out16(uint16_t port, uint16_t value);
uint16_t board_in16(uint16_t port);
void board_far_store(uint16_t seg, uint16_t off, uint8_t value);
uint8_t board_far_fetch(uint16_t seg, uint16_t off);
/* a script of 4-byte records (op, port lo, port hi, value); the IN8
 * bytes go to results; -> how many */
uint8_t board_run(const uint8_t *ops, uint8_t n, uint8_t *results);
void board_set_script(const uint8_t *ops, uint8_t n);
void board_safe(void);              /* MOTOR 0, AUX arm/gripper/beeper off */
void board_tick_failed(void);       /* safe, and timer 0 stops interrupting */
uint8_t board_ticking(void);        /* a TICK will come (HEARTBEAT's flag) */
void board_poll(void);              /* run the speed loop and the timer */
uint16_t board_tick_count(void);    /* timer-0 interrupts serviced, mod 2^16 */

/* the link's side: a timer-0 interrupt with INT 1Ch in the Forth segment */
void link_send_tick(uint16_t tick, uint16_t off, const uint8_t *results, uint8_t n);
#endif
