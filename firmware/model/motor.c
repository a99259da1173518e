/* The gearmotor and encoder model of motor.h. */
#include "motor.h"

#include <math.h>

void motor_default_params(motor_params *p)
{
    /* The R-E Robot's encoder: 500 lines on the wheel shaft. Its fastest
     * speed is 5 MPH = 5 wheel turns/s = 2,500 counts/s = 10,000 edges/s
     * (8253 count 50); a motor with 20 % in hand (360 rpm at the wheel)
     * lets the speed loop reach it under load. 50 ms is a small
     * gearmotor's mechanical time constant. */
    p->max_edges_per_s = 12000.0;
    p->time_constant_s = 0.050;
    p->counts_per_rev = 500.0;
}

void motor_init(motor *m, const motor_params *p)
{
    m->p = *p;
    m->speed = 0.0;
    m->position = 0.0;
    m->edges = 0;
}

static double clamp_drive(double d)
{
    if (d > 1.0)
        return 1.0;
    if (d < -1.0)
        return -1.0;
    return d;
}

int motor_step(motor *m, double drive, double dt)
{
    double target = clamp_drive(drive) * m->p.max_edges_per_s;
    double k = 1.0 - exp(-dt / m->p.time_constant_s);
    double start = m->speed;
    long whole;
    int out;

    if (dt <= 0.0)
        return 0;
    m->speed += (target - m->speed) * k;
    /* position gains the mean speed over dt (trapezoid: exact enough for
     * dt well below the time constant) */
    m->position += 0.5 * (start + m->speed) * dt;
    whole = (long)floor(m->position);
    out = (int)(whole - m->edges);
    m->edges = whole;
    return out;
}

double motor_edges(const motor *m)
{
    return (double)m->edges;
}

unsigned motor_ab_at(long edges)
{
    /* Gray code, forward A first: phase 0..3 -> (B,A) 00, 01, 11, 10 */
    static const unsigned gray[4] = { 0u, 1u, 3u, 2u };
    long phase = edges % 4;

    if (phase < 0)
        phase += 4;
    return gray[phase];
}

unsigned motor_ab(const motor *m)
{
    return motor_ab_at(m->edges);
}
