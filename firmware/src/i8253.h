/* One Intel 8253 as the R-E Robot uses it: counter 0 the wheel's speed
 * reference (mode 3, 125 kHz / N), counters 1 and 2 event counters
 * (forward and reverse encoder counts, counting down). The host sees
 * the chip's byte interface: control words, the latch command and the
 * LSB/MSB flip-flops. Binary counting only (RCL never sets BCD). */
#ifndef RCL_I8253_H
#define RCL_I8253_H
#include <stdint.h>

typedef struct counter8253 {
    uint8_t mode;           /* 0..5; 0xFF before the first control word */
    uint8_t rw;             /* 1 LSB, 2 MSB, 3 LSB then MSB */
    uint8_t running;        /* a complete count is loaded */
    uint8_t write_msb;      /* the next write is the MSB (rw 3) */
    uint8_t read_msb;       /* the next read is the MSB (rw 3) */
    uint8_t latched;        /* OL frozen by a latch command */
    uint8_t lsb;            /* written LSB waiting for its MSB */
    uint16_t n;             /* the last complete count (0 = 65536) */
    uint16_t ce;            /* counting element */
    uint16_t ol;            /* output latch */
} counter8253;

typedef struct i8253 {
    counter8253 c[3];
} i8253;

void i8253_init(i8253 *chip);
void i8253_write(i8253 *chip, uint8_t addr, uint8_t byte);
uint8_t i8253_read(i8253 *chip, uint8_t addr);
void i8253_pulse(counter8253 *c, uint16_t n);   /* n CLK pulses */
/* counter 0's reference count N (1..65536) while it runs in mode 2 or 3,
 * else 0: the wheel's target rate is 125,000 / N encoder counts/s */
uint32_t i8253_reference(const i8253 *chip);
#endif
