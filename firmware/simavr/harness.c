/* rcl-simavr: the firmware's real Uno image (ATmega328P, 16 MHz) under
 * simavr, its UART0 on a pseudo-terminal and its motor pins driving the
 * gearmotor + encoder model the native build uses.
 *
 *   rcl-simavr [options] firmware.elf
 *
 * The first line on stdout is the pty's path. Simulated time follows
 * real time (times --rate) and never runs ahead of it: a harness that
 * falls behind (the machine stalls) does not race to catch up, it
 * re-bases, so the board never sees time pass that the host had no
 * chance to answer in. Nor does it run on while a host that is running
 * the ticks owes a TICK its answer for more than 5 ms (a loaded
 * machine), as long as that does not keep the board silent for longer
 * than its 50 ms HEARTBEAT period (--free-running: it never waits).
 *
 * Lines on stdin: "hold arm|jaw", "release arm|jaw", "cut" and "mend"
 * (the serial line: bytes lost both ways while cut), "stats" (one JSON
 * line on stdout), "quit". SIGUSR1 writes the stats file; SIGTERM,
 * SIGINT, SIGHUP and "quit" write it and exit.
 */
#define _GNU_SOURCE
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>
#include <unistd.h>

#include "avr_extint.h"
#include "sim_avr.h"
#include "sim_elf.h"

#include "bridge.h"
#include "frames.h"
#include "wheels.h"

#define MCU "atmega328p"
#define MCU_HZ 16000000
#define BAUD 115200
#define SLICE_US 250          /* input is looked at least this often */
#define MAX_LAG_US 20000      /* further behind than this: re-base */
#define HOST_SLACK_US 5000    /* a host answers a TICK within this (measured: 3-4 ms
                                 at 115200 on an idle machine), or is waited for */
#define HOLD_MAX_S 0.05       /* the longest the board is kept silent by a hold:
                                 its HEARTBEAT period, as the protocol promises */

typedef struct options {
    const char *elf;
    const char *stats_path;
    const char *trace_path;
    double rate;
    int hold[LIMIT_COUNT];
    int quiet;
    int free_running;
} options;

typedef struct harness {
    options opt;
    avr_t *avr;
    bridge br;
    wheels ws;
    link_watch lw;
    void (*core_reset)(avr_t *);
    double base_wall;                 /* wall time of the last (re-)base */
    avr_cycle_count_t base_cycle;     /* simulated cycle at that time */
    double start_wall;
    unsigned long rebases, resets;
    unsigned long reports;            /* stats files written, for a reader to wait on */
    double lag_max_us;                /* deepest fall behind before a re-base */
    int holding;                      /* board time held for the host's answer */
    double hold_start, held_s;
    unsigned long holds;
    int host_away;                    /* gave up waiting; until it answers again */
    unsigned long aways_moving;       /* gave up while a wheel was driven: the wheels
                                         ran on without the host's next writes */
    uint16_t away_answer;             /* its last answer when it went away */
    char line[256];                   /* stdin command being read */
    size_t line_len;
    int stdin_open;
    unsigned long sessions;           /* the link watch's, as last seen */
    FILE *trace;                      /* --trace: a line per good frame */
} harness;

static harness H;                     /* one per process: signals reach it */
static volatile sig_atomic_t quit_signal, stats_signal;

static double now_s(void)
{
    struct timespec t;

    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + t.tv_nsec * 1e-9;
}

static void on_signal(int sig)
{
    if (sig == SIGUSR1)
        stats_signal = 1;
    else
        quit_signal = sig;
}

/* simavr's messages go to stderr: stdout carries the pty path and stats */
static void log_to_stderr(avr_t *avr, const int level, const char *fmt,
                          va_list ap)
{
    if (level > (avr ? avr->log : LOG_WARNING))
        return;
    vfprintf(stderr, fmt, ap);
}

/* The harness paces time itself (run_until); simavr's own sleep would
 * usleep for every idle stretch on top of that. */
static void no_sleep(avr_t *avr, avr_cycle_count_t how_long)
{
    (void)avr;
    (void)how_long;
}

/* ------------------------------------------------------------ stats */
static void stats_json(FILE *f)
{
    const wheels *ws = &H.ws;
    double sim_s = (double)H.avr->cycle / H.avr->frequency;

    fprintf(f, "{\"report\": %lu, \"sim_s\": %.6f, \"wall_s\": %.3f, "
               "\"rate\": %g, \"rebases\": %lu, \"lag_max_us\": %.0f, "
               "\"resets\": %lu, ",
            H.reports, sim_s, now_s() - H.start_wall, H.opt.rate, H.rebases,
            H.lag_max_us, H.resets);
    fprintf(f, "\"holds\": %lu, \"held_s\": %.3f, \"aways_moving\": %lu, ",
            H.holds, H.held_s, H.aways_moving);
    fprintf(f, "\"edges\": [%.0f, %.0f], \"pin_edges\": [%ld, %ld], "
               "\"drive\": [%.4f, %.4f], \"limits_held\": [%d, %d], ",
            motor_edges(&ws->w[WHEEL_LEFT].m), motor_edges(&ws->w[WHEEL_RIGHT].m),
            ws->w[WHEEL_LEFT].shown, ws->w[WHEEL_RIGHT].shown,
            ws->w[WHEEL_LEFT].drive, ws->w[WHEEL_RIGHT].drive,
            ws->limit_held[LIMIT_ARM], ws->limit_held[LIMIT_JAW]);
    fprintf(f, "\"stopped_s\": %.6f, \"aux_pins\": %u, \"cut\": %d, "
               "\"lost_to_cut\": %lu, ",
            (double)ws->stopped_at / H.avr->frequency, wheels_aux(ws),
            H.br.cut, H.br.lost_to_cut);
    fprintf(f, "\"bytes_to_board\": %lu, \"bytes_from_board\": %lu, "
               "\"dropped_to_board\": %lu, \"dropped_from_board\": %lu, ",
            H.br.to_board, H.br.from_board, H.br.dropped_in, H.br.dropped_out);
    link_watch_json(&H.lw, f);
    fputs("}\n", f);
}

/* Written beside and renamed, so a reader never sees half a file. */
static void write_stats_file(void)
{
    char tmp[4096];
    FILE *f;

    if (!H.opt.stats_path)
        return;
    H.reports++;
    snprintf(tmp, sizeof tmp, "%s.tmp", H.opt.stats_path);
    f = fopen(tmp, "w");
    if (!f) {
        fprintf(stderr, "rcl-simavr: %s: %s\n", tmp, strerror(errno));
        return;
    }
    stats_json(f);
    fclose(f);
    rename(tmp, H.opt.stats_path);
}

/* ------------------------------------------------------------ trace */
/* A line per good frame on the wire: simulated time in us, who sent it
 * (> to the board, < from it), SEQ, type, payload in hex, and the motor
 * model's true edges and drive of each wheel at that moment. Two
 * sessions' traces side by side show where they part. */
static void trace_frame(void *ctx, int from_board, const uint8_t *f, int len,
                        avr_cycle_count_t at)
{
    const wheels *ws = &H.ws;

    (void)ctx;
    fprintf(H.trace, "%.1f %c %3u %02X ", (double)at * 1e6 / H.avr->frequency,
            from_board ? '<' : '>', f[2], f[3]);
    for (int i = 4; i < len - 2; i++)
        fprintf(H.trace, "%02X", f[i]);
    fprintf(H.trace, " | %.0f %.0f %.4f %.4f\n",
            motor_edges(&ws->w[WHEEL_LEFT].m), motor_edges(&ws->w[WHEEL_RIGHT].m),
            ws->w[WHEEL_LEFT].drive, ws->w[WHEEL_RIGHT].drive);
}

/* ---------------------------------------------------- stdin commands */
static int limit_named(const char *name)
{
    if (strcmp(name, "arm") == 0)
        return LIMIT_ARM;
    if (strcmp(name, "jaw") == 0)
        return LIMIT_JAW;
    return -1;
}

static void command(const char *cmd)
{
    char verb[32] = "", arg[32] = "";
    int which;

    if (sscanf(cmd, "%31s %31s", verb, arg) < 1)
        return;
    if (strcmp(verb, "stats") == 0) {
        stats_json(stdout);
        fflush(stdout);
        write_stats_file();
    } else if (strcmp(verb, "quit") == 0) {
        quit_signal = SIGTERM;
    } else if (strcmp(verb, "cut") == 0 || strcmp(verb, "mend") == 0) {
        bridge_cut(&H.br, verb[0] == 'c');
    } else if ((strcmp(verb, "hold") == 0 || strcmp(verb, "release") == 0) &&
               (which = limit_named(arg)) >= 0) {
        wheels_hold_limit(&H.ws, which, verb[0] == 'h');
    } else {
        fprintf(stderr, "rcl-simavr: unknown command: %s\n", cmd);
    }
}

static void read_commands(void)
{
    struct pollfd p = { .fd = 0, .events = POLLIN };
    char c;

    while (H.stdin_open && poll(&p, 1, 0) > 0) {
        if (read(0, &c, 1) != 1) {    /* EOF: no more commands, run on */
            H.stdin_open = 0;
            return;
        }
        if (c == '\n') {
            H.line[H.line_len] = 0;
            command(H.line);
            H.line_len = 0;
        } else if (H.line_len < sizeof H.line - 1) {
            H.line[H.line_len++] = c;
        }
    }
}

/* ------------------------------------------------------------ pacing */
static void rebase(double t)
{
    H.base_wall = t;
    H.base_cycle = H.avr->cycle;
}

/* The cycle at which the host, running the ticks, has had HOST_SLACK_US
 * to answer the last TICK and nothing of its is on the wire: board time
 * waits there for it (0: no wait). A host that answers in time, as on an
 * idle machine, is never waited for; a loaded one gets the board a real
 * board would be to an unloaded host, instead of one that runs on and
 * makes it skip ticks. --free-running: never wait. */
static avr_cycle_count_t host_due(void)
{
    avr_cycle_count_t slack = (avr_cycle_count_t)H.avr->frequency / 1000000 * HOST_SLACK_US;
    avr_cycle_count_t due;

    if (H.lw.sessions != H.sessions) {
        H.sessions = H.lw.sessions;
        H.host_away = 0;              /* a new host: nothing owed, not away */
    }
    if (H.host_away && H.lw.answered != H.away_answer)
        H.host_away = 0;              /* it answered again: it runs the ticks */
    if (H.opt.free_running || H.br.count || H.host_away)
        return 0;
    due = link_watch_host_due(&H.lw, slack);
    return due;
}

/* Hold board time at `due` while the host owes its answer, but never so
 * long that the board has sent nothing for HOLD_MAX_S of wall time: a
 * held board sends no HEARTBEAT either, and a host catching up through
 * its backlog of TICKs must hear from the board well before its 250 ms
 * "no frame" limit. A host that makes a hold end that way is away (at
 * the prompt, or cut off): no more holds until it answers a tick again.
 * -> 1 while holding. */
static int hold_for_host(avr_cycle_count_t due, double t)
{
    int owed = due && H.avr->cycle >= due;

    if (owed && t - H.br.last_sent_wall > HOLD_MAX_S) {
        H.host_away = 1;
        if (H.ws.moving)
            H.aways_moving++;
        H.away_answer = H.lw.answered;
        owed = 0;
    }
    if (owed && !H.holding) {
        H.holding = 1;
        H.holds++;
        H.hold_start = t;
    }
    if (H.holding && !owed) {
        H.holding = 0;
        H.held_s += t - H.hold_start;
        rebase(t);                    /* on from here: the held time is not caught up */
        return 0;
    }
    if (H.holding)
        rebase(t);
    return H.holding;
}

/* The cycle simulated time may reach now: never ahead of the wall clock
 * (times rate). Further behind than MAX_LAG_US means the harness was
 * not running (a stall): start counting again from here instead of
 * racing through the lost time with nobody able to answer. */
static avr_cycle_count_t allowed_cycle(avr_cycle_count_t due)
{
    double t = now_s();
    double hz = H.avr->frequency * H.opt.rate;
    double target, lag_us;

    if (hold_for_host(due, t))
        return H.avr->cycle;
    target = H.base_cycle + (t - H.base_wall) * hz;
    lag_us = (target - (double)H.avr->cycle) / hz * 1e6;
    if (lag_us > MAX_LAG_US) {
        H.rebases++;
        if (lag_us > H.lag_max_us)
            H.lag_max_us = lag_us;
        rebase(t);
        return H.avr->cycle;
    }
    if (due && due > H.avr->cycle && target > due)
        target = due;                 /* stop where the host is owed */
    return target > 0 ? (avr_cycle_count_t)target : 0;
}

/* Wait until the wall clock lets simulated time move on by a slice,
 * waking early for host bytes or commands. */
static void wait_for_time(avr_cycle_count_t ahead)
{
    double s = (double)ahead / (H.avr->frequency * H.opt.rate);
    struct timespec ts = { 0, (long)(s * 1e9) + 1000 };
    struct pollfd p[2] = {
        { .fd = H.br.host_present ? H.br.master : -1, .events = POLLIN },
        { .fd = H.stdin_open ? 0 : -1, .events = POLLIN },
    };

    ppoll(p, 2, &ts, NULL);
}

static int run_slice(void)
{
    avr_cycle_count_t slice = (avr_cycle_count_t)H.avr->frequency / 1000000 * SLICE_US;
    avr_cycle_count_t allowed = allowed_cycle(host_due());
    avr_cycle_count_t limit;

    if (H.avr->cycle >= allowed) {
        wait_for_time(H.holding ? slice : H.avr->cycle + slice - allowed);
        return cpu_Running;
    }
    limit = allowed < H.avr->cycle + slice ? allowed : H.avr->cycle + slice;
    while (H.avr->cycle < limit) {
        int state = avr_run(H.avr);
        if (state == cpu_Done || state == cpu_Crashed)
            return state;
    }
    return cpu_Running;
}

/* ------------------------------------------------------------ set-up */
static void on_wire_byte(void *ctx, uint8_t byte, int to_board,
                         avr_cycle_count_t when)
{
    link_watch_byte(ctx, byte, to_board, when);
}

/* An AVR reset (its watchdog, say) clears the I/O registers and every
 * cycle timer: start the wheels and the wire again, pins as they were. */
static void on_reset(avr_t *avr)
{
    if (H.core_reset)
        H.core_reset(avr);
    H.resets++;
    wheels_rearm(&H.ws);
    bridge_rearm(&H.br);
}

static void usage(void)
{
    fprintf(stderr,
        "usage: rcl-simavr [--rate R] [--hold arm|jaw]... [--stats FILE] [--trace FILE] [--free-running] [--quiet] firmware.elf\n"
        "  --rate R      simulated seconds per real second (default 1)\n"
        "  --hold SW     start with the arm or jaw limit switch held (pin low)\n"
        "  --stats FILE  JSON figures at exit, on SIGUSR1 and on \"stats\"\n"
        "  --free-running  never wait for a host late with a TICK's answer\n"
        "  --trace FILE  a line per good frame: time, way, SEQ, type, payload, wheels\n");
    exit(2);
}

static void parse_options(int argc, char **argv, options *o)
{
    o->rate = 1.0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--rate") == 0 && i + 1 < argc) {
            o->rate = atof(argv[++i]);
            if (!(o->rate > 0.0 && o->rate <= 100.0))
                usage();
        } else if (strcmp(a, "--hold") == 0 && i + 1 < argc) {
            int which = limit_named(argv[++i]);
            if (which < 0)
                usage();
            o->hold[which] = 1;
        } else if (strcmp(a, "--stats") == 0 && i + 1 < argc) {
            o->stats_path = argv[++i];
        } else if (strcmp(a, "--trace") == 0 && i + 1 < argc) {
            o->trace_path = argv[++i];
        } else if (strcmp(a, "--free-running") == 0) {
            o->free_running = 1;
        } else if (strcmp(a, "--quiet") == 0) {
            o->quiet = 1;
        } else if (a[0] == '-' || o->elf) {
            usage();
        } else {
            o->elf = a;
        }
    }
    if (!o->elf)
        usage();
}

static avr_t *load(const char *path)
{
    elf_firmware_t f;
    avr_t *avr;

    memset(&f, 0, sizeof f);
    if (elf_read_firmware(path, &f) != 0) {
        fprintf(stderr, "rcl-simavr: cannot read firmware %s\n", path);
        exit(1);
    }
    /* the image is a plain avr-gcc ELF: no .mmcu section to name its
     * chip, so the Uno's is given here */
    strcpy(f.mmcu, MCU);
    f.frequency = MCU_HZ;
    avr = avr_make_mcu_by_name(f.mmcu);
    if (!avr || avr_init(avr) != 0) {
        fprintf(stderr, "rcl-simavr: simavr has no %s\n", MCU);
        exit(1);
    }
    avr->log = LOG_WARNING;
    avr_load_firmware(avr, &f);
    /* simavr polls a low INT0/INT1 pin at every cycle while its (reset
     * default) low-level mode is set, enabled or not; the Uno's D2 and
     * D3 are outputs that sit low, which cost a full core. As a falling
     * edge it is only looked at when the pin changes. */
    avr_extint_set_strict_lvl_trig(avr, 0, 0);
    avr_extint_set_strict_lvl_trig(avr, 1, 0);
    avr->sleep = no_sleep;
    return avr;
}

static void install_signals(void)
{
    struct sigaction sa;

    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
    sigaction(SIGUSR1, &sa, NULL);
    signal(SIGPIPE, SIG_IGN);
    /* a test that dies must not leave a simulated robot running */
    prctl(PR_SET_PDEATHSIG, SIGTERM);
}

int main(int argc, char **argv)
{
    int state = cpu_Running;

    parse_options(argc, argv, &H.opt);
    avr_global_logger_set(log_to_stderr);
    install_signals();
    H.avr = load(H.opt.elf);
    link_watch_init(&H.lw, H.avr->frequency);
    if (bridge_open(&H.br, H.avr, BAUD) < 0) {
        perror("rcl-simavr: openpty");
        return 1;
    }
    H.br.on_byte = on_wire_byte;
    H.br.on_byte_ctx = &H.lw;
    if (H.opt.trace_path) {
        H.trace = fopen(H.opt.trace_path, "w");
        if (!H.trace) {
            perror(H.opt.trace_path);
            return 1;
        }
        setvbuf(H.trace, NULL, _IOLBF, 0);
        H.lw.on_frame = trace_frame;
    }
    memcpy(H.ws.limit_held, H.opt.hold, sizeof H.ws.limit_held);
    wheels_start(&H.ws, H.avr);
    H.core_reset = H.avr->reset;
    H.avr->reset = on_reset;
    H.stdin_open = 1;
    printf("%s\n", H.br.slave_name);
    fflush(stdout);
    H.start_wall = H.base_wall = now_s();
    H.base_cycle = H.avr->cycle;
    while (!quit_signal && state == cpu_Running) {
        read_commands();
        bridge_pump(&H.br);
        state = run_slice();
        bridge_pump(&H.br);
        if (stats_signal) {
            stats_signal = 0;
            write_stats_file();
        }
    }
    if (state != cpu_Running)
        fprintf(stderr, "rcl-simavr: the AVR stopped (%s) at %.6f s\n",
                state == cpu_Crashed ? "crashed" : "sleeping with interrupts off",
                (double)H.avr->cycle / H.avr->frequency);
    write_stats_file();
    if (!H.opt.quiet)
        stats_json(stderr);
    bridge_close(&H.br);
    return state == cpu_Running ? 0 : 1;
}
