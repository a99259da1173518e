/* The link of link.h. Section numbers are docs/protocol.md's. */
#include "link.h"
#include "board.h"
#include "config.h"
#include "crc16.h"
#include "hal.h"

#include <string.h>

enum {
    HELLO = 0x01, OUT8, OUT16, IN8, IN16, FAR_STORE, FAR_FETCH, SNAPSHOT,
    TICK_DONE, SAFE, TICK_FAILED, PING, NAK, RUN, WAIT,
    IDENTIFY = 0x81, ACK, VALUE, TICK, HEARTBEAT, REFUSED, RESULTS
};

typedef struct saved_frame {
    uint8_t len;                    /* 0: empty */
    uint8_t bytes[SAVED_MAX];
} saved_frame;

static struct {
    uint8_t rx_buf[2 * FRAME_MAX]; /* the bytes held are rx_buf[rx_at, rx_at + rx_n) */
    uint8_t rx_at, rx_n;
    uint8_t rx_waiting;             /* the frame at rx_at is incomplete ... */
    uint32_t rx_since_us;           /* ... since this link time */
    uint8_t expected;               /* the host's next SEQ */
    uint8_t send_seq;               /* the board's next SEQ */
    saved_frame window[WINDOW];     /* by SEQ mod WINDOW, for NAK */
    saved_frame last_reply;         /* the answer a repeat gets again */
    uint8_t last_reply_seq;         /* the host SEQ it answered */
    uint32_t last_sent_us, last_valid_us;
    uint32_t last_valid_board_us;   /* the same moment in board time */
    uint8_t watchdog_tripped;
} k;

/* ------------------------------------------------------------ sending */

static void put_frame(const uint8_t *f, uint8_t n)
{
    for (uint8_t i = 0; i < n; i++)
        hal_putc(f[i]);
    k.last_sent_us = hal_link_micros();
}

/* Build a frame in `out`; -> its length. */
static uint8_t build(uint8_t *out, uint8_t seq, uint8_t type, const uint8_t *payload,
                     uint8_t len)
{
    uint16_t crc;

    out[0] = SYNC;
    out[1] = len;
    out[2] = seq;
    out[3] = type;
    memcpy(out + 4, payload, len);
    crc = crc16(out + 1, (size_t)len + 3);
    out[4 + len] = (uint8_t)(crc >> 8);     /* high byte first (section 1) */
    out[5 + len] = (uint8_t)crc;
    return (uint8_t)(len + 6);
}

/* A sequenced board frame: numbered, kept for NAK, sent; -> its slot. */
static saved_frame *send_sequenced(uint8_t type, const uint8_t *payload, uint8_t len)
{
    saved_frame *s = &k.window[k.send_seq % WINDOW];

    if (len + 6 > SAVED_MAX)
        len = SAVED_MAX - 6;        /* only a long REFUSED reason is cut */
    s->len = build(s->bytes, k.send_seq, type, payload, len);
    k.send_seq++;                   /* the board wraps 255 -> 0 (section 3) */
    put_frame(s->bytes, s->len);
    return s;
}

static void reply(uint8_t ack, uint8_t type, const uint8_t *payload, uint8_t len)
{
    uint8_t p[SAVED_MAX];

    p[0] = ack;
    memcpy(p + 1, payload, len);
    k.last_reply = *send_sequenced(type, p, (uint8_t)(len + 1));
    k.last_reply_seq = ack;
}

static void refuse(uint8_t ack, const char *why)
{
    reply(ack, REFUSED, (const uint8_t *)why, (uint8_t)strlen(why));
}

static void value(uint8_t ack, uint16_t v)
{
    uint8_t p[2] = { (uint8_t)v, (uint8_t)(v >> 8) };
    reply(ack, VALUE, p, 2);
}

void link_send_tick(uint16_t tick, uint16_t off, const uint8_t *results, uint8_t n)
{
    uint8_t p[4 + SCRIPT_MAX];

    p[0] = (uint8_t)tick;
    p[1] = (uint8_t)(tick >> 8);
    p[2] = (uint8_t)off;
    p[3] = (uint8_t)(off >> 8);
    memcpy(p + 4, results, n);
    send_sequenced(TICK, p, (uint8_t)(4 + n));
    hal_note(NOTE_TICK_SENT, tick);
}

/* Append " key=value" to the name being built in p (up to MAX_PAYLOAD). */
static uint8_t put_count(uint8_t *p, uint8_t n, const char *key, uint16_t v)
{
    char digits[5];
    uint8_t d = 0;

    do {
        digits[d++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    if (n + 2 + strlen(key) + d > MAX_PAYLOAD)
        return n;
    p[n++] = ' ';
    while (*key)
        p[n++] = (uint8_t)*key++;
    p[n++] = '=';
    while (d)
        p[n++] = (uint8_t)digits[--d];
    return n;
}

static void identify(void)
{
    /* the name, then the line's error counts since power-on and the
     * hardware watchdog's resets (docs/firmware.md, "Errors") */
    uint8_t f[FRAME_MAX], p[MAX_PAYLOAD];
    const char *name = hal_name();
    hal_errors e;
    uint8_t n = 4;

    p[0] = PROTOCOL_VERSION;
    p[1] = (uint8_t)TICK_US;
    p[2] = (uint8_t)(TICK_US >> 8);
    p[3] = 0;                       /* flags: not a lockstep board (section 4) */
    while (*name && n < MAX_PAYLOAD)
        p[n++] = (uint8_t)*name++;
    hal_errors_get(&e);
    n = put_count(p, n, "fe", e.framing);
    n = put_count(p, n, "or", e.overrun);
    n = put_count(p, n, "tx", e.lost);
    n = put_count(p, n, "wd", e.watchdog);
    put_frame(f, build(f, 0, IDENTIFY, p, n));
}

static void heartbeat(void)
{
    uint32_t t = hal_micros();
    uint8_t p[5] = { (uint8_t)t, (uint8_t)(t >> 8), (uint8_t)(t >> 16), (uint8_t)(t >> 24),
                     board_ticking() };
    send_sequenced(HEARTBEAT, p, 5);
}

/* ------------------------------------------------------------ acting */

static uint16_t u16(const uint8_t *p)
{
    return (uint16_t)(p[0] | (uint16_t)p[1] << 8);
}

/* The payload's size fits the message's fields (section 2). */
static uint8_t well_formed(uint8_t type, uint8_t len)
{
    static const uint8_t fixed[16] = {
        0, 1, 3, 4, 2, 2, 5, 4, 0xFF, 0xFE, 0, 0, 0, 1, 0xFF, 2
    };
    uint8_t f;

    if (type > WAIT)
        return 0;
    f = fixed[type];
    if (f == 0xFF)
        return len % 4 == 0;                    /* ops:*BHB */
    if (f == 0xFE)
        return len >= 5 && (len - 5) % 3 == 0;  /* tick final us writes:*HB */
    return len == f;
}

static void act(uint8_t seq, uint8_t type, const uint8_t *p, uint8_t len)
{
    uint8_t results[MAX_PAYLOAD / 4];

    switch (type) {
    case OUT8: board_out8(u16(p), p[2]); break;
    case OUT16: board_out16(u16(p), u16(p + 2)); break;
    case IN8: value(seq, board_in8(u16(p))); return;
    case IN16: value(seq, board_in16(u16(p))); return;
    case FAR_STORE: board_far_store(u16(p), u16(p + 2), p[4]); break;
    case FAR_FETCH: value(seq, board_far_fetch(u16(p), u16(p + 2))); return;
    case SNAPSHOT:
        if (len > SCRIPT_MAX * 4) {
            refuse(seq, "script too long");
            return;
        }
        board_set_script(p, (uint8_t)(len / 4));
        break;
    case RUN:
        reply(seq, RESULTS, results, board_run(p, (uint8_t)(len / 4), results));
        return;
    case TICK_DONE:                 /* the handler's writes, at once; `us` unused */
        for (uint8_t i = 5; i < len; i += 3)
            board_out8(u16(p + i), p[i + 2]);
        if (p[2])
            hal_note(NOTE_TICK_DONE, u16(p));
        break;
    case SAFE: board_safe(); break;
    case TICK_FAILED:
        board_tick_failed();
        hal_note(NOTE_TICK_DONE, board_tick_count());
        break;
    default:
        refuse(seq, "not a host message");
        return;
    }
    reply(seq, ACK, 0, 0);
}

static void hello(void)
{
    /* a new session: the board as at power-on before the host hears
     * IDENTIFY, nothing of the last host left (docs/protocol.md, "Sessions") */
    board_power_on();
    k.expected = 1;
    k.send_seq = 1;
    k.last_reply.len = 0;
    for (uint8_t i = 0; i < WINDOW; i++)
        k.window[i].len = 0;
    identify();
}

static void resend(uint8_t seq)
{
    saved_frame *s = &k.window[seq % WINDOW];

    /* only if that slot still holds that SEQ: an older frame has gone */
    if (s->len && s->bytes[2] == seq)
        put_frame(s->bytes, s->len);
}

/* A good frame (section 3's rules). */
static void frame(uint8_t seq, uint8_t type, const uint8_t *p, uint8_t len)
{
    /* a board's frame is nobody's request: on a line that echoes, the
     * board's own frames come back, and must neither use up the host's
     * next SEQ nor feed the watchdog for a host that has gone */
    if (type & 0x80)
        return;
    k.last_valid_us = hal_link_micros();
    k.last_valid_board_us = hal_micros();
    k.watchdog_tripped = 0;
    if (type == HELLO) {
        if (len != 1)
            return;                 /* version:B, or it is not a HELLO: no session (section 4) */
        hal_note(NOTE_HELLO, p[0]);
        hello();
        return;
    }
    if (type == PING || type == WAIT)
        return;                     /* WAIT is for lockstep boards */
    if (type == NAK) {
        if (len == 1)
            resend(p[0]);
        return;
    }
    if (type == SAFE)
        board_safe();               /* whatever its SEQ */
    if (seq == (k.expected == 1 ? 255 : k.expected - 1)) {
        if (k.last_reply.len && k.last_reply_seq == seq)
            put_frame(k.last_reply.bytes, k.last_reply.len);   /* byte for byte */
        return;
    }
    if (seq != k.expected)
        return;
    k.expected = (uint8_t)(k.expected % 255 + 1);
    if (!well_formed(type, len)) {
        refuse(seq, "bad payload");
        return;
    }
    act(seq, type, p, len);
}

/* ---------------------------------------------------------- receiving */

static uint8_t known_type(uint8_t t)
{
    /* the host's types only: a board frame (an echo of our own) is no
     * frame here, feeds no watchdog and uses up no SEQ (section 1) */
    return t >= HELLO && t <= WAIT;
}

static void drop(uint8_t n)
{
    /* O(1): garbage drops a byte at a time, and a shift of the whole
     * buffer each time would outrun the Uno in a flood */
    k.rx_at = (uint8_t)(k.rx_at + n);
    k.rx_n = (uint8_t)(k.rx_n - n);
    if (k.rx_n == 0)
        k.rx_at = 0;
    if (n)
        k.rx_waiting = 0;           /* another frame, if any, is at the front */
}

/* Section 1's receiver over the bytes held: a bad frame loses only its
 * SYNC, so a good frame that began inside it is still found. */
static void scan(void)
{
    for (;;) {
        const uint8_t *rx;
        uint8_t i = 0, need;
        uint16_t crc;

        while (i < k.rx_n && k.rx_buf[k.rx_at + i] != SYNC)
            i++;
        drop(i);
        rx = k.rx_buf + k.rx_at;
        if (k.rx_n < 2)
            return;
        if (rx[1] > MAX_PAYLOAD) {
            drop(1);
            continue;
        }
        need = (uint8_t)(rx[1] + 6);
        if (k.rx_n < need) {
            if (!k.rx_waiting) {
                k.rx_waiting = 1;
                k.rx_since_us = hal_link_micros();
            }
            return;
        }
        crc = (uint16_t)(rx[need - 2] << 8 | rx[need - 1]);
        /* the type first: garbage rarely has a known one, and the CRC of a
         * 70-byte candidate is the receiver's only real cost */
        if (!known_type(rx[3]) || crc != crc16(rx + 1, (size_t)need - 3)) {
            drop(1);
            continue;
        }
        frame(rx[2], rx[3], rx + 4, rx[1]);
        drop(need);
    }
}

void link_rx(uint8_t byte)
{
    if (k.rx_at + k.rx_n == sizeof k.rx_buf) {      /* at the end: back to the start */
        memmove(k.rx_buf, k.rx_buf + k.rx_at, k.rx_n);
        k.rx_at = 0;
    }
    k.rx_buf[k.rx_at + k.rx_n++] = byte;    /* scan leaves under FRAME_MAX held */
    scan();
}

/* The caller found no byte waiting. A frame still incomplete FRAME_GAP_US
 * after its SYNC came is no frame (a corrupted LEN, section 1 step 3): a
 * PING whose LEN turned 0 -> 32 would otherwise hide the next five PINGs
 * from the watchdog. Judged only here, with the line read empty, so a
 * frame whose bytes were all waiting is never cut short. */
void link_rx_idle(void)
{
    if (k.rx_waiting && hal_link_micros() - k.rx_since_us >= FRAME_GAP_US) {
        drop(1);
        scan();
    }
}

/* ------------------------------------------------------------- timing */

void link_poll(void)
{
    uint32_t now = hal_link_micros();

    /* the watchdog counts board time: a native board holding its time
     * for a host that is late (a busy machine) does not count the wait */
    if (!k.watchdog_tripped && hal_micros() - k.last_valid_board_us >= WATCHDOG_US) {
        board_tick_failed();        /* section 6: the host is silent: safe, no tick */
        k.watchdog_tripped = 1;
        hal_note(NOTE_SILENCE, now - k.last_valid_us);            /* link clock */
        hal_note(NOTE_WATCHDOG, hal_micros() - k.last_valid_board_us);   /* board time */
    }
    if (now - k.last_sent_us >= (hal_holding() ? HOLD_HEARTBEAT_US : HEARTBEAT_US))
        heartbeat();
    hal_led(link_up());
}

uint8_t link_up(void)
{
    return !k.watchdog_tripped;
}

void link_init(void)
{
    memset(&k, 0, sizeof k);
    k.expected = 1;
    k.send_seq = 1;
    k.last_valid_us = k.last_sent_us = hal_link_micros();
    k.last_valid_board_us = hal_micros();
    k.watchdog_tripped = 1;         /* nobody has spoken yet */
}
