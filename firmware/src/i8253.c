/* The 8253 of i8253.h, after Intel's data sheet (docs/firmware.md, "What it emulates"). */
#include "i8253.h"

#define NO_MODE 0xFF

void i8253_init(i8253 *chip)
{
    for (uint8_t i = 0; i < 3; i++) {
        counter8253 *c = &chip->c[i];
        *c = (counter8253){ 0 };
        c->mode = NO_MODE;
        c->rw = 3;
    }
}

static void program(counter8253 *c, uint8_t rw, uint8_t mode)
{
    c->rw = rw;
    c->mode = mode > 5 ? (uint8_t)(mode - 4) : mode;   /* 110, 111 are 2, 3 */
    c->write_msb = c->read_msb = 0;
    c->latched = 0;
    c->running = 0;
}

static void complete(counter8253 *c, uint16_t word)
{
    c->n = word;
    /* modes 2 and 3 already running take the count at the next reload;
     * an event counter at 65536 reloads to the same value, so RCL's
     * counters never notice */
    if (!c->running || c->mode == 0 || c->mode == 4)
        c->ce = word;
    c->running = 1;
}

static void control(i8253 *chip, uint8_t byte)
{
    uint8_t sc = byte >> 6, rw = (byte >> 4) & 3;
    counter8253 *c;

    if (sc == 3)
        return;                     /* the 8254's read-back: not on an 8253 */
    c = &chip->c[sc];
    if (rw == 0) {                  /* latch: a second one before the read is ignored */
        if (!c->latched) {
            c->ol = c->ce;
            c->latched = 1;
        }
        return;
    }
    program(c, rw, (byte >> 1) & 7);
}

void i8253_write(i8253 *chip, uint8_t addr, uint8_t byte)
{
    counter8253 *c;

    addr &= 3;
    if (addr == 3) {
        control(chip, byte);
        return;
    }
    c = &chip->c[addr];
    if (c->mode == NO_MODE)
        return;
    if (c->rw == 1) {
        complete(c, byte);
    } else if (c->rw == 2) {
        complete(c, (uint16_t)byte << 8);
    } else if (!c->write_msb) {
        c->lsb = byte;
        c->write_msb = 1;
    } else {
        c->write_msb = 0;
        complete(c, (uint16_t)(c->lsb | (uint16_t)byte << 8));
    }
}

uint8_t i8253_read(i8253 *chip, uint8_t addr)
{
    counter8253 *c;
    uint8_t msb, byte;

    addr &= 3;
    if (addr == 3)
        return 0xFF;                /* the control register is write-only */
    c = &chip->c[addr];
    if (!c->latched && !c->read_msb)
        c->ol = c->ce;              /* OL follows CE: one sample per pair */
    msb = c->rw == 2 || (c->rw == 3 && c->read_msb);
    byte = msb ? (uint8_t)(c->ol >> 8) : (uint8_t)c->ol;
    if (c->rw == 3)
        c->read_msb = !c->read_msb;
    if (!c->read_msb)
        c->latched = 0;             /* fully read: OL follows CE again */
    return byte;
}

void i8253_pulse(counter8253 *c, uint16_t n)
{
    uint32_t period, left;

    if (!c->running || n == 0)
        return;
    if (c->mode != 2) {             /* modes 0, 4 (and others) wrap through 0 */
        c->ce = (uint16_t)(c->ce - n);
        return;
    }
    /* mode 2: CE runs N..1, and the pulse after 1 reloads N */
    period = c->n ? c->n : 65536UL;
    left = c->ce ? c->ce : 65536UL;
    if (n >= left)
        left = period - (n - left) % period;
    else
        left -= n;
    c->ce = (uint16_t)left;
}

uint32_t i8253_reference(const i8253 *chip)
{
    const counter8253 *c = &chip->c[0];

    if (!c->running || (c->mode != 2 && c->mode != 3))
        return 0;
    return c->n ? c->n : 65536UL;
}
