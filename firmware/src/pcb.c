/* The peripheral control block of pcb.h (docs/firmware.md, "What it emulates"). */
#include "pcb.h"

#define T_WRITABLE 0x203Fu          /* INT, MC, RTG, P, EXT, ALT, CONT */
#define T2_PRESCALE 3               /* 2 MHz / 3: timer 0 counts 1.5 us */
#define BIOS_T0_COUNT 36617u        /* 54.9 ms, the PC's 18.2 Hz */

void pcb_power_on(pcb *p)
{
    *p = (pcb){ { 0 }, { 0 }, { 0 }, { 0 }, 0, 0xFC, 0, 0 };
    /* as the board's BIOS leaves it: timer 2 prescales by 3, timer 0
     * interrupts every 36617 of its counts, the timer interrupt unmasked */
    p->t_max_a[2] = T2_PRESCALE;
    p->t_control[2] = T_EN | 0x0001u;
    p->t_max_a[0] = BIOS_T0_COUNT;
    p->t_control[0] = T_EN | T_INT | T_P | 0x0001u;
}

static int8_t timer_of(uint8_t offset, uint8_t *field)
{
    if (offset < 0x50 || offset > 0x66)
        return -1;
    *field = (uint8_t)((offset - 0x50) & 7) >> 1;       /* count, A, B, control */
    return (int8_t)((offset - 0x50) >> 3);
}

static uint16_t count_now(const pcb *p, uint32_t now_us)
{
    /* timer 0's count: its input clocks since its last expiry, taken
     * mod its max count; 2e / prescale clocks in e us, split so that no
     * step overflows 32 bits (e reaches 2^32 - 1 between two reads) */
    pcb_period t = pcb_tick_period(p);
    uint32_t e = now_us - p->last_expiry_us;
    uint32_t q, r;

    if (t.count == 0)
        return p->t_count[0];
    q = e / t.prescale % t.count;
    r = e % t.prescale;
    return (uint16_t)((2 * q + 2 * r / t.prescale) % t.count);
}

uint16_t pcb_read(pcb *p, uint8_t offset, uint32_t now_us)
{
    uint8_t field;
    int8_t t = timer_of(offset, &field);

    if (t >= 0) {
        if (field == 0)
            return t == 0 ? count_now(p, now_us) : p->t_count[t];
        if (field == 1)
            return p->t_max_a[t];
        if (field == 2)
            return t < 2 ? p->t_max_b[t] : 0;
        return p->t_control[t];
    }
    switch (offset) {
    case 0x28: return p->other_masks | (pcb_masked(p) ? 1u : 0u);
    case 0x2E: return p->pending ? 1u : 0u;
    case 0x30: return p->pending ? 1u : 0u;
    case 0x32: return p->timer_control;
    default: return 0;
    }
}

static void write_control(pcb *p, int8_t t, uint16_t word)
{
    uint16_t en = (word & T_INH) ? (word & T_EN) : (p->t_control[t] & T_EN);
    p->t_control[t] = (uint16_t)(en | (word & T_WRITABLE));
}

uint8_t pcb_write(pcb *p, uint8_t offset, uint16_t word)
{
    uint8_t field;
    int8_t t = timer_of(offset, &field);

    if (t >= 0) {
        if (field == 0)
            p->t_count[t] = word;
        else if (field == 1)
            p->t_max_a[t] = word;
        else if (field == 2 && t < 2)
            p->t_max_b[t] = word;
        else if (field == 3)
            write_control(p, t, word);
        return t == 0 || t == 2;
    }
    if (offset == 0x28) {
        p->other_masks = word & 0xFEu;
        p->timer_control = (uint16_t)((p->timer_control & ~TIMER_MASK_BIT)
                                      | ((word & 1u) ? TIMER_MASK_BIT : 0));
    } else if (offset == 0x32) {
        p->timer_control = word & 0x000Fu;
    }
    /* 0x22 EOI: the firmware ends each interrupt itself */
    return 0;
}

pcb_period pcb_tick_period(const pcb *p)
{
    /* 2 MHz input: 1 half-us a clock, or timer 2's period with P; a max
     * count of 0 is 65536 */
    pcb_period t = { p->t_max_a[0] ? p->t_max_a[0] : 65536UL, 1 };

    if (!(p->t_control[0] & T_EN) || (p->t_control[0] & T_EXT))
        t.count = 0;
    else if (p->t_control[0] & T_P) {
        if (!(p->t_control[2] & T_EN))
            t.count = 0;
        t.prescale = p->t_max_a[2] ? p->t_max_a[2] : 65536UL;
    }
    return t;
}

void pcb_period_split(pcb_period t, uint32_t *step, uint32_t *every)
{
    if (t.prescale <= 65536UL / t.count) {
        *step = t.count * t.prescale;
        *every = 1;
    } else {
        *step = t.count > t.prescale ? t.count : t.prescale;
        *every = t.count > t.prescale ? t.prescale : t.count;
    }
}

uint8_t pcb_masked(const pcb *p)
{
    return (p->timer_control & TIMER_MASK_BIT) != 0;
}

uint8_t pcb_interrupting(const pcb *p)
{
    return (p->t_control[0] & (T_EN | T_INT)) == (T_EN | T_INT);
}

void pcb_stop_interrupts(pcb *p)
{
    p->t_control[0] &= (uint16_t)~T_INT;
    p->pending = 0;
}
