/* rcl board firmware: the R-E Robot's I/O behind rcl's link protocol.
 * One loop, no threads: bytes in, the board's timers, the link's. */
#include "board.h"
#include "config.h"
#include "hal.h"
#include "link.h"

int main(int argc, char **argv)
{
    hal_args(argc, argv);
    hal_init();
    board_power_on();
    link_init();
    for (;;) {
        int c = -1;
        uint8_t busy = 0;

        /* a bounded helping of input, then the timers: a flood of
         * garbage must not keep the tick waiting */
        for (uint8_t n = 0; n < INPUT_PER_PASS && (c = hal_getc()) >= 0; n++) {
            link_rx((uint8_t)c);
            busy = 1;
        }
        if (c < 0)
            link_rx_idle();         /* everything waiting was read */
        board_poll();
        link_poll();
        hal_feed_watchdog();        /* a pass done: the loop is alive */
        if (!busy)
            hal_idle();
    }
}
