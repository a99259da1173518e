/* The R-E Robot's phase-locked speed loop, in software: the 8253's
 * counter 0 gives the reference, 125,000 / N counts/s; the loop keeps
 * the wheel's encoder phase locked to the reference phase and sets the
 * PWM duty. Run every millisecond. */
#ifndef RCL_SPEED_H
#define RCL_SPEED_H
#include <stdint.h>

typedef struct speed_loop {
    int32_t err_q16;        /* reference phase - wheel phase, edges << 16 */
    int32_t past_q16[4];    /* the error of the last 4 ms, for its slope */
    uint8_t at;             /* where the oldest of them is */
    uint32_t last_edges;    /* encoder edges at the last step, mod 2^32 */
    int16_t duty;           /* the last output, -255..255 */
    uint32_t n;             /* the count inc and ff were computed for */
    int32_t inc_q16, ff;    /* per ms; kept: an AVR divides 32 bits slowly */
    uint32_t inc_rem;       /* what inc_q16 leaves of the exact rate, in 1/n */
    uint32_t inc_part;      /* those remainders summed, toward the next (< n) */
    uint8_t locked;         /* |phase error| within LOCK_EDGES */
} speed_loop;

/* edges from `then` to `now` on a counter that wraps at 2^32 (within
 * +-2^31: between two looks, always), without signed overflow */
static inline int32_t edges_between(uint32_t now, uint32_t then)
{
    uint32_t d = now - then;
    return d < 0x80000000UL ? (int32_t)d : -(int32_t)(~d) - 1;
}

void speed_init(speed_loop *s, uint32_t edges);
/* n: counter 0's count (0 = no reference); run: ON and GO; rev: REV;
 * edges: the wheel's encoder edges now; ms: milliseconds since the last
 * step (any 0..255). Returns the duty, -255..255. */
int16_t speed_step(speed_loop *s, uint32_t n, uint8_t run, uint8_t rev,
                   uint32_t edges, uint8_t ms);
#endif
