/* CRC-16/CCITT-FALSE, a byte at a time from a 256-entry table: a flood
 * of frame-like garbage makes the receiver check a 70-byte candidate for
 * every byte that comes, and bit by bit that would outrun the Uno at
 * 115200 baud. On the AVR the table lives in flash. */
#include "crc16.h"

#ifdef __AVR__
#include <avr/pgmspace.h>
#define TABLE_ENTRY(i) pgm_read_word(&table[i])
#define IN_FLASH PROGMEM
#else
#define TABLE_ENTRY(i) table[i]
#define IN_FLASH
#endif

/* table[i] = the CRC register after shifting byte i through it from 0.
 * R1 names its argument twice, not three times: R8 nests it 8 deep, and
 * 3^8 copies of each entry took gcc 16 CPU s and 1.4 GB for this file, 2^8 take 1 s. */
#define R1(c) ((uint16_t)(((c) << 1) ^ (((c) >> 15) * 0x1021u)))
#define R2(c) R1(R1(c))
#define R4(c) R2(R2(c))
#define R8(c) R4(R4(c))
#define T(i) (uint16_t)R8((uint16_t)((i) << 8))
#define T4(i) T(i), T((i) + 1), T((i) + 2), T((i) + 3)
#define T16(i) T4(i), T4((i) + 4), T4((i) + 8), T4((i) + 12)
#define T64(i) T16(i), T16((i) + 16), T16((i) + 32), T16((i) + 48)

static const uint16_t table[256] IN_FLASH = { T64(0), T64(64), T64(128), T64(192) };

uint16_t crc16_update(uint16_t crc, uint8_t byte)
{
    return (uint16_t)((crc << 8) ^ TABLE_ENTRY((uint8_t)((crc >> 8) ^ byte)));
}

uint16_t crc16(const uint8_t *p, size_t n)
{
    uint16_t crc = 0xFFFF;
    while (n--)
        crc = crc16_update(crc, *p++);
    return crc;
}
