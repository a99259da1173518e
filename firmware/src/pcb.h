/* The 80188 peripheral control block (I/O 0xFF00-0xFFFF) as far as RCL
 * uses it: the timers' registers, the timer interrupt's mask, request
 * and EOI registers. Timer 0's period (max count A times the input
 * clock, 0.5 us or timer 2's period with P set) is turned into the
 * hardware tick timer's period; each expiry with INT set is one
 * interrupt, held while masked (several held make one, as on the chip). */
#ifndef RCL_PCB_H
#define RCL_PCB_H
#include <stdint.h>

#define T_EN 0x8000u
#define T_INH 0x4000u
#define T_INT 0x2000u
#define T_RIU 0x1000u
#define T_P 0x0008u
#define T_EXT 0x0004u
#define TIMER_MASK_BIT 0x0008u      /* in 0x32 */

typedef struct pcb {
    uint16_t t_count[3], t_max_a[3], t_max_b[2], t_control[3];
    uint16_t timer_control;         /* 0x32: mask bit 3, priority 2-0 */
    uint16_t other_masks;           /* 0x28 without the timer bit */
    uint8_t pending;                /* a timer-0 request waits (masked) */
    uint32_t last_expiry_us;        /* board time of the last expiry */
} pcb;

/* timer 0's period as the chip makes it: `count` clocks of `prescale`
 * half-microseconds, each 1..65536 (kept apart: their product reaches
 * 2^32, which 32 bits do not hold); count 0: timer 0 does not count */
typedef struct pcb_period {
    uint32_t count, prescale;
} pcb_period;

void pcb_power_on(pcb *p);
/* now_us: board time, for timer 0's running count */
uint16_t pcb_read(pcb *p, uint8_t offset, uint32_t now_us);
/* a word write; returns 1 when the tick period may have changed */
uint8_t pcb_write(pcb *p, uint8_t offset, uint16_t word);
pcb_period pcb_tick_period(const pcb *p);
/* The period as a 16-bit timer makes it exactly: a match every `step`
 * half-us (1..65536), a tick every `every`-th match (1..65536). One
 * match a tick when the period fits 16 bits; else the larger factor is
 * the step, so matches are at least 256 half-us apart. */
void pcb_period_split(pcb_period t, uint32_t *step, uint32_t *every);
uint8_t pcb_masked(const pcb *p);
uint8_t pcb_interrupting(const pcb *p);      /* timer 0 enabled with INT */
void pcb_stop_interrupts(pcb *p);            /* TICK_FAILED: INT off, INH set */
#endif
