/* The wheels of wheels.h: registers in, encoder edges out. */
#include "wheels.h"

#include <stdint.h>

#include "avr_ioport.h"
#include "sim_cycle_timers.h"
#include "sim_irq.h"

/* ATmega328P data-space addresses (datasheet, register summary). simavr
 * keeps every I/O register at its data address in avr->data. */
#define R_DDRB   0x24
#define R_PINC   0x26
#define R_PORTB  0x25
#define R_DDRD   0x2A
#define R_PORTD  0x2B
#define R_TCCR0A 0x44
#define R_TCCR0B 0x45
#define R_OCR0A  0x47
#define R_OCR0B  0x48

typedef struct wheel_pins {
    int ocr;              /* OCR0A or OCR0B */
    int com_shift;        /* COM0A bits 7:6, COM0B bits 5:4 of TCCR0A */
    int pwm_bit;          /* the OC0x pin on PORTD */
    int in1_port, in1_bit, in2_port, in2_bit;
    int enc_a, enc_b;     /* PORTC pins */
} wheel_pins;

static const wheel_pins PINS[WHEEL_COUNT] = {
    [WHEEL_LEFT]  = { R_OCR0B, 4, 5, R_PORTD, 4, R_PORTD, 7, 0, 1 },
    [WHEEL_RIGHT] = { R_OCR0A, 6, 6, R_PORTB, 0, R_PORTB, 4, 2, 3 },
};

static const int LIMIT_PINS[LIMIT_COUNT] = { [LIMIT_ARM] = 4, [LIMIT_JAW] = 5 };
#define PORTC_DRIVEN 0x3Fu    /* PC0..PC5: encoders and limit switches */

/* An output pin's level; an input pin floats and the L298N reads low. */
static int out_level(const avr_t *avr, int port, int bit)
{
    int ddr = port - 1;   /* DDRx sits just below PORTx */

    return (avr->data[ddr] >> bit & 1) && (avr->data[port] >> bit & 1);
}

/* The fraction of time the OC0x pin is high, from Timer0's mode, the
 * pin's compare-output mode and its OCR0x. */
static double pwm_duty(const avr_t *avr, const wheel_pins *p)
{
    unsigned tccr0a = avr->data[R_TCCR0A];
    unsigned wgm = (tccr0a & 3u) | (avr->data[R_TCCR0B] >> 1 & 4u);
    unsigned com = tccr0a >> p->com_shift & 3u;
    unsigned clock = avr->data[R_TCCR0B] & 7u;
    double ocr = avr->data[p->ocr];

    if (!(avr->data[R_DDRD] >> p->pwm_bit & 1))
        return 0.0;
    if (com < 2 || clock == 0)      /* the pin is a plain output */
        return out_level(avr, R_PORTD, p->pwm_bit);
    if (wgm == 1 || wgm == 5) {     /* phase correct: high below OCR */
        double d = ocr / 255.0;
        return com == 2 ? d : 1.0 - d;
    }
    /* fast PWM (3, 7): high from BOTTOM through OCR, so OCR 0 is a
     * one-clock spike and 255 is always on */
    return com == 2 ? (ocr + 1.0) / 256.0 : (255.0 - ocr) / 256.0;
}

double wheels_drive(const wheels *ws, int which)
{
    const wheel_pins *p = &PINS[which];
    int in1 = out_level(ws->avr, p->in1_port, p->in1_bit);
    int in2 = out_level(ws->avr, p->in2_port, p->in2_bit);
    double duty = pwm_duty(ws->avr, p);

    if (in1 == in2)       /* brake (both high) or both low: no drive */
        return 0.0;
    return in1 ? duty : -duty;
}

/* A level on a PORTC input pin. simavr 1.6 re-raises an input pin from
 * its "external pull" whenever the firmware writes PORTC or DDRC (to
 * model pull-ups), which would undo a level raised only through the
 * pin's IRQ: so the pull is kept equal to what the harness drives. */
static void set_pin(wheels *ws, avr_irq_t *pin, int bit, unsigned level)
{
    avr_ioport_external_t ext = { .name = 'C', .mask = PORTC_DRIVEN };

    ws->portc = (uint8_t)((ws->portc & ~(1u << bit)) | (level & 1u) << bit);
    ext.value = ws->portc;
    avr_ioctl(ws->avr, AVR_IOCTL_IOPORT_SET_EXTERNAL('C'), &ext);
    avr_raise_irq(pin, level & 1u);
}

/* One edge toward the model's count: gray code, so one pin changes. */
static void show_one_edge(wheels *ws, int i)
{
    wheel *w = &ws->w[i];
    unsigned ab;

    if (w->shown == w->m.edges)
        return;
    w->shown += w->shown < w->m.edges ? 1 : -1;
    ab = motor_ab_at(w->shown);
    if ((ab ^ w->ab) & 1u)
        set_pin(ws, w->pin_a, PINS[i].enc_a, ab & 1u);
    if ((ab ^ w->ab) & 2u)
        set_pin(ws, w->pin_b, PINS[i].enc_b, ab >> 1 & 1u);
    w->ab = ab;
}

static avr_cycle_count_t step(avr_t *avr, avr_cycle_count_t when, void *param)
{
    wheels *ws = param;
    double dt = (double)ws->step_cycles / avr->frequency;

    int moving = 0;

    for (int i = 0; i < WHEEL_COUNT; i++) {
        wheel *w = &ws->w[i];
        w->drive = wheels_drive(ws, i);
        moving |= w->drive != 0.0;
        motor_step(&w->m, w->drive, dt);
        show_one_edge(ws, i);
    }
    if (ws->moving && !moving)
        ws->stopped_at = when;
    ws->moving = moving;
    ws->steps++;
    return when + ws->step_cycles;
}

unsigned wheels_aux(const wheels *ws)
{
    return (unsigned)(out_level(ws->avr, R_PORTB, 1) |
                      out_level(ws->avr, R_PORTB, 2) << 1 |
                      out_level(ws->avr, R_PORTB, 3) << 2);
}

void wheels_hold_limit(wheels *ws, int which, int held)
{
    ws->limit_held[which] = held;
    set_pin(ws, ws->limit_pin[which], LIMIT_PINS[which], held ? 0 : 1);
}

void wheels_rearm(wheels *ws)
{
    avr_t *avr = ws->avr;

    /* the reset zeroed PINC behind the pins' IRQs: put the levels back */
    avr->data[R_PINC] = (uint8_t)((avr->data[R_PINC] & ~PORTC_DRIVEN) | ws->portc);
    if (avr_cycle_timer_status(avr, step, ws) == 0)
        avr_cycle_timer_register(avr, ws->step_cycles, step, ws);
}

void wheels_start(wheels *ws, avr_t *avr)
{
    motor_params params;

    motor_default_params(&params);
    ws->avr = avr;
    ws->steps = 0;
    ws->portc = 0;
    ws->step_cycles = (avr_cycle_count_t)avr->frequency / 1000000 * WHEEL_STEP_US;
    for (int i = 0; i < WHEEL_COUNT; i++) {
        wheel *w = &ws->w[i];
        motor_init(&w->m, &params);
        w->shown = 0;
        w->ab = motor_ab_at(0);
        w->drive = 0.0;
        w->pin_a = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('C'), PINS[i].enc_a);
        w->pin_b = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('C'), PINS[i].enc_b);
    }
    for (int i = 0; i < LIMIT_COUNT; i++) {
        ws->limit_pin[i] = avr_io_getirq(avr, AVR_IOCTL_IOPORT_GETIRQ('C'),
                                         LIMIT_PINS[i]);
        /* a released switch is high: its pull-up */
        wheels_hold_limit(ws, i, ws->limit_held[i]);
    }
    avr_cycle_timer_register(avr, ws->step_cycles, step, ws);
}
