/* The software PLL of speed.h.
 *
 *   duty = feed-forward (the duty that turns the motor at the reference
 *          rate, from MOTOR_MAX_EDGES_PER_S)
 *        + KP * phase error + KD * its slope over the last 4 ms
 *
 * The phase error is the integral of the rate error, so the loop is a PI
 * speed loop that also owes back every edge it fell behind: like the
 * article's PLL, the wheel's distance follows the reference's, not only
 * its speed. The slope term damps it (it is the rate error, measured
 * over 4 ms so that one encoder edge is not a kick). The gains place
 * the phase error within 2 counts through RCL's ramps (measured on
 * model/motor.c: 12,000 edges/s, 50 ms); docs/firmware.md says how to
 * retune. The error is clamped (ERR_MAX) so a held wheel does not wind
 * up and lurch when let go. */
#include "speed.h"
#include "config.h"

/* edges per ms << 16, and the feed-forward duty, times N (folded at
 * compile time in 64 bits; the results fit 32) */
#define EDGES_PER_MS_Q16 ((uint32_t)(((uint64_t)(REF_CLOCK_HZ / 1000) * EDGES_PER_COUNT_NUM << 16) \
                                     / EDGES_PER_COUNT_DEN))
#define FF_NUM ((uint32_t)((uint64_t)REF_CLOCK_HZ * 255 * EDGES_PER_COUNT_NUM / EDGES_PER_COUNT_DEN))
#ifndef KP_Q8
#define KP_Q8 512L                          /* 2 duty steps per edge of phase error */
#endif
#ifndef KD_Q8
#define KD_Q8 2048L                         /* 8 duty steps per edge per 4 ms */
#endif
#define ERR_MAX (256L << 16)                /* 64 counts */
/* Bounds of a step's terms, 8192 edges each (2^29 << 16): the sum with
 * the error stays under 2^31. The error is clamped to +-ERR_MAX after
 * the step, so a larger advance (a step over 16 x N ms late) ends the
 * same way, unless the wheel also moved over 8192 edges in that step
 * (32,000 edges/s: no motor here) */
#define INC_MAX (1L << 29)
#define MOVED_MAX 8192L
#define LOCK_EDGES 8                        /* 2 counts: the STATUS lock bit */

static void forget(speed_loop *s)
{
    s->err_q16 = 0;
    for (uint8_t i = 0; i < 4; i++)
        s->past_q16[i] = 0;
    s->locked = 0;
    s->duty = 0;
}

void speed_init(speed_loop *s, uint32_t edges)
{
    forget(s);
    s->at = 0;
    s->n = 0;
    s->last_edges = edges;
}

static int16_t clamp_duty(int32_t d)
{
    if (d > 255)
        return 255;
    if (d < -255)
        return -255;
    return (int16_t)d;
}

static int32_t clamp_err(int32_t e)
{
    if (e > ERR_MAX)
        return ERR_MAX;
    if (e < -ERR_MAX)
        return -ERR_MAX;
    return e;
}

/* The reference's advance over `ms`, edges << 16: EDGES_PER_MS_Q16 / n
 * a ms exactly, its remainder summed in inc_part and carried, so the
 * reference never drifts from 125,000 / N counts a second. */
static int32_t advance(speed_loop *s, uint8_t ms)
{
    uint32_t part = s->inc_part + s->inc_rem * ms;      /* < 2^16 x 257 */
    uint32_t carry = 0;

    if (ms == 1) {                  /* the usual step: no division */
        if (part >= s->n) {
            part -= s->n;
            carry = 1;
        }
    } else {
        carry = part / s->n;
        part -= carry * s->n;
    }
    s->inc_part = part;
    if (ms > 1 && s->inc_q16 > (INC_MAX - (int32_t)carry) / ms)
        return INC_MAX;
    return s->inc_q16 * ms + (int32_t)carry;
}

int16_t speed_step(speed_loop *s, uint32_t n, uint8_t run, uint8_t rev,
                   uint32_t edges, uint8_t ms)
{
    int32_t moved = edges_between(edges, s->last_edges);
    int32_t inc, ff, p, d, slope;

    s->last_edges = edges;
    if (!run || n == 0) {
        forget(s);                  /* a new GO starts locked where the wheel is */
        return 0;
    }
    if (ms == 0)
        return s->duty;
    if (n != s->n) {
        s->n = n;
        s->inc_q16 = (int32_t)(EDGES_PER_MS_Q16 / n);
        s->inc_rem = EDGES_PER_MS_Q16 % n;
        s->inc_part = 0;
        s->ff = (int32_t)(FF_NUM / n / MOTOR_MAX_EDGES_PER_S);
    }
    inc = advance(s, ms);
    ff = s->ff;
    if (rev) {
        inc = -inc;
        ff = -ff;
    }
    if (moved > MOVED_MAX)
        moved = MOVED_MAX;
    else if (moved < -MOVED_MAX)
        moved = -MOVED_MAX;
    s->err_q16 = clamp_err(s->err_q16 + inc - moved * 65536L);
    slope = s->err_q16 - s->past_q16[s->at];           /* over the last 4 steps */
    s->past_q16[s->at] = s->err_q16;
    s->at = (uint8_t)((s->at + 1) & 3);
    /* |err| <= 2^24 and |slope| <= 2^25: the products fit 32 bits */
    p = ((s->err_q16 >> 8) * KP_Q8) >> 16;
    d = ((slope >> 10) * KD_Q8) >> 14;
    s->locked = s->err_q16 < (LOCK_EDGES * 65536L) && s->err_q16 > -(LOCK_EDGES * 65536L);
    s->duty = clamp_duty(ff + p + d);
    return s->duty;
}
