/* The board's side of the link (docs/protocol.md): frames in and out,
 * sequencing, answers, NAK, HEARTBEAT and the watchdog. */
#ifndef RCL_LINK_H
#define RCL_LINK_H
#include <stdint.h>

void link_init(void);
void link_rx(uint8_t byte);         /* one received byte */
void link_rx_idle(void);            /* no byte waiting: drop a frame cut short */
void link_poll(void);               /* HEARTBEAT and the watchdog */
uint8_t link_up(void);              /* a valid host frame within 250 ms */
#endif
