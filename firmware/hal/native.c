/* The native Linux board: the core behind a pseudo-terminal, with the
 * motor model of model/motor.c in place of the pins.
 *
 *   rcl-firmware-native [--rate R] [--edges-from E]
 *
 * prints the pty's path as the first line of stdout, then a line per
 * event (hello, motor latch, safe state, watchdog) with the board time
 * and tick count, for tests. Board time follows the wall clock times R
 * (default 1) in 1 ms steps, and never catches up: after a stall (the
 * process not scheduled) it goes on from where it was, as if the board
 * had been paused, so no tick is ever due that the host could not have
 * answered. Nor does it run far ahead of the host: past HOST_SLACK_US of
 * board time after a TICK, it waits until the host has finished that
 * tick (its final TICK_DONE), for at most HOLD_MAX_US of wall time, and
 * not once the watchdog has tripped; so the handler's writes land within
 * HOST_SLACK_US of their tick however slow the host (as rcl-simavr's
 * harness holds the Uno). A host that keeps up (a round trip over the
 * pty is about 1 ms) never meets the wait,
 * and the board runs free as firmware on a microcontroller does; a host
 * stalled by a busy machine finds the board where it left it, its
 * watchdog (board time) not tripped by the wait. HEARTBEATs keep to the
 * wall clock, as the host's silence rule does. --edges-from E starts both
 * encoders' edge counters at E (mod 2^32) instead of 0, as a board that
 * has run for days has them. The tick timer keeps timer 0's period in
 * half-us exactly: a tick falls in the 1 ms step its time falls in, and
 * the ticks' mean period is the 80188's (RCL's 10.0005 ms), never 10. */
#define _GNU_SOURCE                 /* ppoll */
#include "../src/hal.h"
#include "../model/motor.h"
#include "../src/config.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#define STEP_US 1000u               /* physics and speed-loop step */
#define MAX_BEHIND_US 2000.0        /* more behind than this is dropped, not caught up */
#define HOLD_MAX_US 1000000.0       /* the host's own give-up time for an answer */
#define HOST_SLACK_US 3000u         /* board time a host may take to answer a TICK
                                       before the board waits for it */

static struct {
    int master, slave;
    double rate;
    double wall_us;                 /* wall clock at the last step, us */
    double owed_us;                 /* board time due but not yet stepped */
    uint32_t now_us;                /* board time */
    uint8_t ms, ticks;              /* steps and tick expiries not yet taken */
    uint64_t period_half, tick_left_half;   /* the tick timer, in half-us */
    uint32_t edges_from;
    uint16_t lost;                  /* bytes dropped: the line's buffer full */
    uint32_t tick_total;
    int waiting;                    /* a TICK sent, its final TICK_DONE not come */
    int host_gone;                  /* a wait ran out, or the watchdog tripped */
    uint16_t waiting_tick;
    double waiting_since;           /* wall us */
    uint32_t waiting_from;          /* board time (us) the TICK was sent at */
    unsigned long holds;            /* steps a tick waited for the host */
    motor wheel[2];
    double drive[2];
    uint8_t out[4096];
    size_t out_n;
} n = { .rate = 1.0 };

const char *hal_name(void)
{
    return "rcl-firmware " FIRMWARE_VERSION_STRING " (native)";
}

void hal_args(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--rate") && i + 1 < argc) {
            n.rate = atof(argv[++i]);
            if (n.rate <= 0.0)
                n.rate = 1.0;
        } else if (!strcmp(argv[i], "--edges-from") && i + 1 < argc) {
            n.edges_from = (uint32_t)strtoul(argv[++i], NULL, 0);
        } else {
            fprintf(stderr, "usage: %s [--rate R] [--edges-from E]\n", argv[0]);
            exit(2);
        }
    }
}

static double wall_us(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e6 + (double)t.tv_nsec / 1e3;
}

static void open_pty(void)
{
    struct termios t;
    const char *path;

    n.master = posix_openpt(O_RDWR | O_NOCTTY);
    if (n.master < 0 || grantpt(n.master) || unlockpt(n.master)) {
        perror("pty");
        exit(1);
    }
    path = ptsname(n.master);
    /* held open by us too: the pty stays raw, and the master never reads
     * EIO between two hosts */
    n.slave = open(path, O_RDWR | O_NOCTTY);
    if (n.slave < 0 || tcgetattr(n.slave, &t)) {
        perror(path);
        exit(1);
    }
    cfmakeraw(&t);
    tcsetattr(n.slave, TCSANOW, &t);
    fcntl(n.master, F_SETFL, fcntl(n.master, F_GETFL) | O_NONBLOCK);
    printf("%s\n", path);
    fflush(stdout);
}

void hal_init(void)
{
    motor_params p;

    open_pty();
    motor_default_params(&p);
    motor_init(&n.wheel[0], &p);
    motor_init(&n.wheel[1], &p);
    n.wall_us = wall_us();
}

/* ------------------------------------------------------------- time */

/* The host owes the last TICK's answer, and the board has gone on for
 * HOST_SLACK_US since (or the next tick is due within this step). */
static int owed(void)
{
    return n.waiting && n.period_half
        && (n.now_us - n.waiting_from >= HOST_SLACK_US
            || n.tick_left_half <= 2 * STEP_US);
}

/* Wait for the host's answer (a bounded time). */
static int held(double wall)
{
    if (!owed())
        return 0;
    if (wall - n.waiting_since > HOLD_MAX_US) {
        n.waiting = 0;              /* the host has gone: run free until it answers */
        n.host_gone = 1;
        return 0;
    }
    n.holds++;
    return 1;
}

uint8_t hal_holding(void)
{
    return (uint8_t)owed();
}

static void step(void)
{
    for (int w = 0; w < 2; w++)
        motor_step(&n.wheel[w], n.drive[w], STEP_US / 1e6);
    n.now_us += STEP_US;
    if (n.ms < 255)
        n.ms++;
    if (n.period_half) {
        if (n.tick_left_half <= 2 * STEP_US) {     /* due within this step */
            n.tick_left_half += n.period_half;
            n.ticks++;
            n.tick_total++;
        }
        n.tick_left_half -= 2 * STEP_US;
    }
}

/* Bring board time up to the wall clock, by whole steps, no catching up. */
static void pace(void)
{
    double w = wall_us();

    n.owed_us += (w - n.wall_us) * n.rate;
    n.wall_us = w;
    if (n.owed_us > MAX_BEHIND_US)
        n.owed_us = MAX_BEHIND_US;
    while (n.owed_us >= STEP_US) {
        if (held(w)) {
            n.owed_us = 0.0;        /* held time is not owed afterwards */
            return;
        }
        n.owed_us -= STEP_US;
        step();
    }
}

uint32_t hal_micros(void)
{
    return n.now_us;
}

uint32_t hal_link_micros(void)
{
    return (uint32_t)(uint64_t)wall_us();
}

uint8_t hal_take_ms(void)
{
    uint8_t ms;

    pace();
    ms = n.ms;
    n.ms = 0;
    return ms;
}

uint8_t hal_take_ticks(void)
{
    uint8_t t = n.ticks;
    n.ticks = 0;
    return t;
}

void hal_tick_period(uint32_t count, uint32_t prescale)
{
    /* a period under a step ticks at most once a step (the core never
     * asks for one: TICK_MIN_HALF_US) */
    n.period_half = (uint64_t)count * prescale;
    if (n.period_half && n.period_half < 2 * STEP_US)
        n.period_half = 2 * STEP_US;
    n.tick_left_half = n.period_half;
    n.ticks = 0;
}

void hal_idle(void)
{
    /* sleep until a byte comes or the next step is due (a busy loop here
     * would take a core from the host on a busy machine) */
    struct pollfd p = { .fd = n.master, .events = POLLIN };
    double wait_us = (STEP_US - n.owed_us) / n.rate;
    struct timespec t;

    if (wait_us < 50.0)
        wait_us = 50.0;
    if (n.out_n)
        p.events |= POLLOUT;
    t.tv_sec = 0;
    t.tv_nsec = (long)(wait_us * 1000.0);
    ppoll(&p, 1, &t, NULL);
}

/* --------------------------------------------------------- the line */

static void flush_out(void)
{
    ssize_t w;

    if (!n.out_n)
        return;
    w = write(n.master, n.out, n.out_n);
    if (w > 0) {
        memmove(n.out, n.out + w, n.out_n - (size_t)w);
        n.out_n -= (size_t)w;
    }
}

int hal_getc(void)
{
    static uint8_t buf[256];
    static ssize_t have, at;

    flush_out();
    if (at < have)
        return buf[at++];
    have = read(n.master, buf, sizeof buf);
    at = 0;
    if (have <= 0) {
        have = 0;
        return -1;
    }
    return buf[at++];
}

void hal_putc(uint8_t byte)
{
    /* a line with nobody reading drops what does not fit, as a UART
     * would, and counts it: the board never waits for a reader */
    if (n.out_n == sizeof n.out)
        flush_out();
    if (n.out_n < sizeof n.out)
        n.out[n.out_n++] = byte;
    else if (n.lost < 0xFFFF)
        n.lost++;
}

void hal_errors_get(hal_errors *e)
{
    /* a pty has no framing or overruns, nor this board a watchdog */
    e->framing = e->overrun = 0;
    e->lost = n.lost;
    e->watchdog = 0;
}

void hal_feed_watchdog(void)
{
}

/* --------------------------------------------------------- the robot */

void hal_wheel(uint8_t wheel, int16_t duty, uint8_t brake)
{
    (void)brake;                    /* the model brakes and coasts alike */
    n.drive[wheel & 1] = duty / 255.0;
}

uint32_t hal_encoder(uint8_t wheel)
{
    return n.edges_from + (uint32_t)n.wheel[wheel & 1].edges;
}

void hal_aux(uint8_t aux)
{
    (void)aux;
}

uint8_t hal_switches(void)
{
    return 0;                       /* no arm or jaw at a limit */
}

void hal_led(uint8_t on)
{
    (void)on;
}

static int pacing_note(uint8_t event, uint32_t value)
{
    if (event == NOTE_TICK_SENT && !n.host_gone) {
        n.waiting = 1;
        n.waiting_tick = (uint16_t)value;
        n.waiting_since = wall_us();
        n.waiting_from = n.now_us;
    } else if (event == NOTE_TICK_DONE) {
        n.host_gone = 0;            /* the host is here again */
        if ((uint16_t)value == n.waiting_tick)
            n.waiting = 0;
    } else if (event == NOTE_HELLO) {
        n.waiting = n.host_gone = 0;        /* a new host: nothing owed */
    } else if (event == NOTE_WATCHDOG) {
        n.waiting = 0;              /* nobody to wait for */
        n.host_gone = 1;
    }
    return event == NOTE_TICK_SENT || event == NOTE_TICK_DONE;
}

void hal_note(uint8_t event, uint32_t value)
{
    static const char *names[] = { "hello", "motor", "watchdog", "safe", "silence" };

    if (pacing_note(event, value))
        return;
    /* the wheels' positions in whole encoder counts, as the 8253s see them */
    printf("%s us=%lu tick=%lu holds=%lu value=%lu left=%ld right=%ld left_rate=%d "
           "right_rate=%d\n",
           names[event], (unsigned long)n.now_us, (unsigned long)n.tick_total, n.holds,
           (unsigned long)value, n.wheel[0].edges / 4, n.wheel[1].edges / 4,
           (int)(n.wheel[0].speed / 4), (int)(n.wheel[1].speed / 4));
    fflush(stdout);
}
