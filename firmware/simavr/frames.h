/* Watching the link's frames go by on the wire, for the figures: the
 * firmware's TICK frames give its tick period and jitter in simulated
 * time (what the host sees, UART queueing included), and the bytes
 * between two TICKs give the bytes per tick each way.
 *
 * The receiver is docs/protocol.md section 1's, so what it counts as a
 * frame is what rcl counts as one.
 */
#ifndef RCL_SIMAVR_FRAMES_H
#define RCL_SIMAVR_FRAMES_H

#include <stdint.h>
#include <stdio.h>

#include "sim_avr.h"

#define FRAME_MAX_PAYLOAD 64
#define FRAME_MAX (FRAME_MAX_PAYLOAD + 6)
#define FRAME_SYNC 0xA5
#define FRAME_TICK 0x84
#define FRAME_TICK_DONE 0x09
#define FRAME_IDENTIFY 0x81

/* A good frame seen on the wire (SYNC to CRC), for a trace. */
typedef void (*frame_fn)(void *ctx, int from_board, const uint8_t *frame,
                         int len, avr_cycle_count_t at);

/* Running figures of one quantity. */
typedef struct acc {
    unsigned long n;
    double sum, sumsq, min, max;
} acc;

void acc_add(acc *a, double x);
double acc_mean(const acc *a);
double acc_rms_dev(const acc *a);     /* standard deviation */

/* One direction's receiver. */
typedef struct frame_rx {
    int from_board;                   /* which types are known */
    uint8_t buf[FRAME_MAX];
    avr_cycle_count_t when[FRAME_MAX];
    int n;
    unsigned long good, bad, by_type[256];
} frame_rx;

typedef struct link_watch {
    double hz;                        /* the AVR's clock */
    frame_rx to_board, from_board;
    int have_tick;
    uint16_t last_tick;
    avr_cycle_count_t last_tick_at;
    unsigned long ticks, missed;
    avr_cycle_count_t last_host_frame; /* end of the last good host frame */
    int have_answer;
    uint16_t answered;                /* the last tick whose final TICK_DONE came */
    avr_cycle_count_t tick_at[64];    /* when each of the last 64 TICKs was first sent */
    int awaiting;                     /* a host frame the board has not answered yet */
    uint8_t awaiting_seq, awaiting_type;
    acc period_us;                    /* one TICK to the next */
    unsigned long bytes_in[2];        /* [to_board, from_board] since last TICK */
    acc per_tick[2];
    unsigned long sessions;           /* IDENTIFYs seen: each starts a session */
    frame_fn on_frame;                /* every good frame, if set */
    void *on_frame_ctx;
} link_watch;

void link_watch_init(link_watch *w, double hz);

/* A byte on the wire, to the board or from it, at cycle `when`. */
void link_watch_byte(link_watch *w, uint8_t byte, int to_board,
                     avr_cycle_count_t when);

/* The host has answered ticks (a final TICK_DONE came), owes a later
 * TICK its answer, and is not waiting for an answer of the board's: ->
 * the cycle `slack` after the first TICK it owes; 0 when none. */
avr_cycle_count_t link_watch_host_due(const link_watch *w,
                                      avr_cycle_count_t slack);

/* The figures as JSON members (no braces), for the stats object. */
void link_watch_json(const link_watch *w, FILE *f);

#endif
