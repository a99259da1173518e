/* UART0 of the simulated AVR on a pseudo-terminal, at the wire's pace.
 *
 * simavr's own uart_pty part runs a thread of its own, prints its own
 * banner on stdout and makes /tmp/simavr-uart* links that two harnesses
 * running at once would fight over; and it feeds bytes to the UART as
 * fast as they come. This bridge runs in the simulation's thread and
 * hands the UART one byte per byte time of 115200 8N1 in simulated time,
 * as a serial line would, however fast the host writes into the pty.
 */
#ifndef RCL_SIMAVR_BRIDGE_H
#define RCL_SIMAVR_BRIDGE_H

#include <stddef.h>
#include <stdint.h>

#include "avr_uart.h"
#include "sim_avr.h"

#define BRIDGE_QUEUE 65536          /* host bytes not yet on the wire */

typedef void (*bridge_byte_fn)(void *ctx, uint8_t byte, int to_board,
                               avr_cycle_count_t when);

typedef struct bridge {
    avr_t *avr;
    int master;                     /* pty master, non-blocking */
    char slave_name[64];
    int host_present;               /* the slave is open at the other end */
    int cut;                        /* the wire is cut: bytes lost both ways */
    avr_irq_t *uart_in;             /* simavr's UART0 input IRQ */
    avr_uart_t *uart;               /* its state, for the byte time */
    avr_cycle_count_t byte_cycles;  /* one 8N1 byte at 115200 baud */
    uint8_t queue[BRIDGE_QUEUE];    /* host -> board, not yet sent */
    size_t head, count;
    uint8_t out[4096];              /* board -> host, not yet written */
    size_t out_len;
    unsigned long to_board, from_board, dropped_in, dropped_out, lost_to_cut;
    double last_sent_wall;          /* wall time the board last sent a byte */
    bridge_byte_fn on_byte;         /* every byte each way, for the stats */
    void *on_byte_ctx;
} bridge;

/* Open the pty and connect to UART0; 0 on success, -1 (errno set). */
int bridge_open(bridge *b, avr_t *avr, long baud);

/* Move bytes between the pty and the simulation: read what the host
 * wrote, write what the board sent. Call often (every slice). */
void bridge_pump(bridge *b);

/* Cut the wire (1) or mend it (0): what is on it is lost. */
void bridge_cut(bridge *b, int cut);

/* After an AVR reset, which cancels every cycle timer. */
void bridge_rearm(bridge *b);

void bridge_close(bridge *b);

#endif
