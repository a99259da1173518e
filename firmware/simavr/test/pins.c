/* pins-test: a small ATmega328P program that checks rcl-simavr on its
 * own, without the firmware: UART0 at 115200, Timer0 fast PWM and the
 * L298N direction pins on the firmware's Uno pin map, a Timer1 10 ms
 * tick and a pin-change quadrature decoder on PC0..PC3.
 *
 * Commands (bytes on UART0):
 *   'm' L R   drive: L and R signed bytes, -127..127 (sign = direction,
 *             duty = (2|v|+1)/256); 0 = both inputs low
 *   'c'       -> 'c', left and right edges (int32 LE), decode errors (u8)
 *   't'       -> 't', Timer1 ticks (u16 LE)
 *   's'       -> 's', limit pins: bit 0 arm (PC4), bit 1 jaw (PC5), 1 = high
 *   others    echoed back
 */
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <stdint.h>

#define RING 64

static volatile uint8_t ring[RING];
static volatile uint8_t ring_head, ring_tail;
static volatile int32_t edges[2];
static volatile uint8_t errors;
static volatile uint16_t ticks;
static uint8_t last_pinc;

/* (B,A) forward is 00 -> 01 -> 11 -> 10: +1 each step, -1 back, 2 apart
 * is an edge the decoder missed */
static const int8_t STEP[16] = {
    /* old 0 */ 0, +1, -1, 2,
    /* old 1 */ -1, 0, 2, +1,
    /* old 2 */ +1, 2, 0, -1,
    /* old 3 */ 2, -1, +1, 0,
};

ISR(USART_RX_vect)
{
    uint8_t next = (uint8_t)((ring_head + 1) % RING);
    uint8_t c = UDR0;

    if (next != ring_tail) {
        ring[ring_head] = c;
        ring_head = next;
    }
}

ISR(TIMER1_COMPA_vect)
{
    ticks++;
}

static void decode(uint8_t wheel, uint8_t old_ab, uint8_t new_ab)
{
    int8_t s = STEP[old_ab << 2 | new_ab];

    if (s == 2)
        errors++;
    else
        edges[wheel] += s;
}

ISR(PCINT1_vect)
{
    uint8_t now = PINC;

    decode(0, last_pinc & 3, now & 3);
    decode(1, last_pinc >> 2 & 3, now >> 2 & 3);
    last_pinc = now;
}

static void put(uint8_t c)
{
    while (!(UCSR0A & _BV(UDRE0)))
        ;
    UDR0 = c;
}

static void put_bytes(const volatile void *p, uint8_t n)
{
    const volatile uint8_t *b = p;

    while (n--)
        put(*b++);
}

/* Waits asleep (idle mode) for a byte: simavr then skips to the next
 * event instead of running a busy loop. */
static uint8_t get(void)
{
    uint8_t c;

    for (;;) {
        cli();
        if (ring_head != ring_tail)
            break;
        sleep_enable();
        sei();
        sleep_cpu();
        sleep_disable();
    }
    c = ring[ring_tail];
    ring_tail = (uint8_t)((ring_tail + 1) % RING);
    sei();
    return c;
}

static void drive(volatile uint8_t *ocr, volatile uint8_t *in_port,
                  uint8_t in1, uint8_t in2, int8_t v)
{
    uint8_t mag = (uint8_t)(v < 0 ? -v : v);

    *ocr = (uint8_t)(2 * mag + 1);
    if (v > 0)
        *in_port = (uint8_t)((*in_port | _BV(in1)) & ~_BV(in2));
    else if (v < 0)
        *in_port = (uint8_t)((*in_port | _BV(in2)) & ~_BV(in1));
    else
        *in_port = (uint8_t)(*in_port & ~(_BV(in1) | _BV(in2)));
}

static void setup(void)
{
    UCSR0A = _BV(U2X0);
    UBRR0 = 16;                                 /* 115200 at 16 MHz, U2X */
    UCSR0B = _BV(RXEN0) | _BV(TXEN0) | _BV(RXCIE0);
    UCSR0C = _BV(UCSZ01) | _BV(UCSZ00);         /* 8N1 */
    DDRD |= _BV(PD4) | _BV(PD5) | _BV(PD6) | _BV(PD7);
    DDRB |= _BV(PB0) | _BV(PB4);
    TCCR0A = _BV(COM0A1) | _BV(COM0B1) | _BV(WGM01) | _BV(WGM00);
    TCCR0B = _BV(CS01);                         /* fast PWM, 7.8 kHz */
    TCCR1B = _BV(WGM12) | _BV(CS11) | _BV(CS10);  /* CTC, 16 MHz / 64 */
    OCR1A = 2499;                               /* / 2500: 10 ms */
    TIMSK1 = _BV(OCIE1A);
    PORTC |= _BV(PC4) | _BV(PC5);               /* limit switch pull-ups */
    last_pinc = PINC;
    PCMSK1 = 0x0F;
    PCICR = _BV(PCIE1);
    set_sleep_mode(SLEEP_MODE_IDLE);
    sei();
}

static void command(uint8_t c)
{
    uint8_t snap[9];

    if (c == 'm') {
        int8_t l = (int8_t)get(), r = (int8_t)get();
        drive(&OCR0B, &PORTD, PD4, PD7, l);
        drive(&OCR0A, &PORTB, PB0, PB4, r);
    } else if (c == 'c') {
        cli();
        for (uint8_t i = 0; i < 4; i++) {
            snap[i] = (uint8_t)(edges[0] >> (8 * i));
            snap[4 + i] = (uint8_t)(edges[1] >> (8 * i));
        }
        snap[8] = errors;
        sei();
        put('c');
        put_bytes(snap, sizeof snap);
    } else if (c == 't') {
        uint16_t t;
        cli();
        t = ticks;
        sei();
        put('t');
        put_bytes(&t, 2);
    } else if (c == 's') {
        put('s');
        put((uint8_t)(PINC >> 4 & 3));
    } else {
        put(c);
    }
}

int main(void)
{
    setup();
    for (;;)
        command(get());
}
