/* The software PLL of speed.h.
 *
 *   duty = feed-forward (the duty that turns the motor at the reference
 *          rate, from MOTOR_MAX_EDGES_PER_S) + KP * phase error
 *
 * The phase error is the integral of the rate error, so the loop is a PI
 * speed loop that also owes back every edge it fell behind: like the
 * article's PLL, the wheel's distance follows the reference's, not only
 * its speed. The error is clamped (ERR_MAX) so a held wheel does not
 * wind up and lurch when let go. */
#include "speed.h"
#include "config.h"

#define EDGES_PER_MS_Q16 ((REF_CLOCK_HZ * EDGES_PER_COUNT / 1000UL) << 16)   /* / N */
#define FF_NUM (REF_CLOCK_HZ * EDGES_PER_COUNT * 255UL)                      /* / N / max */
#define KP_Q8 51L                           /* 0.2 duty steps per edge of error */
#define ERR_MAX (256L << 16)                /* 64 counts */
#define LOCK_EDGES 8                        /* 2 counts: the STATUS lock bit */

void speed_init(speed_loop *s, int32_t edges)
{
    s->err_q16 = 0;
    s->last_edges = edges;
    s->duty = 0;
    s->locked = 0;
}

static int16_t clamp_duty(int32_t d)
{
    if (d > 255)
        return 255;
    if (d < -255)
        return -255;
    return (int16_t)d;
}

int16_t speed_step(speed_loop *s, uint32_t n, uint8_t run, uint8_t rev,
                   int32_t edges, uint8_t ms)
{
    int32_t moved = edges - s->last_edges;
    int32_t inc, ff, p;

    s->last_edges = edges;
    if (!run || n == 0) {
        s->err_q16 = 0;             /* a new GO starts locked where the wheel is */
        s->locked = 0;
        s->duty = 0;
        return 0;
    }
    inc = (int32_t)(EDGES_PER_MS_Q16 / n) * ms;
    ff = (int32_t)(FF_NUM / n / MOTOR_MAX_EDGES_PER_S);
    if (rev) {
        inc = -inc;
        ff = -ff;
    }
    s->err_q16 += inc - moved * 65536L;
    if (s->err_q16 > ERR_MAX)
        s->err_q16 = ERR_MAX;
    if (s->err_q16 < -ERR_MAX)
        s->err_q16 = -ERR_MAX;
    p = ((s->err_q16 >> 8) * KP_Q8) >> 16;   /* |err| <= 2^24: no overflow */
    s->locked = s->err_q16 < (LOCK_EDGES * 65536L) && s->err_q16 > -(LOCK_EDGES * 65536L);
    s->duty = clamp_duty(ff + p);
    return s->duty;
}
