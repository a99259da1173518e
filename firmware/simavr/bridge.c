/* The pty <-> UART0 bridge of bridge.h. */
#define _GNU_SOURCE
#include "bridge.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include "avr_uart.h"
#include "sim_cycle_timers.h"
#include "sim_irq.h"
#include "sim_time.h"

/* One byte off the queue onto the wire each byte time, while any wait. */
static avr_cycle_count_t send_next(avr_t *avr, avr_cycle_count_t when,
                                   void *param)
{
    bridge *b = param;
    uint8_t byte;

    (void)avr;
    if (b->count == 0)
        return 0;
    byte = b->queue[b->head];
    b->head = (b->head + 1) % BRIDGE_QUEUE;
    b->count--;
    b->to_board++;
    if (b->on_byte)
        b->on_byte(b->on_byte_ctx, byte, 1, when);
    avr_raise_irq(b->uart_in, byte);
    return b->count ? when + b->byte_cycles : 0;
}

static double wall_now(void)
{
    struct timespec t;

    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + t.tv_nsec * 1e-9;
}

/* A byte the firmware wrote to UDR0: simavr raises this as the byte
 * starts on the wire, paced by its own UDRE timing. */
static void board_sent(avr_irq_t *irq, uint32_t value, void *param)
{
    bridge *b = param;

    (void)irq;
    if (b->cut) {
        b->lost_to_cut++;
        return;
    }
    b->from_board++;
    b->last_sent_wall = wall_now();
    if (b->on_byte)
        b->on_byte(b->on_byte_ctx, (uint8_t)value, 0, b->avr->cycle);
    if (b->out_len < sizeof b->out)
        b->out[b->out_len++] = (uint8_t)value;
    else
        b->dropped_out++;
}

/* The wire starts 1 byte time after the first byte queued; later bytes
 * follow back to back (send_next re-arms itself). */
static void enqueue(bridge *b, const uint8_t *p, size_t n)
{
    int idle = b->count == 0;

    if (b->cut) {
        b->lost_to_cut += n;
        return;
    }
    for (size_t i = 0; i < n; i++) {
        if (b->count == BRIDGE_QUEUE) {
            b->dropped_in += n - i;
            break;
        }
        b->queue[(b->head + b->count) % BRIDGE_QUEUE] = p[i];
        b->count++;
    }
    if (idle && b->count &&
        avr_cycle_timer_status(b->avr, send_next, b) == 0)
        avr_cycle_timer_register(b->avr, b->byte_cycles, send_next, b);
}

int bridge_open(bridge *b, avr_t *avr, long baud)
{
    struct termios raw;
    int slave;
    uint32_t flags = 0;

    memset(b, 0, sizeof *b);
    b->avr = avr;
    b->last_sent_wall = wall_now();
    /* 10 bits a byte: start, 8 data, stop */
    b->byte_cycles = (avr_cycle_count_t)((10.0 * avr->frequency) / baud + 0.5);
    memset(&raw, 0, sizeof raw);
    cfmakeraw(&raw);
    if (openpty(&b->master, &slave, b->slave_name, &raw, NULL) < 0)
        return -1;
    /* Closed here so that the master sees a hang-up until a host opens
     * the slave: what the board sends then is lost, as on a cable with
     * nobody at the other end, not stored for the next host to read. */
    close(slave);
    fcntl(b->master, F_SETFL, fcntl(b->master, F_GETFL) | O_NONBLOCK);
    b->uart_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    for (avr_io_t *io = avr->io_port; io; io = io->next)
        if (strcmp(io->kind, "uart") == 0 && ((avr_uart_t *)io)->name == '0')
            b->uart = (avr_uart_t *)io;
    avr_irq_register_notify(
        avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT),
        board_sent, b);
    /* simavr's polling sleep would stall the simulation on every status
     * read; this harness paces time itself */
    avr_ioctl(avr, AVR_IOCTL_UART_GET_FLAGS('0'), &flags);
    flags &= ~AVR_UART_FLAG_POLL_SLEEP;
    flags &= ~AVR_UART_FLAG_STDIO;
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    return 0;
}

static void read_host(bridge *b)
{
    uint8_t buf[4096];

    for (;;) {
        ssize_t n = read(b->master, buf, sizeof buf);
        if (n <= 0)
            return;
        enqueue(b, buf, (size_t)n);
    }
}

static void write_host(bridge *b)
{
    size_t done = 0;

    if (!b->host_present) {
        b->dropped_out += b->out_len;
        b->out_len = 0;
        return;
    }
    while (done < b->out_len) {
        ssize_t n = write(b->master, b->out + done, b->out_len - done);
        if (n <= 0)
            break;
        done += (size_t)n;
    }
    /* a host that does not read: the line has no flow control */
    b->dropped_out += b->out_len - done;
    b->out_len = 0;
}

/* ATmega328P USART0 registers (data-space addresses) */
#define R_UCSR0A 0xC0
#define R_UCSR0B 0xC1
#define R_UCSR0C 0xC2
#define R_UBRR0L 0xC4
#define R_UBRR0H 0xC5

/* simavr 1.6 times every UART byte as if it had a parity bit (11 bits
 * for 8N1), so the simulated UART both sends and takes bytes 10 % slower
 * than the AVR does, and a long burst from the 115200 wire overruns its
 * receive FIFO. Put the AVR's own byte time back, from the same
 * registers simavr reads. */
static void fix_uart_timing(bridge *b)
{
    const uint8_t *d = b->avr->data;
    unsigned ubrr = d[R_UBRR0L] | (d[R_UBRR0H] & 0x0Fu) << 8;
    unsigned size = d[R_UCSR0C] >> 1 & 3u;
    unsigned bits = 1 + (size == 3 ? 8 : 5 + size) + (d[R_UCSR0B] >> 2 & 1u) +
                    ((d[R_UCSR0C] >> 4 & 3u) ? 1 : 0) + 1 + (d[R_UCSR0C] >> 3 & 1u);
    avr_cycle_count_t per_bit = (ubrr + 1) * ((d[R_UCSR0A] >> 1 & 1u) ? 8 : 16);

    if (b->uart)
        b->uart->cycles_per_byte = per_bit * bits;
}

void bridge_pump(bridge *b)
{
    struct pollfd p = { .fd = b->master, .events = POLLIN };

    fix_uart_timing(b);
    if (poll(&p, 1, 0) < 0)
        return;
    b->host_present = !(p.revents & POLLHUP);
    if (p.revents & POLLIN)
        read_host(b);
    write_host(b);
}

void bridge_cut(bridge *b, int cut)
{
    b->cut = cut;
    if (cut) {
        b->lost_to_cut += b->count;
        b->count = 0;
    }
}

void bridge_rearm(bridge *b)
{
    if (b->count && avr_cycle_timer_status(b->avr, send_next, b) == 0)
        avr_cycle_timer_register(b->avr, b->byte_cycles, send_next, b);
}

void bridge_close(bridge *b)
{
    if (b->master >= 0)
        close(b->master);
    b->master = -1;
}
