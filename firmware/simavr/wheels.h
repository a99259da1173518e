/* The Uno's two wheels under simavr: each wheel's L298N inputs and PWM
 * duty, read from the simulated ATmega328P's registers, drive the same
 * gearmotor + encoder model as the native build (firmware/model/motor.h),
 * and the model's quadrature edges are raised on the encoder pins, one
 * at a time, so the firmware's pin-change interrupt sees each of them.
 *
 * Pins (the firmware's fixed Uno map):
 *   left:  PWM D5 = OC0B (PD5), IN1 D4 (PD4), IN2 D7 (PD7), A = PC0, B = PC1
 *   right: PWM D6 = OC0A (PD6), IN3 D8 (PB0), IN4 D12 (PB4), A = PC2, B = PC3
 *   limit switches, active low: arm PC4, jaw PC5
 */
#ifndef RCL_SIMAVR_WHEELS_H
#define RCL_SIMAVR_WHEELS_H

#include "sim_avr.h"
#include "motor.h"

/* The model's step: 20 us is 0.24 edges at the motor's top speed, so
 * the edges it makes come out one per step, never bunched. */
#define WHEEL_STEP_US 20

enum { WHEEL_LEFT, WHEEL_RIGHT, WHEEL_COUNT };
enum { LIMIT_ARM, LIMIT_JAW, LIMIT_COUNT };

typedef struct wheel {
    motor m;
    long shown;                 /* edges raised on the pins so far */
    unsigned ab;                /* levels now on the pins, bit0 A bit1 B */
    double drive;               /* last drive given to the model */
    avr_irq_t *pin_a, *pin_b;
} wheel;

typedef struct wheels {
    avr_t *avr;
    wheel w[WHEEL_COUNT];
    avr_irq_t *limit_pin[LIMIT_COUNT];
    int limit_held[LIMIT_COUNT];
    uint8_t portc;              /* levels driven on PC0..PC5 */
    avr_cycle_count_t step_cycles;
    unsigned long steps;
    int moving;                 /* some wheel had drive at the last step */
    avr_cycle_count_t stopped_at;  /* when the drive last went to none */
} wheels;

/* Wire the models to the pins and start stepping them. */
void wheels_start(wheels *ws, avr_t *avr);

/* After an AVR reset, which clears the pins and every cycle timer. */
void wheels_rearm(wheels *ws);

/* Hold (1) or release (0) a limit switch: held pulls its pin low. */
void wheels_hold_limit(wheels *ws, int which, int held);

/* The drive the pins ask of a wheel now, in [-1, 1]. */
double wheels_drive(const wheels *ws, int which);

/* The AUX outputs' levels: bit 0 arm motor (PB1), bit 1 gripper (PB2),
 * bit 2 beeper (PB3). */
unsigned wheels_aux(const wheels *ws);

#endif
