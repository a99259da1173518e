/* The emulated board of board.h. */
#include "board.h"
#include "config.h"
#include "hal.h"
#include "i8253.h"
#include "pcb.h"
#include "speed.h"

#include <string.h>

#define LOW_VECTORS 0x80            /* vectors 0..31 kept: 1Ch is at 0x70 */
#define TICKS_ADDR 0x46CUL
#define MIDNIGHT_ADDR 0x470UL
#define PER_DAY_ADDR 0x4F0UL
#define SCRATCH 8                   /* other low-memory bytes the host may store */
#define TICKS_PER_DAY_BIOS 1573040UL

static struct {
    i8253 chip[2];
    pcb pcb;
    uint8_t motor, aux;
    uint32_t seen_edges[2];         /* encoder edges already counted, mod 2^32 */
    int32_t part[2];                /* edges toward the next whole count, x DEN */
    speed_loop loop[2];
    uint8_t script[SCRIPT_MAX * 4];
    uint8_t script_n;
    uint16_t ticks;
    uint8_t vectors[LOW_VECTORS];
    uint32_t bios_ticks, per_day;
    uint8_t midnight;
    uint32_t scratch_addr[SCRATCH];
    uint8_t scratch_val[SCRATCH], scratch_n;
} b;

/* ------------------------------------------------------------ wheels */

static void count_encoder(uint8_t w)
{
    /* whole encoder counts go to counter 1 (forward) or 2 (reverse), as
     * the R-E Robot's direction decoder steers them; edges are weighed
     * EDGES_PER_COUNT_DEN each and a count is EDGES_PER_COUNT_NUM */
    uint32_t now = hal_encoder(w);
    int32_t d = edges_between(now, b.seen_edges[w]);
    i8253 *chip = &b.chip[w];
    int32_t whole;

    if (d == 0)
        return;
    b.seen_edges[w] = now;
    if (d > 30000 || d < -30000)
        d = d > 0 ? 30000 : -30000;    /* cannot happen between two polls */
    b.part[w] += d * EDGES_PER_COUNT_DEN;
    whole = b.part[w] / EDGES_PER_COUNT_NUM;
    b.part[w] -= whole * EDGES_PER_COUNT_NUM;
    if (whole > 0)
        i8253_pulse(&chip->c[1], (uint16_t)whole);
    else if (whole < 0)
        i8253_pulse(&chip->c[2], (uint16_t)-whole);
}

static void sync_encoders(void)
{
    count_encoder(0);
    count_encoder(1);
}

static void drive_wheel(uint8_t w, uint8_t ms)
{
    uint8_t on = w ? M2_ON : M1_ON, go = w ? M2_GO : M1_GO, rev = w ? M2_REV : M1_REV;
    uint8_t run = (b.motor & on) && (b.motor & go);
    int16_t duty = speed_step(&b.loop[w], i8253_reference(&b.chip[w]), run,
                              (b.motor & rev) != 0, hal_encoder(w), ms);

    hal_wheel(w, duty, !(b.motor & on));
}

static void apply_motor_latch(void)
{
    drive_wheel(0, 0);
    drive_wheel(1, 0);
}

static uint8_t status_byte(void)
{
    /* one limit switch per mechanism: reported as the limit it is
     * travelling toward (docs/firmware.md, "Limit switches") */
    uint8_t sw = hal_switches(), s = 0;

    if (sw & 1)
        s |= (b.aux & ARM_DOWN) ? ARM_BOTTOM : ARM_TOP;
    if (sw & 2)
        s |= (b.aux & GRIP_CLOSE) ? GRIP_CLOSED : GRIP_OPENED;
    if (b.loop[0].locked)
        s |= M1_LOCK;
    if (b.loop[1].locked)
        s |= M2_LOCK;
    return s;
}

/* ------------------------------------------------------------- ports */

static void restart_tick(void)
{
    /* timer 0's period to the tick timer, exactly; one shorter than the
     * board can serve runs at the shortest it can (config.h) */
    pcb_period t = pcb_tick_period(&b.pcb);

    if (t.count && t.prescale < TICK_MIN_HALF_US && t.count * t.prescale < TICK_MIN_HALF_US) {
        t.count = TICK_MIN_HALF_US;
        t.prescale = 1;
    }
    b.pcb.last_expiry_us = hal_micros();         /* a new period starts now */
    hal_tick_period(t.count, t.prescale);
}

void board_out8(uint16_t port, uint8_t value)
{
    if (port >= LEFT_8253 && port < LEFT_8253 + 8) {
        sync_encoders();
        i8253_write(&b.chip[(port - LEFT_8253) >> 2], (uint8_t)port, value);
    } else if (port == MOTOR_PORT) {
        if (value != b.motor)
            hal_note(NOTE_MOTOR, value);
        b.motor = value;
        apply_motor_latch();
    } else if (port == AUX_PORT) {
        b.aux = value;
        hal_aux(value);
#ifdef TEST_HANG_PORT
    } else if (port == TEST_HANG_PORT) {
        hal_test_hang(value);
#endif
    } else if (port >= 0xFF00) {
        uint16_t old = pcb_read(&b.pcb, (uint8_t)(port & 0xFE), hal_micros());
        uint16_t word = (port & 1) ? (uint16_t)((old & 0xFF) | (uint16_t)value << 8)
                                   : (uint16_t)((old & 0xFF00) | value);
        board_out16(port & 0xFFFE, word);
    }
}

uint8_t board_in8(uint16_t port)
{
    if (port >= LEFT_8253 && port < LEFT_8253 + 8) {
        sync_encoders();
        return i8253_read(&b.chip[(port - LEFT_8253) >> 2], (uint8_t)port);
    }
    if (port == STATUS_PORT)
        return status_byte();
    if (port >= 0xFF00) {
        uint16_t word = pcb_read(&b.pcb, (uint8_t)(port & 0xFE), hal_micros());
        return (port & 1) ? (uint8_t)(word >> 8) : (uint8_t)word;
    }
    return 0xFF;                    /* write-only latches and empty ports float */
}

void board_out16(uint16_t port, uint16_t value)
{
    if (port < 0xFF00) {            /* an external port: two byte cycles */
        board_out8(port, (uint8_t)value);
        board_out8((uint16_t)(port + 1), (uint8_t)(value >> 8));
        return;
    }
    if (pcb_write(&b.pcb, (uint8_t)(port & 0xFE), value))
        restart_tick();
}

uint16_t board_in16(uint16_t port)
{
    if (port >= 0xFF00)
        return pcb_read(&b.pcb, (uint8_t)(port & 0xFE), hal_micros());
    return (uint16_t)(board_in8(port) | (uint16_t)board_in8((uint16_t)(port + 1)) << 8);
}

/* ------------------------------------------------------------ memory */

static uint32_t *cell32(uint32_t a, uint8_t *shift)
{
    /* the BIOS's 32-bit cells, and the byte of them at a */
    if (a >= TICKS_ADDR && a < TICKS_ADDR + 4) {
        *shift = (uint8_t)(8 * (a - TICKS_ADDR));
        return &b.bios_ticks;
    }
    if (a >= PER_DAY_ADDR && a < PER_DAY_ADDR + 4) {
        *shift = (uint8_t)(8 * (a - PER_DAY_ADDR));
        return &b.per_day;
    }
    return 0;
}

static int8_t scratch_find(uint32_t a)
{
    for (uint8_t i = 0; i < b.scratch_n; i++)
        if (b.scratch_addr[i] == a)
            return (int8_t)i;
    return -1;
}

void board_far_store(uint16_t seg, uint16_t off, uint8_t value)
{
    uint32_t a = (((uint32_t)seg << 4) + off) & 0xFFFFFUL;
    uint8_t shift;
    uint32_t *c = cell32(a, &shift);
    int8_t i;

    if (a < LOW_VECTORS) {
        b.vectors[a] = value;
    } else if (c) {
        *c = (*c & ~(0xFFUL << shift)) | ((uint32_t)value << shift);
    } else if (a == MIDNIGHT_ADDR) {
        b.midnight = value;
    } else if (a < 0x10000UL) {
        i = scratch_find(a);
        if (i < 0 && b.scratch_n < SCRATCH) {
            i = (int8_t)b.scratch_n++;
            b.scratch_addr[i] = a;
        }
        if (i >= 0)
            b.scratch_val[i] = value;
    }
    /* segment 0x1000 is the host's; the rest of the 1 MiB is not here */
}

uint8_t board_far_fetch(uint16_t seg, uint16_t off)
{
    uint32_t a = (((uint32_t)seg << 4) + off) & 0xFFFFFUL;
    uint8_t shift;
    uint32_t *c = cell32(a, &shift);
    int8_t i;

    if (a < LOW_VECTORS)
        return b.vectors[a];
    if (c)
        return (uint8_t)(*c >> shift);
    if (a == MIDNIGHT_ADDR)
        return b.midnight;
    if (a < 0x10000UL) {
        i = scratch_find(a);
        return i < 0 ? 0 : b.scratch_val[i];
    }
    return 0xFF;
}

static uint16_t vector_word(uint8_t at)
{
    return (uint16_t)(b.vectors[at] | (uint16_t)b.vectors[at + 1] << 8);
}

static void set_vector(uint8_t n, uint16_t seg, uint16_t off)
{
    uint8_t *v = &b.vectors[4 * n];
    v[0] = (uint8_t)off;
    v[1] = (uint8_t)(off >> 8);
    v[2] = (uint8_t)seg;
    v[3] = (uint8_t)(seg >> 8);
}

/* ------------------------------------------------------------ script */

uint8_t board_run(const uint8_t *ops, uint8_t n, uint8_t *results)
{
    uint8_t got = 0;

    for (uint8_t i = 0; i < n; i++, ops += 4) {
        uint16_t port = (uint16_t)(ops[1] | (uint16_t)ops[2] << 8);
        if (ops[0] == 0)
            board_out8(port, ops[3]);
        else if (ops[0] == 1)
            results[got++] = board_in8(port);
    }
    return got;
}

void board_set_script(const uint8_t *ops, uint8_t n)
{
    if (n > SCRIPT_MAX)
        n = SCRIPT_MAX;
    memcpy(b.script, ops, (size_t)n * 4);
    b.script_n = n;
}

/* -------------------------------------------------------------- tick */

static void bios_tick(void)
{
    /* the type-8 handler: count the time of day (midnight wraps it and
     * sets the flag), run the script, then INT 1Ch */
    uint8_t results[SCRIPT_MAX];
    uint8_t n;
    uint32_t per_day = b.per_day ? b.per_day : 1;

    b.ticks++;
    if (++b.bios_ticks >= per_day) {
        b.bios_ticks = 0;
        b.midnight = 1;
    }
    n = board_run(b.script, b.script_n, results);
    if (vector_word(0x72) == FORTH_SEG)
        link_send_tick(b.ticks, vector_word(0x70), results, n);
}

static void timer_expiries(uint8_t n)
{
    while (n--) {
        b.pcb.last_expiry_us = hal_micros();
        if (!pcb_interrupting(&b.pcb))
            continue;
        if (pcb_masked(&b.pcb))
            b.pcb.pending = 1;      /* held: several make one interrupt */
        else
            bios_tick();
    }
    if (b.pcb.pending && !pcb_masked(&b.pcb) && pcb_interrupting(&b.pcb)) {
        b.pcb.pending = 0;
        bios_tick();
    }
}

void board_poll(void)
{
    uint8_t ms = hal_take_ms();

    if (ms) {
        sync_encoders();
        drive_wheel(0, ms);
        drive_wheel(1, ms);
    }
    timer_expiries(hal_take_ticks());
}

uint16_t board_tick_count(void)
{
    return b.ticks;
}

uint8_t board_ticking(void)
{
    return pcb_interrupting(&b.pcb) && !pcb_masked(&b.pcb)
        && vector_word(0x72) == FORTH_SEG;
}

/* -------------------------------------------------------------- safety */

void board_safe(void)
{
    hal_note(NOTE_SAFE, b.motor);
    board_out8(MOTOR_PORT, 0);
    board_out8(AUX_PORT, (uint8_t)(b.aux & ~AUX_SAFE_CLEAR));
}

void board_tick_failed(void)
{
    board_safe();
    pcb_stop_interrupts(&b.pcb);
}

void board_power_on(void)
{
    memset(&b, 0, sizeof b);
    i8253_init(&b.chip[0]);
    i8253_init(&b.chip[1]);
    pcb_power_on(&b.pcb);
    set_vector(8, 0xF000, 0xFEA5);          /* the BIOS's timer handler */
    set_vector(0x1C, 0xF000, 0xFF53);       /* INT 1Ch: an IRET */
    b.per_day = TICKS_PER_DAY_BIOS;
    for (uint8_t w = 0; w < 2; w++) {
        b.seen_edges[w] = hal_encoder(w);
        speed_init(&b.loop[w], b.seen_edges[w]);
    }
    board_safe();
    restart_tick();
}
