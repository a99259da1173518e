/* A DC gearmotor with a quadrature encoder on its wheel shaft: the part
 * that stands in for the pins in the native build and in the simavr
 * harness. PWM duty and direction in, quadrature edges out.
 *
 * First-order speed response: speed moves toward drive * max_edges_per_s
 * with time constant time_constant_s (an unloaded DC motor's mechanical
 * time constant; its electrical one is far shorter and left out). A drive
 * of 0 lets the speed decay with the same constant (the L298N's brake and
 * a coasting wheel are not told apart here).
 *
 * Edges: 4 per encoder count (both edges of A and of B). Forward (drive
 * > 0) means encoder A leads B: (B,A) goes 00 -> 01 -> 11 -> 10 -> 00.
 */
#ifndef RCL_MOTOR_H
#define RCL_MOTOR_H

typedef struct motor_params {
    double max_edges_per_s;   /* no-load speed at full duty, edges/s */
    double time_constant_s;   /* first-order speed time constant */
    double counts_per_rev;    /* encoder counts (lines) per wheel turn */
} motor_params;

typedef struct motor {
    motor_params p;
    double speed;             /* edges/s, signed, + forward */
    double position;          /* edges, signed, exact */
    long edges;               /* whole edges delivered so far */
} motor;

void motor_default_params(motor_params *p);
void motor_init(motor *m, const motor_params *p);

/* drive in [-1, 1] (signed PWM duty; 0 = off or brake); advance dt
 * seconds; returns the signed number of quadrature edges in dt. */
int motor_step(motor *m, double drive, double dt);

/* total signed edges so far */
double motor_edges(const motor *m);

/* Encoder pin levels now: bit 0 = channel A, bit 1 = channel B. */
unsigned motor_ab(const motor *m);

/* The levels after `edges` edges from the zero position (A = B = 0). */
unsigned motor_ab_at(long edges);

#endif
