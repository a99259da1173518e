/* The firmware core's arithmetic, natively, over the ranges a board
 * meets in days of running: the tick's period (exact, no wrap), the
 * speed loop's reference (exact, no overflow) and the encoder counts
 * across their 2^31 and 2^32 wraps; and the link's CRC table against
 * the CRC computed bit by bit. Run by tests/test_firmware_hardening.py;
 * prints one line per check, "ok NAME figures" or "FAIL NAME why", and
 * exits 1 on a failure.
 *
 *   make -C firmware test-programs && firmware/build/core-test */
#include "../src/config.h"
#include "../src/crc16.h"
#include "../src/pcb.h"
#include "../src/speed.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

static int failed;

static void result(int ok, const char *name, const char *figures)
{
    printf("%s %s %s\n", ok ? "ok" : "FAIL", name, figures);
    if (!ok)
        failed = 1;
}

/* Timer 0 as RCL's INSTALL programs it (max count 6667, P: timer 2's
 * prescaler of 3), or any max count and prescale. */
static pcb rcl_timer(uint16_t max_count, uint16_t prescale)
{
    pcb p;

    pcb_power_on(&p);
    pcb_write(&p, 0x62, prescale);             /* timer 2 max count A */
    pcb_write(&p, 0x52, max_count);            /* timer 0 max count A */
    pcb_write(&p, 0x56, (uint16_t)(T_EN | T_INH | T_INT | T_P | 1u));
    return p;
}

/* Every max count with a spread of prescales: the split is the period
 * exactly, in 16-bit steps; 0 x 0 (65536 x 65536) is 2^32 half-us, not 0. */
static void check_split(void)
{
    static const uint32_t prescales[] = { 1, 2, 3, 7, 255, 256, 257, 1000, 4095, 4096,
                                          9999, 32768, 40000, 65535, 65536 };
    unsigned long checked = 0, bad = 0;
    char why[160] = "";

    for (size_t i = 0; i < sizeof prescales / sizeof prescales[0]; i++) {
        for (uint32_t count = 1; count <= 65536; count++) {
            pcb_period t = { count, prescales[i] };
            uint32_t step, every;
            uint64_t period = (uint64_t)count * prescales[i];

            pcb_period_split(t, &step, &every);
            checked++;
            if ((uint64_t)step * every != period || step < 1 || step > 65536
                || every < 1 || every > 65536 || (period > 65536 && step < 256)
                || (period <= 65536 && every != 1)) {
                if (!bad++)
                    snprintf(why, sizeof why, "count %u prescale %u: step %u every %u",
                             (unsigned)count, (unsigned)prescales[i], (unsigned)step,
                             (unsigned)every);
            }
        }
    }
    {
        pcb p = rcl_timer(0, 0);              /* 0 is 65536 for both */
        pcb_period t = pcb_tick_period(&p);
        uint32_t step, every;

        pcb_period_split(t, &step, &every);
        if (t.count != 65536 || t.prescale != 65536 || step != 65536 || every != 65536) {
            bad++;
            snprintf(why, sizeof why, "65536 x 65536 gave %u x %u", (unsigned)t.count,
                     (unsigned)t.prescale);
        }
    }
    {
        char figures[200];
        snprintf(figures, sizeof figures, "pairs=%lu bad=%lu %s", checked, bad, why);
        result(bad == 0, "period_split", figures);
    }
}

/* Timer 0's count register read long after its last expiry: no 32-bit
 * step overflows (the product 2 x elapsed did, past 35 minutes). */
static void check_count_now(void)
{
    pcb p = rcl_timer(0, 0);
    unsigned long bad = 0;

    for (uint64_t e = 0; e < 0x100000000ULL; e += 0x10001ULL * 977) {
        uint64_t clocks = (2 * e) / 65536 % 65536;
        uint16_t got;

        p.last_expiry_us = 12345;
        got = pcb_read(&p, 0x50, (uint32_t)(12345 + e));
        if (got != clocks)
            bad++;
    }
    {
        char figures[64];
        snprintf(figures, sizeof figures, "bad=%lu", bad);
        result(bad == 0, "count_now", figures);
    }
}

/* RCL's tick (6667 x 3) against RCL's ADVANCE over 2,000,000 ticks (5.6
 * hours): the wheel's reference, 125,000 / N counts a second of board
 * time, at each tick's board time, less RCL's q (1,500,075 / N crpm a
 * tick, remainders kept) stays within a count. The 10.000 ms tick the
 * firmware had gains 0.0625 / N counts a tick: 2,500 counts at N = 50. */
static long worst_drift(uint32_t step, uint32_t every, uint32_t n, uint32_t ticks)
{
    uint64_t t_half = 0;                    /* the tick's board time, half-us */
    uint64_t q_crpm = 0;                    /* RCL's q, in 1/1200 counts, times N */
    long worst = 0;

    for (uint32_t k = 1; k <= ticks; k++) {
        int64_t ref_counts, q_counts, d;

        t_half += (uint64_t)step * every;
        q_crpm += 1500075;                  /* exact: ADVANCE's remainders kept */
        /* 125,000 / N counts a second: t_half / 2e6 s */
        ref_counts = (int64_t)(t_half * 125000 / 2000000 / n);
        q_counts = (int64_t)(q_crpm / 1200 / n);
        d = ref_counts - q_counts;
        if (d < 0)
            d = -d;
        if (d > worst)
            worst = (long)d;
    }
    return worst;
}

static void check_tick_against_advance(void)
{
    pcb p = rcl_timer(6667, 3);
    pcb_period t = pcb_tick_period(&p);
    uint32_t step, every;
    long exact, old;
    char figures[160];

    pcb_period_split(t, &step, &every);
    exact = worst_drift(step, every, 50, 2000000);
    old = worst_drift(20000, 1, 50, 2000000);
    snprintf(figures, sizeof figures,
             "period_half_us=%u worst_counts=%ld ten_ms_tick_worst_counts=%ld",
             (unsigned)(step * every), exact, old);
    result(step * every == 20001 && exact <= 1 && old >= 2000, "tick_vs_advance", figures);
}

/* The speed loop's reference, fed a wheel exactly where 125,000 / N
 * counts a second puts it: its phase error stays under an edge at every
 * ms for 10,000,000 ms (2.8 hours) at counts that do not divide it
 * evenly (the quotient alone had lost up to 1/inc of the rate). */
static void check_reference_exact(void)
{
    static const uint32_t counts[] = { 50, 51, 97, 1250, 2500, 9999, 30000, 65535 };
    long worst_q16 = 0;
    char figures[120];

    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; i++) {
        uint32_t n = counts[i];
        speed_loop s;
        uint64_t num = (uint64_t)(REF_CLOCK_HZ / 1000) * EDGES_PER_COUNT_NUM * 65536;
        uint64_t den = (uint64_t)EDGES_PER_COUNT_DEN * n * 65536;

        speed_init(&s, 0);
        for (uint32_t ms = 1; ms <= 10000000; ms++) {
            /* the ideal wheel: ms x 125 x edges-per-count / N edges, whole */
            uint32_t edges = (uint32_t)(ms * num / den);
            long e;

            speed_step(&s, n, 1, 0, edges, 1);
            e = s.err_q16 < 0 ? -s.err_q16 : s.err_q16;
            if (e > worst_q16)
                worst_q16 = e;
        }
    }
    snprintf(figures, sizeof figures, "worst_error_q16=%ld (65536 = an edge)", worst_q16);
    result(worst_q16 < 65536, "reference_exact", figures);
}

/* A long step (the main loop late by up to 255 ms) at counts 1..7, the
 * fastest: the result is the 64-bit one, clamped as the loop clamps. */
static void check_long_steps(void)
{
    unsigned long bad = 0;
    char figures[120] = "";

    for (uint32_t n = 1; n <= 7; n++) {
        for (int ms = 1; ms <= 255; ms++) {
            for (int moved = -300; moved <= 300; moved += 150) {
                speed_loop s;
                int64_t inc, err, max = 256LL << 16;

                speed_init(&s, 1000);
                speed_step(&s, n, 1, 0, 1000, 1);           /* the first ms */
                err = s.err_q16;
                speed_step(&s, n, 1, 0, (uint32_t)(1000 + moved), (uint8_t)ms);
                inc = (int64_t)ms * ((125LL * EDGES_PER_COUNT_NUM << 16) / EDGES_PER_COUNT_DEN) / n;
                err = err + inc - (int64_t)moved * 65536;
                err = err > max ? max : err < -max ? -max : err;
                /* within the reference's remainder, under 1/65536 edge a ms */
                if (s.err_q16 - err > ms || err - s.err_q16 > ms) {
                    if (!bad++)
                        snprintf(figures, sizeof figures, "n %u ms %d moved %d: %ld, not %lld",
                                 (unsigned)n, ms, moved, (long)s.err_q16, (long long)err);
                }
            }
        }
    }
    {
        char out[160];
        snprintf(out, sizeof out, "bad=%lu %s", bad, figures);
        result(bad == 0, "long_steps", out);
    }
}

/* The same run of steps with the encoder's count starting at 0, below
 * 2^31 and below 2^32: the same duties every ms (the counter wrapped
 * through 2^31, a signed overflow before, and through 2^32). */
static void check_edge_wrap(void)
{
    static const uint32_t starts[] = { 0, 0x80000000UL - 3000, 0xFFFFFFFFUL - 3000 };
    int16_t duty[3][2000];
    unsigned long bad = 0;
    char figures[80];

    for (int k = 0; k < 3; k++) {
        speed_loop s;
        uint32_t e = starts[k];

        speed_init(&s, e);
        for (int ms = 0; ms < 2000; ms++) {
            duty[k][ms] = speed_step(&s, 100, 1, 0, e, 1);
            e += (uint32_t)(3 + ms % 3);   /* a wheel at about 4 edges a ms */
        }
    }
    for (int ms = 0; ms < 2000; ms++)
        if (duty[1][ms] != duty[0][ms] || duty[2][ms] != duty[0][ms])
            bad++;
    if (edges_between(5, 0xFFFFFFFEUL) != 7 || edges_between(0x7FFFFFFFUL, 0x80000001UL) != -2
        || edges_between(0x80000000UL, 0x7FFFFFFFUL) != 1)
        bad++;
    snprintf(figures, sizeof figures, "steps=6000 bad=%lu", bad);
    result(bad == 0, "edge_wrap", figures);
}

/* docs/protocol.md section 1's CRC, bit by bit, from `crc` */
static uint16_t crc_bitwise(uint16_t crc, const uint8_t *p, size_t n)
{
    while (n--) {
        crc ^= (uint16_t)(*p++ << 8);
        for (int i = 0; i < 8; i++)
            crc = (crc & 0x8000u) ? (uint16_t)((crc << 1) ^ 0x1021u) : (uint16_t)(crc << 1);
    }
    return crc;
}

/* Every table entry (each byte after 256 CRC states, one per high
 * byte), and the standard check value of "123456789". */
static void check_crc_table(void)
{
    static const uint8_t check[] = "123456789";
    unsigned long bad = 0;
    char figures[64];

    for (unsigned hi = 0; hi < 256; hi++)
        for (unsigned byte = 0; byte < 256; byte++) {
            uint16_t crc = (uint16_t)(hi << 8 | (hi ^ 0x5Au));
            uint8_t b = (uint8_t)byte;
            if (crc16_update(crc, b) != crc_bitwise(crc, &b, 1))
                bad++;
        }
    if (crc16(check, 9) != 0x29B1 || crc_bitwise(0xFFFF, check, 9) != 0x29B1)
        bad++;
    snprintf(figures, sizeof figures, "pairs=65536 check=0x%04X bad=%lu", crc16(check, 9), bad);
    result(bad == 0, "crc_table", figures);
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : "";

    if (!*only || !strcmp(only, "period_split"))
        check_split();
    if (!*only || !strcmp(only, "count_now"))
        check_count_now();
    if (!*only || !strcmp(only, "tick_vs_advance"))
        check_tick_against_advance();
    if (!*only || !strcmp(only, "reference_exact"))
        check_reference_exact();
    if (!*only || !strcmp(only, "long_steps"))
        check_long_steps();
    if (!*only || !strcmp(only, "edge_wrap"))
        check_edge_wrap();
    if (!*only || !strcmp(only, "crc_table"))
        check_crc_table();
    return failed;
}
