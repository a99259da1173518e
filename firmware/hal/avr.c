/* The AVR boards (Uno, Mega): the pins of pins_uno.h or pins_mega.h.
 *
 *   UART0   the link: 115200 8N1 (U2X, UBRR 16: 2.1 % fast, within a
 *           UART's tolerance), interrupt-driven receive and send rings
 *   Timer0  fast PWM for both wheels' enables (976 Hz)
 *   Timer1  CTC in 0.5 us steps: timer 0 of the 80188, the tick (RCL's
 *           10.0005 ms exactly)
 *   Timer2  CTC 1 kHz: the speed loop's period and the board's clock
 *   PCINT   the quadrature encoders, decoded in the interrupt
 *   WDT     resets the board when the main loop stops for 64 ms; the
 *           first code after any reset drives the motor pins safe */
#include "../src/config.h"
#include "../src/hal.h"
#include "../src/pcb.h"

#ifdef BOARD_MEGA
#include "pins_mega.h"
#else
#include "pins_uno.h"
#endif

#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include <avr/wdt.h>
#include <util/atomic.h>

#define SET(port, bit) ((port) |= (uint8_t)(1u << (bit)))
#define CLR(port, bit) ((port) &= (uint8_t) ~(1u << (bit)))
#define RX_SIZE 128                 /* a RUN frame is 70 bytes */
#define TX_SIZE 64                  /* a TICK and an answer; more waits */
#define TX_WAIT_STEPS 250           /* putc's bound: 1 ms of Timer2's 4 us steps (11 bytes' time) */
#define COUNT_MAX 0xFFFFu

static volatile uint8_t rx_buf[RX_SIZE], tx_buf[TX_SIZE];
static volatile uint8_t rx_head, rx_tail, tx_head, tx_tail;
static volatile uint16_t ms_count;
static volatile uint8_t ms_new, ticks_new;
static volatile uint32_t edges[2];         /* mod 2^32: no overflow after 50 hours */
static volatile uint8_t enc_last;
static volatile uint16_t compares, compares_last;   /* Timer1 matches toward a tick, of last + 1 */

/* The error counts since power-on, kept through other resets (the
 * watchdog's, the bootloader's when the port opens) */
static volatile struct {
    uint16_t magic;
    uint16_t framing, overrun, lost;
    uint8_t watchdog;
} kept __attribute__((section(".noinit")));
#define KEPT_MAGIC 0x5AC3

const char *hal_name(void)
{
    return "rcl-firmware " FIRMWARE_VERSION_STRING " (" BOARD_NAME ")";
}

void hal_args(int argc, char **argv)
{
    (void)argc;
    (void)argv;
}

/* ------------------------------------------------------------ UART */

static void count(volatile uint16_t *n)
{
    if (*n < COUNT_MAX)
        (*n)++;
}

ISR(UART_RX_VECT)
{
    uint8_t status = UCSR0A;        /* its error flags belong to the byte in UDR0 */
    uint8_t b = UDR0, next = (uint8_t)((rx_head + 1) % RX_SIZE);

    if (status & (1u << FE0))
        count(&kept.framing);
    if (status & (1u << DOR0))
        count(&kept.overrun);       /* bytes lost before this one */
    if (next != rx_tail) {
        rx_buf[rx_head] = b;
        rx_head = next;
    } else {
        count(&kept.overrun);       /* the ring is full: this byte is lost */
    }
}

ISR(UART_UDRE_VECT)
{
    if (tx_head == tx_tail) {
        CLR(UCSR0B, UDRIE0);
        return;
    }
    UDR0 = tx_buf[tx_tail];
    tx_tail = (uint8_t)((tx_tail + 1) % TX_SIZE);
}

int hal_getc(void)
{
    uint8_t b;

    if (rx_head == rx_tail)
        return -1;
    b = rx_buf[rx_tail];
    rx_tail = (uint8_t)((rx_tail + 1) % RX_SIZE);
    return b;
}

void hal_putc(uint8_t byte)
{
    /* the line drains a byte every 87 us: a ring still full after 1 ms
     * (Timer2's steps, which count with interrupts off too) is a line
     * that does not drain, and the byte is lost rather than the loop */
    uint8_t next = (uint8_t)((tx_head + 1) % TX_SIZE);
    uint8_t last = TCNT2;
    uint16_t waited = 0;

    while (next == tx_tail) {
        uint8_t now = TCNT2;
        waited += (uint8_t)(now >= last ? now - last : now + 250 - last);
        last = now;
        if (waited >= TX_WAIT_STEPS) {
            count(&kept.lost);
            return;
        }
    }
    tx_buf[tx_head] = byte;
    tx_head = next;
    SET(UCSR0B, UDRIE0);
}

static void uart_init(void)
{
    UCSR0A = (uint8_t)(1u << U2X0);
    UBRR0 = 16;
    UCSR0C = (uint8_t)((1u << UCSZ01) | (1u << UCSZ00));   /* 8N1 */
    UCSR0B = (uint8_t)((1u << RXEN0) | (1u << TXEN0) | (1u << RXCIE0));
}

/* ----------------------------------------------------------- clocks */

ISR(TIMER2_COMPA_vect)
{
    ms_count++;
    if (ms_new < 255)
        ms_new++;
}

ISR(TIMER1_COMPA_vect)
{
    if (compares != compares_last) {
        compares++;
        return;
    }
    compares = 0;
    if (ticks_new < 255)
        ticks_new++;
}

uint32_t hal_micros(void)
{
    /* milliseconds and Timer2's 4 us steps; a compare match not yet
     * served is counted here */
    uint32_t ms;
    uint8_t t;

    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        ms = ms_count;
        t = TCNT2;
        if ((TIFR2 & (1u << OCF2A)) && t < 125)
            ms++;
    }
    /* ms_count is 16 bits: extend it by its wraps */
    {
        static uint16_t last;
        static uint32_t high;
        if ((uint16_t)ms < last)
            high += 65536UL;
        last = (uint16_t)ms;
        return (high + (uint16_t)ms) * 1000UL + t * 4UL;
    }
}

uint32_t hal_link_micros(void)
{
    return hal_micros();
}

/* An ISR's event count, read and cleared with interrupts held off. */
static uint8_t take(volatile uint8_t *count)
{
    uint8_t n;

    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        n = *count;
        *count = 0;
    }
    return n;
}

uint8_t hal_take_ms(void)
{
    return take(&ms_new);
}

uint8_t hal_take_ticks(void)
{
    return take(&ticks_new);
}

void hal_tick_period(uint32_t count, uint32_t prescale)
{
    /* count x prescale half-us exactly: Timer1 at 0.5 us steps matches
     * every `step` of them, and every `every`-th match is a tick (RCL's
     * 6667 x 3: a match every 20001 steps, 10.0005 ms) */
    pcb_period t = { count, prescale };
    uint32_t step, every;

    TCCR1B = 0;
    TIMSK1 = 0;
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        ticks_new = 0;
        compares = 0;
    }
    if (count == 0)
        return;
    pcb_period_split(t, &step, &every);
    compares_last = (uint16_t)(every - 1);
    /* the mode and clock first, then the compare value: simavr (like
     * the data sheet's examples) takes OCR1A in the mode it is written in */
    TCCR1B = (uint8_t)((1u << WGM12) | (1u << CS11));      /* /8: 0.5 us */
    OCR1A = (uint16_t)(step - 1);
    TCNT1 = 0;
    TIFR1 = (uint8_t)(1u << OCF1A);
    TIMSK1 = (uint8_t)(1u << OCIE1A);
}

static void clocks_init(void)
{
    TCCR2A = (uint8_t)(1u << WGM21);                    /* CTC */
    TCCR2B = (uint8_t)(1u << CS22);                     /* /64 */
    OCR2A = 249;                                        /* 16 MHz / 64 / 250 */
    TCNT2 = 0;
    TIMSK2 = (uint8_t)(1u << OCIE2A);
    TCCR1A = 0;
}

/* --------------------------------------------------------- encoders */

ISR(SENSE_VECT)
{
    /* (old << 2 | new) -> -1, 0, +1; A leads B going forward:
     * (B,A) 00 -> 01 -> 11 -> 10 */
    static const int8_t step[16] = { 0, 1, -1, 0, -1, 0, 0, 1, 1, 0, 0, -1, 0, -1, 1, 0 };
    uint8_t now = SENSE_PIN & ENC_MASK, old = enc_last;

    edges[0] += step[((old & 3) << 2) | (now & 3)];
    edges[1] += step[(old & 0x0C) | ((now >> 2) & 3)];
    enc_last = now;
}

uint32_t hal_encoder(uint8_t wheel)
{
    uint32_t e;

    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        e = edges[wheel & 1];
    }
    return e;
}

uint8_t hal_switches(void)
{
    uint8_t pins = SENSE_PIN;

    return (uint8_t)((pins & (1u << LIMIT_ARM_BIT) ? 0 : 1)
                     | (pins & (1u << LIMIT_JAW_BIT) ? 0 : 2));
}

static void sense_init(void)
{
    SENSE_DDR &= (uint8_t) ~(ENC_MASK | (1u << LIMIT_ARM_BIT) | (1u << LIMIT_JAW_BIT));
    SENSE_PORT |= (uint8_t)((1u << LIMIT_ARM_BIT) | (1u << LIMIT_JAW_BIT));  /* pull-ups */
    enc_last = SENSE_PIN & ENC_MASK;
    SENSE_PCMSK = ENC_MASK;
    PCICR |= (uint8_t)(1u << SENSE_PCIE);
}

/* ------------------------------------------------------------ wheels */

static void set_enable(uint8_t wheel, uint8_t level, uint8_t duty)
{
    /* duty > 0: the PWM drives the enable; else a steady level */
    if (wheel == 0) {
        if (duty) {
            L_OCR = duty;
            TCCR0A |= (uint8_t)(1u << L_COM);
        } else {
            TCCR0A &= (uint8_t) ~(1u << L_COM);
            if (level) SET(L_PWM_PORT, L_PWM_BIT); else CLR(L_PWM_PORT, L_PWM_BIT);
        }
    } else {
        if (duty) {
            R_OCR = duty;
            TCCR0A |= (uint8_t)(1u << R_COM);
        } else {
            TCCR0A &= (uint8_t) ~(1u << R_COM);
            if (level) SET(R_PWM_PORT, R_PWM_BIT); else CLR(R_PWM_PORT, R_PWM_BIT);
        }
    }
}

static void set_inputs(uint8_t wheel, uint8_t in1, uint8_t in2)
{
    if (wheel == 0) {
        if (in1) SET(L_IN1_PORT, L_IN1_BIT); else CLR(L_IN1_PORT, L_IN1_BIT);
        if (in2) SET(L_IN2_PORT, L_IN2_BIT); else CLR(L_IN2_PORT, L_IN2_BIT);
    } else {
        if (in1) SET(R_IN1_PORT, R_IN1_BIT); else CLR(R_IN1_PORT, R_IN1_BIT);
        if (in2) SET(R_IN2_PORT, R_IN2_BIT); else CLR(R_IN2_PORT, R_IN2_BIT);
    }
}

void hal_wheel(uint8_t wheel, int16_t duty, uint8_t brake)
{
    /* L298N: IN1 high IN2 low forward, the reverse backward; both low
     * with the enable high is a brake (the R-E Robot's ON = 0, its
     * relay shorting the motor); the enable low lets it coast */
    if (brake) {
        set_inputs(wheel, 0, 0);
        set_enable(wheel, 1, 0);
    } else if (duty == 0) {
        set_enable(wheel, 0, 0);
        set_inputs(wheel, 0, 0);
    } else {
        set_inputs(wheel, duty > 0, duty < 0);
        set_enable(wheel, 0, (uint8_t)(duty > 0 ? duty : -duty));
    }
}

static void wheels_init(void)
{
    SET(L_PWM_DDR, L_PWM_BIT);
    SET(L_IN1_DDR, L_IN1_BIT);
    SET(L_IN2_DDR, L_IN2_BIT);
    SET(R_PWM_DDR, R_PWM_BIT);
    SET(R_IN1_DDR, R_IN1_BIT);
    SET(R_IN2_DDR, R_IN2_BIT);
    TCCR0A = (uint8_t)((1u << WGM01) | (1u << WGM00));  /* fast PWM, TOP 0xFF */
    TCCR0B = (uint8_t)((1u << CS01) | (1u << CS00));    /* /64: 976 Hz */
    hal_wheel(0, 0, 1);
    hal_wheel(1, 0, 1);
}

/* ------------------------------------------------------- AUX and LED */

void hal_aux(uint8_t aux)
{
    if (aux & ARM_ON) SET(AUX_PORT_REG, ARM_BIT); else CLR(AUX_PORT_REG, ARM_BIT);
    if (aux & GRIP_ON) SET(AUX_PORT_REG, GRIP_BIT); else CLR(AUX_PORT_REG, GRIP_BIT);
    if (aux & ARM_DOWN) SET(DIR_PORT, ARM_DOWN_BIT); else CLR(DIR_PORT, ARM_DOWN_BIT);
    if (aux & GRIP_CLOSE) SET(DIR_PORT, GRIP_CLOSE_BIT); else CLR(DIR_PORT, GRIP_CLOSE_BIT);
    if (aux & BEEPER) SET(BEEP_PORT, BEEP_BIT); else CLR(BEEP_PORT, BEEP_BIT);
}

void hal_led(uint8_t on)
{
    if (on) SET(LED_PORT, LED_BIT); else CLR(LED_PORT, LED_BIT);
}

uint8_t hal_holding(void)
{
    return 0;                       /* a real board never waits for the host */
}

void hal_note(uint8_t event, uint32_t value)
{
    (void)event;
    (void)value;
}

void hal_idle(void)
{
    /* sleep until an interrupt (a byte, the 1 ms clock, the tick) */
    set_sleep_mode(SLEEP_MODE_IDLE);
    cli();
    if (rx_head == rx_tail && !ms_new && !ticks_new) {
        sleep_enable();
        sei();
        sleep_cpu();
        sleep_disable();
    }
    sei();
}

/* ---------------------------------------------------------- watchdog */

/* The first code after any reset (before RAM is set up): the watchdog,
 * which stays on at 16 ms after it has reset the board, off; the motor
 * and AUX outputs driven low (the L298N's enables off: coasting), so
 * that nothing the last run left drives a motor; the reset counted. A
 * bootloader may have cleared MCUSR first (the Uno's stock optiboot
 * does): then a watchdog reset reads as any other. */
void early_init(void) __attribute__((naked, used, section(".init3")));
void early_init(void)
{
    uint8_t cause = MCUSR;

    MCUSR = 0;
    wdt_disable();
    CLR(L_PWM_PORT, L_PWM_BIT);
    CLR(R_PWM_PORT, R_PWM_BIT);
    CLR(L_IN1_PORT, L_IN1_BIT);
    CLR(L_IN2_PORT, L_IN2_BIT);
    CLR(R_IN1_PORT, R_IN1_BIT);
    CLR(R_IN2_PORT, R_IN2_BIT);
    CLR(AUX_PORT_REG, ARM_BIT);
    CLR(AUX_PORT_REG, GRIP_BIT);
    CLR(BEEP_PORT, BEEP_BIT);
    SET(L_PWM_DDR, L_PWM_BIT);
    SET(R_PWM_DDR, R_PWM_BIT);
    SET(L_IN1_DDR, L_IN1_BIT);
    SET(L_IN2_DDR, L_IN2_BIT);
    SET(R_IN1_DDR, R_IN1_BIT);
    SET(R_IN2_DDR, R_IN2_BIT);
    SET(AUX_DDR, ARM_BIT);
    SET(AUX_DDR, GRIP_BIT);
    SET(BEEP_DDR, BEEP_BIT);
    if (kept.magic != KEPT_MAGIC || (cause & ((1u << PORF) | (1u << BORF)))) {
        kept.magic = KEPT_MAGIC;
        kept.framing = kept.overrun = kept.lost = 0;
        kept.watchdog = 0;
    }
    if ((cause & (1u << WDRF)) && kept.watchdog < 255)
        kept.watchdog++;
}

void hal_feed_watchdog(void)
{
    wdt_reset();
}

void hal_errors_get(hal_errors *e)
{
    ATOMIC_BLOCK(ATOMIC_RESTORESTATE) {
        e->framing = kept.framing;
        e->overrun = kept.overrun;
    }
    e->lost = kept.lost;
    e->watchdog = kept.watchdog;
}

#ifdef TEST_HANG_PORT
/* A test image only (make uno-hang): the main loop stops here, with
 * interrupts on (value 0) or off, for the watchdog to end. */
void hal_test_hang(uint8_t value)
{
    if (value)
        cli();
    for (;;)
        ;
}
#endif

void hal_init(void)
{
    SET(AUX_DDR, ARM_BIT);
    SET(AUX_DDR, GRIP_BIT);
    SET(DIR_DDR, ARM_DOWN_BIT);
    SET(DIR_DDR, GRIP_CLOSE_BIT);
    SET(BEEP_DDR, BEEP_BIT);
    SET(LED_DDR, LED_BIT);
    hal_aux(0);
    wheels_init();
    sense_init();
    clocks_init();
    uart_init();
    /* system reset mode, not interrupt first: it resets with interrupts
     * off too, on the chip and under simavr alike */
    wdt_enable(WDTO_60MS);
    sei();
}
