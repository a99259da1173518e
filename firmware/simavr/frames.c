/* The frame watcher of frames.h. */
#include "frames.h"

#include <math.h>
#include <string.h>

void acc_add(acc *a, double x)
{
    if (a->n == 0 || x < a->min)
        a->min = x;
    if (a->n == 0 || x > a->max)
        a->max = x;
    a->n++;
    a->sum += x;
    a->sumsq += x * x;
}

double acc_mean(const acc *a)
{
    return a->n ? a->sum / a->n : 0.0;
}

double acc_rms_dev(const acc *a)
{
    double m = acc_mean(a);
    double v;

    if (a->n < 2)
        return 0.0;
    v = a->sumsq / a->n - m * m;
    return v > 0.0 ? sqrt(v) : 0.0;
}

/* CRC-16/CCITT-FALSE, docs/protocol.md section 1 */
static uint16_t crc16(const uint8_t *p, int n)
{
    uint16_t crc = 0xFFFF;

    while (n--) {
        crc ^= (uint16_t)(*p++) << 8;
        for (int i = 0; i < 8; i++)
            crc = (crc & 0x8000) ? (uint16_t)((crc << 1) ^ 0x1021)
                                 : (uint16_t)(crc << 1);
    }
    return crc;
}

static int known_type(const frame_rx *rx, uint8_t type)
{
    if (rx->from_board)
        return type >= 0x81 && type <= 0x87;
    return type >= 0x01 && type <= 0x0F;
}

static void drop(frame_rx *rx, int k)
{
    memmove(rx->buf, rx->buf + k, (size_t)(rx->n - k));
    memmove(rx->when, rx->when + k, (size_t)(rx->n - k) * sizeof rx->when[0]);
    rx->n -= k;
}

static void on_tick(link_watch *w, const uint8_t *payload,
                    avr_cycle_count_t at)
{
    uint16_t tick = (uint16_t)(payload[0] | payload[1] << 8);
    uint16_t step = (uint16_t)(tick - w->last_tick);

    /* a TICK sent again on the host's NAK is not a new tick: its time
     * says nothing about the tick period */
    if (w->have_tick && (step == 0 || step >= 0x8000))
        return;
    if (w->have_tick) {
        if (step == 1) {
            acc_add(&w->period_us, (double)(at - w->last_tick_at) * 1e6 / w->hz);
            acc_add(&w->per_tick[0], (double)w->bytes_in[0]);
            acc_add(&w->per_tick[1], (double)w->bytes_in[1]);
        } else {
            w->missed += (unsigned long)(step - 1);
        }
    }
    w->have_tick = 1;
    w->last_tick = tick;
    w->last_tick_at = at;
    w->tick_at[tick & 63] = at;
    w->ticks++;
    w->bytes_in[0] = w->bytes_in[1] = 0;
}

/* IDENTIFY: the board is as at power-on (docs/protocol.md, "Sessions"),
 * its tick count from 0 again. What was known of the last host's ticks
 * is forgotten, or the new ticks would read as repeats of old ones (a
 * lower number) and the host as far behind: board time held for it. */
static void new_session(link_watch *w)
{
    w->sessions++;
    w->have_tick = 0;
    w->last_tick = 0;
    w->have_answer = 0;
    w->answered = 0;
}

/* Which host frame still waits for the board's answer (section 3): the
 * board must be let run until it has answered. PING and WAIT get none. */
static void track_answers(link_watch *w, int from_board, uint8_t seq,
                          uint8_t type, uint8_t first)
{
    if (!from_board) {
        if (type != 0x0C && type != 0x0F) {
            w->awaiting = 1;
            w->awaiting_seq = seq;
            w->awaiting_type = type;
        }
        return;
    }
    if (!w->awaiting)
        return;
    if (w->awaiting_type == 0x01)             /* HELLO: IDENTIFY */
        w->awaiting = type != 0x81;
    else if (w->awaiting_type == 0x0D)        /* NAK: the frame sent again */
        w->awaiting = 0;
    else if (type == 0x82 || type == 0x83 || type == 0x86 || type == 0x87)
        w->awaiting = first != w->awaiting_seq;
}

/* Section 1's receiver: a good frame is acted on (counted); a bad one
 * loses only its SYNC byte, since a real frame may begin inside it. */
static void scan(link_watch *w, frame_rx *rx)
{
    for (;;) {
        int k = 0, len;
        while (k < rx->n && rx->buf[k] != FRAME_SYNC)
            k++;
        if (k)
            drop(rx, k);
        if (rx->n < 2)
            return;
        len = rx->buf[1];
        if (len > FRAME_MAX_PAYLOAD) {
            drop(rx, 1);
            continue;
        }
        if (rx->n < len + 6)
            return;
        if (crc16(rx->buf + 1, len + 3) !=
                (uint16_t)(rx->buf[len + 4] << 8 | rx->buf[len + 5]) ||
            !known_type(rx, rx->buf[3])) {
            rx->bad++;
            drop(rx, 1);
            continue;
        }
        rx->good++;
        if (rx->from_board && rx->buf[3] == FRAME_IDENTIFY)
            new_session(w);
        if (w->on_frame)
            w->on_frame(w->on_frame_ctx, rx->from_board, rx->buf, len + 6,
                        rx->when[0]);
        if (!rx->from_board)
            w->last_host_frame = rx->when[len + 5];
        rx->by_type[rx->buf[3]]++;
        if (rx->from_board && rx->buf[3] == FRAME_TICK && len >= 4)
            on_tick(w, rx->buf + 4, rx->when[0]);
        if (!rx->from_board && rx->buf[3] == FRAME_TICK_DONE && len >= 5 &&
            rx->buf[6] == 1) {
            w->answered = (uint16_t)(rx->buf[4] | rx->buf[5] << 8);
            w->have_answer = 1;
        }
        track_answers(w, rx->from_board, rx->buf[2], rx->buf[3],
                      len ? rx->buf[4] : 0);
        drop(rx, len + 6);
    }
}

void link_watch_init(link_watch *w, double hz)
{
    memset(w, 0, sizeof *w);
    w->hz = hz;
    w->from_board.from_board = 1;
}

void link_watch_byte(link_watch *w, uint8_t byte, int to_board,
                     avr_cycle_count_t when)
{
    frame_rx *rx = to_board ? &w->to_board : &w->from_board;

    w->bytes_in[to_board ? 0 : 1]++;
    rx->buf[rx->n] = byte;
    rx->when[rx->n] = when;
    rx->n++;
    scan(w, rx);
}

avr_cycle_count_t link_watch_host_due(const link_watch *w,
                                      avr_cycle_count_t slack)
{
    uint16_t owed = (uint16_t)(w->answered + 1);

    if (!w->have_tick || !w->have_answer || w->answered == w->last_tick ||
        w->awaiting)
        return 0;
    if ((uint16_t)(w->last_tick - owed) >= 64)    /* far behind: its times are gone */
        return 1;
    return w->tick_at[owed & 63] + slack;
}

static void acc_json(FILE *f, const char *name, const acc *a)
{
    fprintf(f, "\"%s\": {\"n\": %lu, \"mean\": %.3f, \"min\": %.3f, "
               "\"max\": %.3f, \"sd\": %.3f}",
            name, a->n, acc_mean(a), a->min, a->max, acc_rms_dev(a));
}

static void types_json(FILE *f, const frame_rx *rx)
{
    const char *sep = "";

    fputc('{', f);
    for (int t = 0; t < 256; t++) {
        if (rx->by_type[t]) {
            fprintf(f, "%s\"0x%02X\": %lu", sep, t, rx->by_type[t]);
            sep = ", ";
        }
    }
    fputc('}', f);
}

void link_watch_json(const link_watch *w, FILE *f)
{
    fprintf(f, "\"sessions\": %lu, \"last_tick\": %u, \"answered_tick\": %u, ",
            w->sessions, w->last_tick, w->answered);
    fprintf(f, "\"tick_frames\": %lu, \"ticks_missed\": %lu, "
               "\"last_host_frame_s\": %.6f, ",
            w->ticks, w->missed, (double)w->last_host_frame / w->hz);
    acc_json(f, "tick_period_us", &w->period_us);
    fputs(", ", f);
    acc_json(f, "bytes_per_tick_to_board", &w->per_tick[0]);
    fputs(", ", f);
    acc_json(f, "bytes_per_tick_from_board", &w->per_tick[1]);
    fprintf(f, ", \"frames_to_board\": {\"good\": %lu, \"bad\": %lu, \"types\": ",
            w->to_board.good, w->to_board.bad);
    types_json(f, &w->to_board);
    fprintf(f, "}, \"frames_from_board\": {\"good\": %lu, \"bad\": %lu, \"types\": ",
            w->from_board.good, w->from_board.bad);
    types_json(f, &w->from_board);
    fputc('}', f);
}
